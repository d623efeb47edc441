#include "radiosity/point_direct.h"

#include "core/light.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "radiosity/environment_direct.h"
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
// The largest float below 1: a rescaled coordinate stays in [0, 1).
constexpr float kBelowOne = 0x1.fffffep-1f;

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
    std::map<uint32_t, std::vector<int>> patchesOf;
    for (size_t p = 0; p < mesh.patchCount(); ++p) {
        const int patch = static_cast<int>(p);
        const bool front = exposed(patch, true),
                   back = mesh.twoSided(patch) && exposed(patch, false);
        if (maxComponent(mesh.Le(patch)) <= 0.0f || !(front || back))
            continue;
        byMesh[mesh.sceneMesh(patch)].patches.push_back(
            makePatch(mesh.corners(patch), mesh.normal(patch), mesh.Le(patch), front, back));
        patchesOf[mesh.sceneMesh(patch)].push_back(patch);
    }
    for (auto& [light, patches] : patchesOf)
        placePoints(scene, mesh, patches, light, byMesh[light]);
    for (auto& [sceneMesh, light] : byMesh) {
        light.twoSided = light.patches.front().back;
        lights_.push_back(std::move(light));
    }
}

// The light's cells: each patch cut 1:4 (at its edge midpoints, as RadiosityMesh splits) `levels`
// times, the fewest that give the light kMinCells cells. Its points: point k of a (0,2)-sequence,
// its first coordinate choosing a cell by area (the cells in the mesh's order, which is mostly
// spatial) and, rescaled within that cell's interval, with the second, the point in it. The first
// 2^m points are then stratified over the light's area, so every prefix a point casts rays to is
// spread over the whole light, not over its first patches.
void PointDirect::placePoints(const Scene& scene, const RadiosityMesh& mesh,
                              const std::vector<int>& patches, uint32_t sceneMesh,
                              AreaLight& light) {
    int levels = 0;
    while (patches.size() << (2 * levels) < kMinCells)
        ++levels;
    // Each cell's corners in its patch's barycentric weights.
    std::vector<std::array<Vec3, 3>> cells = {{Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}};
    for (int level = 0; level < levels; ++level) {
        std::vector<std::array<Vec3, 3>> finer;
        for (const auto& [a, b, c] : cells) {
            const std::array<Vec3, 6> points = {
                a, b, c, 0.5f * (a + b), 0.5f * (b + c), 0.5f * (c + a)};
            for (const auto& k : RadiosityMesh::kChildCorners)
                finer.push_back({points[k[0]], points[k[1]], points[k[2]]});
        }
        cells = std::move(finer);
    }
    std::vector<double> cdf(1, 0.0);
    std::vector<std::array<Vec3, 3>> weights;
    for (size_t j = 0; j < patches.size(); ++j) {
        const Patch& patch = light.patches[j];
        for (const std::array<Vec3, 3>& w : cells) {
            std::array<Vec3, 3> corners;
            for (size_t k = 0; k < 3; ++k)
                corners[k] = w[k].x * patch.corners[0] + w[k].y * patch.corners[1] +
                             w[k].z * patch.corners[2];
            light.cells.push_back(
                makePatch(corners, patch.normal, patch.Le, patch.front, patch.back));
            light.cellPatch.push_back(static_cast<uint32_t>(j));
            weights.push_back(w);
            cdf.push_back(cdf.back() + light.cells.back().area);
        }
    }
    const SampleSequence2D sequence(kLightPointSeed, IVec2(static_cast<int>(sceneMesh), 0), 1);
    for (uint32_t k = 0; k < kLightPoints; ++k) {
        const Vec2 u = sequence[k];
        const double at = u.x * cdf.back();
        const size_t cell = std::min<size_t>(
            static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), at) - cdf.begin()) - 1,
            light.cells.size() - 1);
        const double width = cdf[cell + 1] - cdf[cell];
        const float v = width > 0.0 ? static_cast<float>((at - cdf[cell]) / width) : 0.5f;
        const Vec3 b = sampleUniformTriangle(Vec2(std::min(v, kBelowOne), u.y));
        const std::array<Vec3, 3>& w = weights[cell];
        const ElementSampler sampler(scene, mesh, patches[light.cellPatch[cell]]);
        light.points.push_back(sampler.at(b.x * w[0] + b.y * w[1] + b.z * w[2]));
        light.pointCell.push_back(static_cast<uint32_t>(cell));
    }
}

