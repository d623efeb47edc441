#include "radiosity/element_sampling.h"

#include "core/light.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/coincident_faces.h"
#include "radiosity/environment_direct.h"
#include "radiosity/form_factor.h"
#include "radiosity/radiosity_mesh.h"

#include <cassert>
#include <cmath>
#include <optional>
#include <vector>

namespace penumbra {

ElementSampler::ElementSampler(const Scene& scene, const RadiosityMesh& mesh, int element)
    : triangle_(scene.triangle(mesh.sceneMesh(element), mesh.sceneTriangle(element))),
      corners_(mesh.barycentrics(element)),
      n_(mesh.normal(element)) {}

ElementSample ElementSampler::at(const Vec3& w) const {
    const Scene::Triangle::Point x =
        triangle_.at(w.x * corners_[0] + w.y * corners_[1] + w.z * corners_[2]);
    return {x.p, x.pError, n_};
}

ElementSample ElementSampler::insetCorner(size_t k) const {
    Vec3 w(0.0f);
    w[static_cast<int>(k)] = 1.0f;
    return at(insetWeights(w));
}

ElementSample sampleElement(const Scene& scene, const RadiosityMesh& mesh, int element, Vec2 u) {
    return ElementSampler(scene, mesh, element).at(sampleUniformTriangle(u));
}

void stratifiedElementSamples(const Scene& scene, const RadiosityMesh& mesh, int element,
                              uint32_t seed, IVec2 key, std::span<ElementSample> out,
                              std::span<uint8_t> children) {
    assert(children.empty() || children.size() == out.size());
    const SampleSequence2D sequence(seed, key, 1);  // a Sampler's first get2D
    const ElementSampler points(scene, mesh, element);
    for (size_t k = 0; k < out.size(); ++k) {
        const Vec3 w = sampleUniformTriangle(sequence[static_cast<uint32_t>(k)]);
        out[k] = points.at(w);
        if (!children.empty())
            children[k] = static_cast<uint8_t>(RadiosityMesh::childAt(w));
    }
}

Color meanTransmittance(const Scene& scene, std::span<const ElementSample> a,
                        std::span<const ElementSample> b) {
    assert(!a.empty() && a.size() == b.size());
    Color sum(0.0f);
    for (size_t k = 0; k < a.size(); ++k)
        sum += scene.transmittance(a[k].p, a[k].pError, a[k].n, b[k].p, b[k].pError, b[k].n);
    return sum / static_cast<float>(a.size());
}

bool isCovered(const Scene& scene, const RadiosityMesh& mesh, const CoincidentFaces& coincident,
               const ElementSample& x, const Vec3& n, float gap, uint64_t& rays) {
    const Frame frame = Frame::fromNormal(n);
    constexpr float kSin = 0.8660254f, kCos = 0.5f;  // 60 degrees from the normal
    const std::array<Vec3, 5> probes = {Vec3(0.0f, 0.0f, 1.0f), Vec3(kSin, 0.0f, kCos),
                                        Vec3(-kSin, 0.0f, kCos), Vec3(0.0f, kSin, kCos),
                                        Vec3(0.0f, -kSin, kCos)};
    for (const Vec3& local : probes) {
        ++rays;
        const Vec3 w = frame.toWorld(local);
        const std::optional<SurfaceHit> hit =
            scene.intersect(Ray{offsetRayOrigin(x.p, x.pError, x.n, w), w});
        if (!hit)
            return false;
        const Material& material = scene.material(*hit);
        // Light passes through a transmissive surface, which the mesh does not hold.
        if (!holdsMaterial(material))
            return false;
        if (hit->t < gap)
            continue;
        // Farther, only from inside a closed object: the probe meets a one-sided back. A side
        // hidden by a coincident face is not there: the probe meets the side that replaces it
        // (coincident_faces.h), which may be another face's front (a box modelled twice, once
        // wound inwards and once outwards).
        bool frontFace = hit->frontFace(w), doubleSided = material.doubleSided;
        const int element = mesh.locate(hit->mesh, hit->triangle, hit->barycentric).element;
        if (element >= 0) {
            if (const auto side =
                    coincident.replacementAt(mesh.patch(element), frontFace, hit->p)) {
                frontFace = side->front;
                doubleSided = mesh.twoSided(side->patch);
            }
        }
        if (frontFace || doubleSided)
            return false;
    }
    return true;
}

bool hiddenByCoincident(const CoincidentFaces& coincident, const RadiosityMesh& mesh, int element,
                        bool front, const ElementSample& x) {
    return coincident.hidden(mesh.patch(element), front, x.p,
                             2.0f * glm::dot(glm::abs(x.n), x.pError));
}

CoverSamples coverSamples(const Scene& scene, const RadiosityMesh& mesh, int element, int samples,
                          float gap, uint32_t seed, const CoincidentFaces& coincident,
                          uint64_t& rays) {
    assert(samples >= 1 && samples <= CoverSamples::kMaxPoints);
    CoverSamples c;
    c.points.resize(static_cast<size_t>(samples));
    c.child.resize(c.points.size());
    c.sides.resize(c.points.size(), 0);
    stratifiedElementSamples(scene, mesh, element, seed, IVec2(element, 0), c.points, c.child);
    for (size_t k = 0; k < c.points.size(); ++k) {
        const ElementSample& x = c.points[k];
        for (const bool front : {true, false}) {
            const bool covered =
                hiddenByCoincident(coincident, mesh, element, front, x) ||
                isCovered(scene, mesh, coincident, x, front ? x.n : -x.n, gap, rays);
            if (covered)
                continue;
            c.sides[k] |= front ? 1 : 2;
            c.exposed[front ? 0 : 1].push_back(static_cast<uint16_t>(k));
        }
    }
    return c;
}

std::vector<const Light*> punctualLights(const Scene& scene) {
    std::vector<const Light*> lights;
    for (const auto& light : scene.lights()) {
        if (light->isDelta())
            lights.push_back(light.get());
    }
    return lights;
}

PunctualDirect punctualDirect(const Scene& scene, const RadiosityMesh& mesh, int element,
                              std::span<const Light* const> lights, int samples, uint32_t seed,
                              const CoincidentFaces* coincident) {
    PunctualDirect result;
    if (lights.empty() && !scene.environment())
        return result;
    std::vector<ElementSample> points(static_cast<size_t>(samples));
    stratifiedElementSamples(scene, mesh, element, seed, IVec2(element, 0), points);
    std::vector<std::array<bool, 2>> hidden(points.size(), {false, false});
    if (coincident) {
        for (size_t k = 0; k < points.size(); ++k) {
            for (const bool front : {true, false})
                hidden[k][front ? 0 : 1] =
                    hiddenByCoincident(*coincident, mesh, element, front, points[k]);
        }
    }
    const std::array<Vec3, 3> corners = mesh.corners(element);
    const double area = mesh.area(element);
    std::vector<std::array<Color, 2>> E(points.size(), {Color(0.0f), Color(0.0f)});
    for (const Light* light : lights) {
        // Per light: the irradiance E_k = I cos(theta) T / d² (point, spot) or E_perp cos(theta)
        // T (directional) at each point, with the light's position where it has one.
        std::array<Color, 2> lightSum{Color(0.0f), Color(0.0f)};
        std::optional<Vec3> position;
        for (size_t k = 0; k < points.size(); ++k) {
            const ElementSample& x = points[k];
            const LightSampleContext ctx{x.p, x.pError, x.n};
            // A delta light has one direction: the sample point is irrelevant.
            const std::optional<LightLiSample> ls = light->sampleLi(ctx, Vec2(0.5f));
            if (!ls)
                continue;
            if (light->kind() != LightKind::Directional)
                position = ls->pLight;
            const float cosTheta = glm::dot(ls->wi, x.n);
            if (cosTheta == 0.0f || hidden[k][cosTheta > 0.0f ? 0 : 1])
                continue;
            ++result.rays;
            const Color T =
                scene.transmittance(x.p, x.pError, x.n, ls->pLight, ls->pLightError, ls->nLight);
            const Color Ek = ls->L * std::abs(cosTheta) * T;
            E[k][cosTheta > 0.0f ? 0 : 1] += Ek;
            lightSum[cosTheta > 0.0f ? 0 : 1] += Ek;
        }
        if (!position) {  // directional (E constant but for shadows), or no light arrives
            for (int side = 0; side < 2; ++side)
                result.D[side] += lightSum[side] * (kInvPi / static_cast<float>(samples));
            continue;
        }
        // A point or spot light: the mean irradiance is (1 / A) integral of I(omega) T over the
        // solid angle Omega the element subtends, the area samples reweighted to solid angle by
        // w_k = cos(theta_k) / d_k² (a ratio estimator, exact without shadows and falloff): a
        // light a metre over a kilometre-sized element sees its peak, which area samples miss.
        double weights = 0.0;
        for (const ElementSample& x : points) {
            const Vec3 d = *position - x.p;
            const double d2 = glm::dot(d, d);
            if (d2 > 0.0)
                weights += std::abs(glm::dot(d, x.n)) / (std::sqrt(d2) * d2);
        }
        if (!(weights > 0.0) || !(area > 0.0))
            continue;
        const double omega = std::abs(triangleSolidAngle(*position, corners));
        const float scale = static_cast<float>(omega / (area * weights)) * kInvPi;
        for (int side = 0; side < 2; ++side)
            result.D[side] += lightSum[side] * scale;
    }
    if (scene.environment()) {
        for (int side = 0; side < 2; ++side) {
            Color sum(0.0f);
            for (size_t k = 0; k < points.size(); ++k) {
                if (hidden[k][side])
                    continue;
                const ElementSample& x = points[k];
                sum +=
                    environmentD(scene, x, side == 0 ? x.n : -x.n, seed, IVec2(element, 1 + side),
                                 static_cast<uint32_t>(k) * kEnvironmentDirections,
                                 kEnvironmentDirections, result.rays);
            }
            result.environment[side] = sum / static_cast<float>(samples);
            result.D[side] += result.environment[side];
        }
    }
    std::array<float, 2> lo{INFINITY, INFINITY}, hi{0.0f, 0.0f};
    for (const auto& e : E) {
        for (int side = 0; side < 2; ++side) {
            lo[side] = glm::min(lo[side], maxComponent(e[side]));
            hi[side] = glm::max(hi[side], maxComponent(e[side]));
        }
    }
    for (int side = 0; side < 2; ++side)
        result.spread[side] = (hi[side] - lo[side]) * kInvPi;
    return result;
}

}  // namespace penumbra
