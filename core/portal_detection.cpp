#include "core/portal_detection.h"

#include "core/sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <optional>
#include <random>

namespace penumbra {

namespace {

// Hits along a ray, passing through thin transmissive surfaces (a window's glazing lets the sky
// through: the opening is the frame around it).
std::optional<SurfaceHit> firstOpaqueHit(const Scene& scene, Ray ray) {
    for (int crossings = 0; crossings < 8; ++crossings) {
        const std::optional<SurfaceHit> hit = scene.intersect(ray);
        if (!hit)
            return std::nullopt;
        const Material& material = scene.material(*hit);
        if (!(material.transmission > 0.0f && material.thinWalled()))
            return hit;
        ray = Scene::spawnRay(*hit, ray.d);
    }
    return std::nullopt;  // a stack of panes: treated as open
}

// The share of `directions` (unit vectors) from p that hit an opaque surface.
float enclosure(const Scene& scene, const Vec3& p, const std::vector<Vec3>& directions) {
    int hits = 0;
    for (const Vec3& d : directions)
        hits += firstOpaqueHit(scene, Ray{p, d}).has_value() ? 1 : 0;
    return float(hits) / float(directions.size());
}

struct Crossing {
    Vec3 p;       // where the escaping ray crossed the opening
    Vec3 normal;  // the plane of the wall around it, towards the inside
    Vec3 d;       // the escaping ray's direction
};

// Where the ray from p along d (which leaves the scene) crossed the opening: rays turned by
// growing angles off d, eight around it at each angle, until one hits a surface facing it (the
// wall around the opening, not the reveals along the ray); the crossing is d's intersection with
// the plane of the nearest such hit.
std::optional<Crossing> crossing(const Scene& scene, const Vec3& p, const Vec3& d) {
    const Frame frame = Frame::fromNormal(d);
    const Vec3 &u = frame.s, &v = frame.t;
    for (const float degrees : {2.0f, 5.0f, 10.0f, 20.0f, 40.0f}) {
        const float s = std::sin(glm::radians(degrees)), c = std::cos(glm::radians(degrees));
        std::optional<SurfaceHit> nearest;
        for (int k = 0; k < 8; ++k) {
            const float phi = 2.0f * kPi * float(k) / 8.0f;
            const Vec3 w = glm::normalize(c * d + s * (std::cos(phi) * u + std::sin(phi) * v));
            const std::optional<SurfaceHit> hit = firstOpaqueHit(scene, Ray{p, w});
            if (hit && std::abs(glm::dot(hit->ng, w)) > 0.5f && (!nearest || hit->t < nearest->t))
                nearest = hit;
        }
        if (!nearest)
            continue;
        Vec3 n = nearest->ng;
        if (glm::dot(n, d) > 0.0f)
            n = -n;
        const float t = glm::dot(nearest->p - p, n) / glm::dot(d, n);
        if (!(t > 0.0f) || !std::isfinite(t))
            return std::nullopt;
        return Crossing{p + t * d, n, d};
    }
    return std::nullopt;
}

// Union-find over n items: the groups of the pairs `linked` joins.
std::vector<std::vector<size_t>> components(size_t n,
                                            const std::function<bool(size_t, size_t)>& linked) {
    std::vector<size_t> parent(n);
    std::iota(parent.begin(), parent.end(), size_t(0));
    const auto root = [&](size_t i) {
        while (parent[i] != i)
            i = parent[i] = parent[parent[i]];
        return i;
    };
    for (size_t i = 0; i < n; ++i)
        for (size_t j = i + 1; j < n; ++j)
            if (root(i) != root(j) && linked(i, j))
                parent[root(i)] = root(j);
    std::vector<std::vector<size_t>> members(n);
    for (size_t i = 0; i < n; ++i)
        members[root(i)].push_back(i);
    std::erase_if(members, [](const std::vector<size_t>& m) { return m.empty(); });
    return members;
}

// A rectangle in a plane's (u, v) coordinates, and how many crossings it holds.
struct Box {
    float u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
    size_t count = 0;