PointDirect::Patch PointDirect::makePatch(const std::array<Vec3, 3>& corners, const Vec3& normal,
                                          const Color& Le, bool front, bool back) {
    const Vec3 c = (corners[0] + corners[1] + corners[2]) / 3.0f;
    float radius = 0.0f;
    for (const Vec3& corner : corners)
        radius = std::max(radius, glm::length(corner - c));
    const float area =
        0.5f * glm::length(glm::cross(corners[1] - corners[0], corners[2] - corners[0]));
    return {corners, normal, c, area, radius, Le, front, back};
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
    const Bounds3& bounds = scene_.bounds();
    float nearest = scene_.environment() && !bounds.empty()
                        ? kEnvironmentDistance * bounds.boundingRadius()
                        : std::numeric_limits<float>::infinity();
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

// The rays from one point to the fixed points of one light, the visible fraction of each cell
// and of the whole light weighted by the unoccluded kernel.
class PointDirect::LightRays {
  public:
    LightRays(const Scene& scene, const AreaLight& light, const ElementSample& x, const Vec3& n)
        : scene_(scene), light_(light), x_(x), n_(n), cells_(light.cells.size()) {}

    // Traces the light's points [traced(), end).
    void traceTo(size_t end, uint64_t& rays) {
        for (; traced_ < std::min(end, light_.points.size()); ++traced_) {
            const ElementSample& y = light_.points[traced_];
            const Vec3 d = y.p - x_.p;
            const float r2 = glm::dot(d, d);
            const float cosX = glm::dot(n_, d), cosY = -glm::dot(y.n, d);
            if (!(r2 > 0.0f) || cosX <= 0.0f || (cosY <= 0.0f && !light_.twoSided))
                continue;
            const double w = double(cosX) * std::abs(cosY) / (double(r2) * r2);
            ++rays;
            const Color T = scene_.transmittance(x_.p, x_.pError, n_, y.p, y.pError, y.n);
            least_ = std::min(least_, maxComponent(T));
            most_ = std::max(most_, maxComponent(T));
            cells_[light_.pointCell[traced_]].add(w, T);
            all_.add(w, T);
        }
    }
    size_t traced() const { return traced_; }
    bool any() const { return all_.weights > 0.0; }
    // Whether every ray was blocked; whether they differed (a penumbra).
    bool allHidden() const { return any() && most_ == 0.0f; }
    bool disagree() const { return most_ > least_; }
    Color fraction() const { return all_.fraction(); }
    // The sum over the cells of their unoccluded light times their own visible fraction, the
    // light's where a cell has no point yet.
    Color byCells(const std::vector<Color>& cellLight) const {
        Color e(0.0f);
        for (size_t c = 0; c < cells_.size(); ++c)
            e += cellLight[c] * (cells_[c].weights > 0.0 ? cells_[c].fraction() : fraction());
        return e;
    }

  private:
    struct Fraction {
        double weights = 0.0;
        Color visible{0.0f};
        void add(double w, const Color& T) {
            weights += w;
            visible += static_cast<float>(w) * T;
        }
        Color fraction() const { return visible / static_cast<float>(weights); }
    };
    const Scene& scene_;
    const AreaLight& light_;
    const ElementSample& x_;
    const Vec3& n_;
    std::vector<Fraction> cells_;
    Fraction all_;
    size_t traced_ = 0;
    float least_ = std::numeric_limits<float>::infinity(), most_ = 0.0f;
};

Color PointDirect::emitted(const AreaLight& light, const ElementSample& x, const Vec3& n,
                           const Color& unoccluded, float total, uint64_t& rays) const {
    const float share = maxComponent(unoccluded);
    LightRays traced(scene_, light, x, n);
    traced.traceTo(
        std::max(kMinRays, static_cast<size_t>(std::lround(kRaysPerPoint * share / total))), rays);
    const bool major = share * kPenumbraShare >= total;
    if (major && traced.allHidden())
        traced.traceTo(kConfirmRays, rays);
    if (!traced.any())
        return Color(0.0f);
    if (!major || !traced.disagree())
        return unoccluded * traced.fraction();
    std::vector<Color> cellLight;
    cellLight.reserve(light.cells.size());
    for (const Patch& cell : light.cells) {
        cellLight.push_back(emitsToward(cell.normal, cell.corners[0], cell.front, cell.back, x.p)
                                ? cell.Le * formFactor(x.p, n, cell)
                                : Color(0.0f));
    }
    traced.traceTo(kPenumbraRays, rays);
    Color shown = traced.byCells(cellLight);
    while (traced.traced() < light.points.size()) {
        traced.traceTo(2 * traced.traced(), rays);
        const Color finer = traced.byCells(cellLight);
        const bool settled = maxComponent(glm::abs(finer - shown)) <= kSettled * total;
        shown = finer;
        if (settled)
            break;
    }
    return shown;
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
    Parts D;
    D.punctual = E * kInvPi;
    // The environment through the same directions at every point, so that the field is smooth.
    D.environment =
        environmentD(scene_, x, n, kEnvironmentSeed, IVec2(0), 0, kEnvironmentDirections, rays);
    // Each light's unoccluded light (its share of the rays).
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
        if (maxComponent(unoccluded[l]) > 0.0f)
            D.emitters += emitted(lights_[l], x, n, unoccluded[l], total, rays);
    }
    return D;
}

}  // namespace penumbra
