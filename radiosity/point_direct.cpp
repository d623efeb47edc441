#include "radiosity/point_direct.h"

#include "core/light.h"
#include "core/scene.h"
#include "radiosity/form_factor.h"
#include "radiosity/radiosity_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace penumbra {

namespace {

// Seed of the lights' fixed points (stratifiedElementSamples), apart from the solver's others.
constexpr uint32_t kLightPointSeed = 0x5eed0d1c;

// Whether an emitting side of a patch of normal `normal` through `c` faces x.
bool emitsToward(const Vec3& normal, const Vec3& c, bool front, bool back, const Vec3& x) {
    const float facing = glm::dot(normal, x - c);
    return (front && facing > 0.0f) || (back && facing < 0.0f);
}

}  // namespace

PointDirect::PointDirect(const Scene& scene, const RadiosityMesh& mesh,
                         const std::function<bool(int element, bool front)>& exposed)
    : scene_(scene), punctual_(punctualLights(scene)) {
    std::map<uint32_t, AreaLight> byMesh;
    std::map<uint32_t, double> areas;
    std::map<uint32_t, std::vector<int>> patchesOf;
    for (size_t p = 0; p < mesh.patchCount(); ++p) {
        const int patch = static_cast<int>(p);
        const bool front = exposed(patch, true),
                   back = mesh.twoSided(patch) && exposed(patch, false);
        if (maxComponent(mesh.Le(patch)) <= 0.0f || !(front || back))
            continue;
        const Vec3 c = mesh.centroid(patch);
        float radius = 0.0f;
        for (const Vec3& corner : mesh.corners(patch))
            radius = std::max(radius, glm::length(corner - c));
        byMesh[mesh.sceneMesh(patch)].patches.push_back({mesh.corners(patch), mesh.normal(patch), c,
                                                         mesh.area(patch), radius, mesh.Le(patch),
                                                         front, back});
        areas[mesh.sceneMesh(patch)] += mesh.area(patch);
        patchesOf[mesh.sceneMesh(patch)].push_back(patch);
    }
    // Each light's points, shared among its patches by area (at least one each), then dealt out
    // a patch at a time so that the first few are spread over the light.
    for (auto& [light, patches] : patchesOf) {
        std::vector<std::vector<ElementSample>> perPatch;
        for (const int patch : patches) {
            const double share = mesh.area(patch) / areas[light];
            const auto n = static_cast<size_t>(std::max(1.0, std::round(kLightPoints * share)));
            perPatch.emplace_back(n);
            stratifiedElementSamples(scene, mesh, patch, kLightPointSeed, IVec2(patch, 0),
                                     perPatch.back());
        }
        std::vector<ElementSample>& points = byMesh[light].points;
        for (size_t k = 0; points.size() < perPatch.size() * kLightPoints; ++k) {
            bool any = false;
            for (const auto& own : perPatch) {
                if (k < own.size()) {
                    points.push_back(own[k]);
                    any = true;
                }
            }
            if (!any)
                break;
        }
    }
    for (auto& [sceneMesh, light] : byMesh) {
        light.twoSided = light.patches.front().back;
        lights_.push_back(std::move(light));
    }
}

float PointDirect::formFactor(const Vec3& x, const Vec3& n, const Patch& patch) {
    const Vec3 d = patch.centroid - x;
    const float r2 = glm::dot(d, d), far = kFarField * patch.radius;
    if (r2 > far * far) {
        const float cosX = glm::dot(n, d), cosP = std::abs(glm::dot(patch.normal, d));
        return cosX > 0.0f ? patch.area * cosX * cosP / (kPi * r2 * r2) : 0.0f;
    }
    return static_cast<float>(pointToPolygonFormFactor(x, n, patch.corners));
}

float PointDirect::nearestSource(const Vec3& p) const {
    float nearest = std::numeric_limits<float>::infinity();
    for (const Light* light : punctual_) {
        if (light->kind() == LightKind::Directional)
            continue;
        // A delta light's sample is its position, where it sends p any light.
        if (const std::optional<LightLiSample> ls = light->sampleLi({p}, Vec2(0.5f)))
            nearest = std::min(nearest, glm::length(ls->pLight - p));
    }
    for (const AreaLight& light : lights_) {
        for (const Patch& patch : light.patches)
            nearest =
                std::min(nearest, std::max(0.0f, glm::length(p - patch.centroid) - patch.radius));
    }
    return nearest;
}

PointDirect::Parts PointDirect::D(const ElementSample& x, const Vec3& n, uint64_t& rays) const {
    Color E(0.0f);
    const LightSampleContext ctx{x.p, x.pError, n};
    for (const Light* light : punctual_) {
        // A delta light has one direction: the sample point is irrelevant.
        const std::optional<LightLiSample> ls = light->sampleLi(ctx, Vec2(0.5f));
        if (!ls)
            continue;
        const float cosTheta = glm::dot(ls->wi, n);
        if (cosTheta <= 0.0f)
            continue;
        ++rays;
        E += ls->L * cosTheta *
             scene_.transmittance(x.p, x.pError, n, ls->pLight, ls->pLightError, ls->nLight);
    }
    Parts D{E * kInvPi, Color(0.0f)};
    // Each light's unoccluded light, then the rays it gets of kRaysPerPoint.
    std::vector<Color> unoccluded(lights_.size(), Color(0.0f));
    const size_t lights = lights_.size();
    float total = 0.0f;
    for (size_t l = 0; l < lights; ++l) {
        for (const Patch& patch : lights_[l].patches) {
            if (emitsToward(patch.normal, patch.corners[0], patch.front, patch.back, x.p))
                unoccluded[l] += patch.Le * formFactor(x.p, n, patch);
        }
        total += maxComponent(unoccluded[l]);
    }
    for (size_t l = 0; l < lights; ++l) {
        const AreaLight& light = lights_[l];
        const float share = maxComponent(unoccluded[l]);
        if (share <= 0.0f)
            continue;
        const auto count =
            std::clamp<size_t>(static_cast<size_t>(std::lround(kRaysPerPoint * share / total)), 1,
                               light.points.size());
        // The visible fraction, weighted by the unoccluded kernel at each point.
        double weights = 0.0;
        Color visible(0.0f);
        for (const ElementSample& y : std::span(light.points).first(count)) {
            const Vec3 d = y.p - x.p;
            const float r2 = glm::dot(d, d);
            const float cosX = glm::dot(n, d), cosY = -glm::dot(y.n, d);
            if (!(r2 > 0.0f) || cosX <= 0.0f || (cosY <= 0.0f && !light.twoSided))
                continue;
            const double w = double(cosX) * std::abs(cosY) / (double(r2) * r2);
            weights += w;
            ++rays;
            visible +=
                static_cast<float>(w) * scene_.transmittance(x.p, x.pError, n, y.p, y.pError, y.n);
        }
        if (weights > 0.0)
            D.emitters += unoccluded[l] * visible / static_cast<float>(weights);
    }
    return D;
}

}  // namespace penumbra