    void extend(float u, float v) {
        u0 = std::min(u0, u);
        v0 = std::min(v0, v);
        u1 = std::max(u1, u);
        v1 = std::max(v1, v);
    }
    // Whether the two lie within `gap` of each other.
    bool near(const Box& b, float gap) const {
        return b.u0 <= u1 + gap && u0 <= b.u1 + gap && b.v0 <= v1 + gap && v0 <= b.v1 + gap;
    }
};

// The openings in one wall, as portals. A window has depth (a frame, sashes at two depths, a
// reveal), so the crossings found around it lie in parallel planes a few centimetres apart; each
// escaping ray is followed on to the outermost of them, where every ray through the opening
// passes, and the window is one portal there, not pieces at three depths. In that plane: the
// crossings linked by steps shorter than `gap`, each group's rectangle, rectangles within `gap`
// of each other merged (the panes of one window between its mullions), those of fewer than
// `least` crossings dropped (stray rays through a crack), the rest enlarged by half the gap on
// every side, for the crossings sample the opening's inside, not its edge. One edge is
// horizontal (across +Y) unless the plane is nearly horizontal, a skylight, whose edges follow X
// and Z.
void openingsInWall(const std::vector<Crossing>& crossings, const std::vector<size_t>& wall,
                    float gap, size_t least, std::vector<Portal>& portals) {
    Vec3 n(0.0f);
    for (const size_t i : wall)
        n += crossings[i].normal;
    n = glm::normalize(n);  // towards the inside
    float outermost = INFINITY;
    for (const size_t i : wall)
        outermost = std::min(outermost, glm::dot(crossings[i].p, n));
    std::vector<Vec3> onPlane;
    Vec3 centre(0.0f);
    for (const size_t i : wall) {
        const Crossing& c = crossings[i];
        // The escaping ray leaves against n, so the step along it is never negative.
        const float t = (outermost - glm::dot(c.p, n)) / std::min(glm::dot(c.d, n), -1e-3f);
        onPlane.push_back(c.p + t * c.d);
        centre += onPlane.back();
    }
    centre /= float(onPlane.size());
    const Vec3 u = std::abs(n.y) < 0.9f ? glm::normalize(glm::cross(Vec3(0, 1, 0), n))
                                        : glm::normalize(glm::cross(n, Vec3(0, 0, 1)));
    const Vec3 v = glm::cross(n, u);
    std::vector<Vec2> all;
    for (const Vec3& p : onPlane)
        all.push_back(Vec2(glm::dot(p - centre, u), glm::dot(p - centre, v)));
    // Only crossings in a dense crowd count, as in DBSCAN (Ester et al. 1996): a few stray rays
    // (past a frame that does not close, off a misjudged plane) would otherwise chain two windows
    // into one portal across the wall between them, or stretch one over its surroundings.
    constexpr int kCrowd = 4;
    std::vector<Vec2> uv;
    for (const Vec2& a : all) {
        const auto near = std::count_if(all.begin(), all.end(),
                                        [&](const Vec2& b) { return glm::distance(a, b) <= gap; });
        if (near > kCrowd)  // itself and kCrowd others
            uv.push_back(a);
    }
    std::vector<Box> boxes;
    for (const std::vector<size_t>&group : components(
             uv.size(), [&](size_t i, size_t j) { return glm::distance(uv[i], uv[j]) <= gap; })) {
        Box box;
        for (const size_t k : group)
            box.extend(uv[k].x, uv[k].y);
        box.count = group.size();
        boxes.push_back(box);
    }
    for (bool merged = true; merged;) {
        merged = false;
        for (size_t i = 0; i < boxes.size() && !merged; ++i) {
            for (size_t j = i + 1; j < boxes.size() && !merged; ++j) {
                if (!boxes[i].near(boxes[j], gap))
                    continue;
                boxes[i].extend(boxes[j].u0, boxes[j].v0);
                boxes[i].extend(boxes[j].u1, boxes[j].v1);
                boxes[i].count += boxes[j].count;
                boxes.erase(boxes.begin() + std::ptrdiff_t(j));
                merged = true;
            }
        }
    }
    const float margin = 0.5f * gap;
    for (const Box& b : boxes) {
        if (b.count < least)
            continue;
        const Vec3 corner = centre + (b.u0 - margin) * u + (b.v0 - margin) * v;
        portals.push_back(
            Portal{corner, (b.u1 - b.u0 + 2.0f * margin) * u, (b.v1 - b.v0 + 2.0f * margin) * v});
    }
}

}  // namespace

std::vector<Portal> detectPortals(const Scene& scene, const PortalDetectionSettings& settings) {
    if (scene.bounds().empty() || scene.triangleCount() == 0)
        return {};
    // Fixed directions for the enclosure test: a spherical Fibonacci set (Marques et al. 2013),
    // evenly spread.
    std::vector<Vec3> directions;
    constexpr int kEnclosureDirections = 64;
    for (int k = 0; k < kEnclosureDirections; ++k) {
        const float z = 1.0f - (2.0f * float(k) + 1.0f) / float(kEnclosureDirections);
        const float phi = 2.0f * kPi * float(k) * 0.6180339887f;
        const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        directions.push_back(Vec3(r * std::cos(phi), r * std::sin(phi), z));
    }
    // Points on the surfaces by area, each on both sides, a thousandth of the scene's size off.
    std::vector<float> areas;
    std::vector<std::pair<uint32_t, uint32_t>> triangles;
    for (uint32_t m = 0; m < scene.meshes().size(); ++m) {
        for (uint32_t t = 0; t < scene.meshes()[m].triangles.size(); ++t) {
            const Scene::Triangle tri = scene.triangle(m, t);
            areas.push_back(0.5f * glm::length(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0)));
            triangles.emplace_back(m, t);
        }
    }
    std::vector<float> cdf(areas.size() + 1);
    if (!(fillCdf(areas, cdf) > 0.0))
        return {};
    const float radius = scene.bounds().boundingRadius();
    const float offset = 1e-3f * radius;

