// Each source's wedges are made once, one per silhouette edge. The triangles a wedge may cross
// are found by rays cast from points along its edge away from the source, past transparent
// surfaces, so that the cost goes with the edges, not with edges times triangles; each triangle
// they hit first is then cut by the wedge exactly: the wedge's plane through the triangle,
// clipped to the wedge's three sides and to the triangle.
#include "radiosity/shadow_lines.h"

#include "core/scene.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>

namespace penumbra {

namespace {

// The wedge of a silhouette edge (a, b) away from a source: the points L + s (P - L), s >= 1,
// P on the edge (a source at L), or P + s d, s >= 0 (a source at infinity, its light along d).
// It lies in a plane, bounded there by three lines, each given by a point and its inward normal.
struct Wedge {
    glm::dvec3 a{0.0}, b{0.0};
    glm::dvec3 normal{0.0};  // unit normal of the wedge's plane
    std::array<glm::dvec3, 3> sidePoint{};
    std::array<glm::dvec3, 3> sideNormal{};  // in the plane, pointing into the wedge
    glm::dvec3 source{0.0};                  // L, or for a source at infinity -d
    bool atInfinity = false;
    double lit = 1.0;  // the side of the plane (the sign along normal) away from the occluder
};

// An edge of the held triangles, their corners welded within the tolerance, with the normals
// of the triangles that share it.
struct SharedEdge {
    glm::dvec3 a{0.0}, b{0.0};
    std::vector<glm::dvec3> normals;
    glm::dvec3 apex{0.0};  // the first such triangle's corner off the edge
};

// Points along an edge from which rays look for the triangles its wedge cuts.
constexpr int kMaxPointsPerEdge = 32;

std::vector<SharedEdge> sharedEdges(const std::vector<HeldTriangle>& held, double tolerance) {
    using Corner = std::array<int64_t, 3>;
    const auto weld = [&](const glm::dvec3& p) {
        return Corner{std::llround(p.x / tolerance), std::llround(p.y / tolerance),
                      std::llround(p.z / tolerance)};
    };
    std::map<std::pair<Corner, Corner>, size_t> index;
    std::vector<SharedEdge> edges;
    for (const HeldTriangle& t : held) {
        for (size_t k = 0; k < 3; ++k) {
            const glm::dvec3& a = t.p[k];
            const glm::dvec3& b = t.p[(k + 1) % 3];
            const Corner ka = weld(a), kb = weld(b);
            const auto key = ka < kb ? std::pair{ka, kb} : std::pair{kb, ka};
            const auto [it, added] = index.try_emplace(key, edges.size());
            if (added)
                edges.push_back({a, b, {}, t.p[(k + 2) % 3]});
            edges[it->second].normals.push_back(t.normal);
        }
    }
    return edges;
}

// The direction from x towards the source (not unit).
glm::dvec3 towardsSource(const ShadowSource& s, const glm::dvec3& x) {
    return s.atInfinity() ? -glm::dvec3(s.direction) : glm::dvec3(s.position) - x;
}

// Whether the edge is on the outline of the occluders seen from the source: the faces that
// share it face the source differently, or it has one face (an open surface's border) or more
// than two.
bool silhouette(const SharedEdge& e, const ShadowSource& s) {
    if (e.normals.size() != 2)
        return true;
    const glm::dvec3 toSource = towardsSource(s, 0.5 * (e.a + e.b));
    return (glm::dot(e.normals[0], toSource) > 0.0) != (glm::dot(e.normals[1], toSource) > 0.0);
}

// The wedge of edge e away from source s; none when the source is on the edge's line.
std::optional<Wedge> wedgeOf(const SharedEdge& e, const ShadowSource& s) {
    Wedge w;
    w.a = e.a;
    w.b = e.b;
    w.atInfinity = s.atInfinity();
    const glm::dvec3 edge = e.b - e.a;
    glm::dvec3 away;  // from the source through the edge's first end
    if (w.atInfinity) {
        away = glm::normalize(glm::dvec3(s.direction));
        w.source = -away;
        w.normal = glm::cross(away, edge);
        if (!(glm::length(w.normal) > 1e-9 * glm::length(edge)))
            return std::nullopt;
        w.normal = glm::normalize(w.normal);
        const glm::dvec3 across = glm::cross(w.normal, away);
        w.sidePoint = {e.a, e.a, e.b};
        w.sideNormal = {glm::cross(w.normal, edge), across, across};
    } else {
        const glm::dvec3 L(s.position);
        away = e.a - L;
        w.source = L;
        w.normal = glm::cross(e.a - L, e.b - L);
        if (!(glm::length(w.normal) > 1e-9 * glm::length(e.a - L) * glm::length(e.b - L)))
            return std::nullopt;
        w.normal = glm::normalize(w.normal);
        w.sidePoint = {e.a, L, L};
        w.sideNormal = {glm::cross(w.normal, edge), glm::cross(w.normal, e.a - L),
                        glm::cross(w.normal, e.b - L)};
    }
    // Inwards: beyond the edge, away from the source; from side a towards b; from side b
    // towards a.
    const std::array<glm::dvec3, 3> inwards = {away, edge, -edge};
    for (size_t k = 0; k < 3; ++k) {
        if (glm::dot(w.sideNormal[k], inwards[k]) < 0.0)
            w.sideNormal[k] = -w.sideNormal[k];
    }
    w.lit = glm::dot(e.apex - e.a, w.normal) > 0.0 ? -1.0 : 1.0;
    return w;
}

// The part of triangle t's crossing with the wedge's plane that lies inside the wedge, clipped
// to t; false when there is none of minLength or more off t's own edges.
bool crossing(const HeldTriangle& t, const Wedge& w, double tolerance, double minLength,
              TriangleSegment& segment) {
    // The edge in t's plane (t's own edge, or an edge lying on it) casts nothing on t.
    if (std::abs(glm::dot(t.normal, w.a - t.p[0])) <= tolerance &&
        std::abs(glm::dot(t.normal, w.b - t.p[0])) <= tolerance)
        return false;
    glm::dvec3 from, to;
    if (!planeCrossing(t.p, w.normal, w.a, tolerance, from, to))
        return false;
    // The wedge's three sides, each linear along the segment.
    double t0 = 0.0, t1 = 1.0;
    for (size_t k = 0; k < 3; ++k) {
        const double f0 = glm::dot(from - w.sidePoint[k], w.sideNormal[k]);
        const double f1 = glm::dot(to - w.sidePoint[k], w.sideNormal[k]);
        if (f0 < 0.0 && f1 < 0.0)
            return false;
        if (f0 < 0.0)
            t0 = std::max(t0, f0 / (f0 - f1));
        else if (f1 < 0.0)
            t1 = std::min(t1, f0 / (f0 - f1));
    }
    if (!(t1 > t0))
        return false;
    return clipToTriangle(t, from + t0 * (to - from), from + t1 * (to - from), tolerance, minLength,
                          segment);
}

// The held triangles (indices into `held`, by `heldIndex`) that rays from points along the
// wedge's edge, cast away from the source, meet first past transparent surfaces: those the
// wedge may cut where the edge's shadow begins. A point from which the source is hidden casts
// none. The rays start `nudge` metres off the edge, on the wedge's lit side, so that the faces
// meeting at the edge do not stop them.
std::vector<uint32_t> struckTriangles(const Scene& scene, const Wedge& w,
                                      const std::unordered_map<uint64_t, uint32_t>& heldIndex,
                                      double spacing, double nudge, double reach) {
    std::vector<uint32_t> struck;
    const double length = glm::distance(w.a, w.b);
    const int points = std::clamp(int(std::ceil(length / spacing)) + 1, 2, kMaxPointsPerEdge);
    const Vec3 zero(0.0f);
    for (int i = 0; i < points; ++i) {
        // From one end to the other, a thousandth of the edge inside.
        const double f = 1e-3 + (1.0 - 2e-3) * double(i) / double(points - 1);
        const glm::dvec3 p = w.a + f * (w.b - w.a);
        const glm::dvec3 toSource = w.atInfinity ? w.source : glm::normalize(w.source - p);  // unit
        const glm::dvec3 offEdge = p + nudge * w.lit * w.normal;
        const glm::dvec3 source = w.atInfinity ? offEdge + reach * toSource : w.source;
        if (luminance(scene.transmittance(Vec3(offEdge + nudge * toSource), zero, zero,
                                          Vec3(source), zero, zero)) < 0.5f)
            continue;
        Ray ray{Vec3(offEdge - nudge * toSource), Vec3(-toSource)};
        for (int layer = 0; layer <= Scene::kMaxTransparentLayers; ++layer) {
            const std::optional<SurfaceHit> hit = scene.intersect(ray);
            if (!hit)
                break;
            const auto it = heldIndex.find(triangleKey(hit->mesh, hit->triangle));
            if (it != heldIndex.end()) {
                struck.push_back(it->second);
                break;
            }
            ray = Scene::spawnRay(*hit, ray.d);  // through a surface the mesh does not hold
        }
    }
    std::ranges::sort(struck);
    struck.erase(std::unique(struck.begin(), struck.end()), struck.end());
    return struck;
}

}  // namespace

std::vector<ShadowSource> shadowSources(const Scene& scene) {
    const SceneDescription& description = scene.description();
    std::vector<ShadowSource> sources;
    for (const PunctualLightDesc& light : description.lights) {
        if (light.type == PunctualType::Directional)
            sources.push_back({Vec3(0.0f), glm::normalize(light.direction)});
        else
            sources.push_back({light.position, Vec3(0.0f)});
    }
    for (const LuminaireDesc& luminaire : description.luminaires)
        sources.push_back({luminaire.position, Vec3(0.0f)});
    if (description.environment && description.environment->sun)
        sources.push_back({Vec3(0.0f), -glm::normalize(description.environment->sun->direction)});
    return sources;
}

ShadowLines::ShadowLines(const Scene& scene, const std::vector<ShadowSource>& sources,
                         float minTriangleArea, float minSegmentLength) {
    const std::vector<HeldTriangle> held = heldTriangles(scene);
    if (held.empty() || sources.empty())
        return;
    const double diagonal = glm::length(glm::dvec3(scene.bounds().diagonal()));
    const double tolerance = kOnPlaneFraction * diagonal;

    std::vector<Wedge> wedges;
    std::vector<size_t> wedgeSource;
    const std::vector<SharedEdge> edges = sharedEdges(held, tolerance);
    for (size_t s = 0; s < sources.size(); ++s) {
        for (const SharedEdge& e : edges) {
            if (!silhouette(e, sources[s]))
                continue;
            if (const std::optional<Wedge> w = wedgeOf(e, sources[s])) {
                wedges.push_back(*w);
                wedgeSource.push_back(s);
            }
        }
    }
    wedges_ = wedges.size();

    std::unordered_map<uint64_t, uint32_t> heldIndex;
    for (uint32_t i = 0; i < held.size(); ++i)
        heldIndex.emplace(triangleKey(held[i].mesh, held[i].triangle), i);
    // Rays a receiver of the smallest size cut apart, and off the edge by ten tolerances.
    const double spacing = 4.0 * double(std::sqrt(minTriangleArea / 16.0f));
    const double nudge = 10.0 * tolerance;
    std::vector<std::vector<std::pair<uint32_t, TriangleSegment>>> cuts(wedges.size());
    tbb::parallel_for(size_t(0), wedges.size(), [&](size_t k) {
        const Wedge& w = wedges[k];
        for (const uint32_t i :
             struckTriangles(scene, w, heldIndex, spacing, nudge, 2.0 * diagonal)) {
            const HeldTriangle& t = held[i];
            const glm::dvec3 centre = (t.p[0] + t.p[1] + t.p[2]) / 3.0;
            // Too small to cut, or one-sided and facing away from the source (no light from it).
            if (t.area < double(minTriangleArea) ||
                (!t.twoSided &&
                 !(glm::dot(t.normal, towardsSource(sources[wedgeSource[k]], centre)) > 0.0)))
                continue;
            TriangleSegment segment;
            if (crossing(t, w, tolerance, double(minSegmentLength), segment))
                cuts[k].emplace_back(i, segment);
        }
    });
    std::vector<std::vector<TriangleSegment>> found(held.size());
    for (const auto& wedgeCuts : cuts) {
        for (const auto& [i, segment] : wedgeCuts)
            found[i].push_back(segment);
    }
    for (size_t i = 0; i < held.size(); ++i) {
        keepLongest(held[i], found[i], kMaxSegmentsPerTriangle);
        set(held[i], std::move(found[i]));
    }
}

}  // namespace penumbra