    const Bounds3 bounds = scene.bounds();
    // The crossings from origins [first, first + count), those outside the scene's bounds left
    // out (they met a plane far off, not an opening of the scene).
    const auto crossingsFrom = [&](int first, int count) {
        std::vector<std::vector<Crossing>> found(static_cast<size_t>(count));
        tbb::parallel_for(0, count, [&](int k) {
            const int o = first + k;
            std::mt19937 random(uint32_t(o) * 2654435761u + 17u);
            std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
            const auto [mesh, triangle] = triangles[invertCdf(cdf, uniform(random)).index];
            const Vec3 b = sampleUniformTriangle(Vec2(uniform(random), uniform(random)));
            const SurfaceHit hit = scene.surfaceAt(mesh, triangle, b);
            for (const float side : {1.0f, -1.0f}) {
                const Vec3 p = hit.p + side * (offset + glm::length(hit.pError)) * hit.ng;
                if (enclosure(scene, p, directions) < settings.enclosedShare)
                    continue;
                for (int r = 0; r < settings.raysPerOrigin; ++r) {
                    const Vec3 d = sampleUniformSphere(Vec2(uniform(random), uniform(random)));
                    if (firstOpaqueHit(scene, Ray{p, d}))
                        continue;
                    if (const std::optional<Crossing> c = crossing(scene, p, d))
                        found[size_t(k)].push_back(*c);
                }
            }
        });
        std::vector<Crossing> all;
        for (const std::vector<Crossing>& f : found)
            all.insert(all.end(), f.begin(), f.end());
        std::erase_if(all, [&](const Crossing& c) {
            return glm::any(glm::lessThan(c.p, bounds.lo - Vec3(offset))) ||
                   glm::any(glm::greaterThan(c.p, bounds.hi + Vec3(offset)));
        });
        return all;
    };
    // A first round of origins; then as many more as the rate it found them at says are needed
    // for `targetCrossings` (small openings and large rooms give few per origin, and too few
    // crossings leave an opening in pieces), up to `maxOrigins`. None in the first round: no
    // opening worth a portal, and a closed room costs one round.
    std::vector<Crossing> crossings = crossingsFrom(0, settings.origins);
    if (!crossings.empty() && crossings.size() < size_t(settings.targetCrossings)) {
        const double perOrigin = double(crossings.size()) / double(settings.origins);
        const int more =
            int(std::min(double(settings.maxOrigins - settings.origins),
                         double(settings.targetCrossings) / perOrigin - double(settings.origins)));
        if (more > 0) {
            const std::vector<Crossing> rest = crossingsFrom(settings.origins, more);
            crossings.insert(crossings.end(), rest.begin(), rest.end());
        }
    }
    // At most a few thousand crossings: the grouping compares every pair.
    constexpr size_t kMaxCrossings = 6000;
    if (crossings.size() > kMaxCrossings) {
        std::vector<Crossing> kept;
        for (size_t k = 0; k < kMaxCrossings; ++k)
            kept.push_back(crossings[k * crossings.size() / kMaxCrossings]);
        crossings = std::move(kept);
    }
    // The walls the crossings lie in: normals within about 8 degrees, depths within a twentieth of
    // the scene's bounding radius (a wall's thickness, its window's reveal and frame).
    const float gap = 0.02f * radius;
    const float wallDepth = 0.05f * radius;
    const auto sameWall = [&](size_t i, size_t j) {
        const Crossing &a = crossings[i], &b = crossings[j];
        return glm::dot(a.normal, b.normal) > 0.99f &&
               std::abs(glm::dot(b.p - a.p, a.normal)) <= wallDepth;
    };
    const size_t least = std::max<size_t>(8, crossings.size() / 50);
    std::vector<Portal> portals;
    for (const std::vector<size_t>& wall : components(crossings.size(), sameWall))
        openingsInWall(crossings, wall, gap, least, portals);
    std::sort(portals.begin(), portals.end(),
              [](const Portal& a, const Portal& b) { return a.area() > b.area(); });
    if (portals.size() > size_t(settings.maxPortals))
        portals.resize(size_t(settings.maxPortals));
    std::erase_if(portals, [](const Portal& p) { return !(p.area() > 0.0f); });
    return portals;
}

}  // namespace penumbra
