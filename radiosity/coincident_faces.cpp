#include "radiosity/coincident_faces.h"

#include "core/scene.h"
#include "radiosity/box_grid.h"
#include "radiosity/radiosity_mesh.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace penumbra {

namespace {

using DVec3 = glm::dvec3;

// Parallel or opposite normals: |cos| above this (about 0.25 degrees).
constexpr double kParallelCosine = 1.0 - 1e-5;
// Corners within this fraction of the coordinates' magnitude of the other's plane: float
// positions of the same plane, not a surface laid a visible distance over another (which the
// covering probes see). Ray offsets are of the order of 1e-7 to 1e-6 of the magnitude.
constexpr double kRelativePlaneTolerance = 1e-5;
// Two triangles whose projections overlap by less than this fraction of their size only touch
// (neighbours in one plane share edges).
constexpr double kRelativeTouch = 1e-6;
// Hops from a hidden leaf side to the side that replaces it at most (shownLeafSide): three
// stacked copies of a face take two.
constexpr int kMaxCoincidentHops = 4;

struct Box {
    Vec3 lo, hi;
};

Box boundsOf(const std::array<Vec3, 3>& c) {
    return {glm::min(c[0], glm::min(c[1], c[2])), glm::max(c[0], glm::max(c[1], c[2]))};
}

DVec3 toDouble(const Vec3& v) {
    return DVec3(v);
}

// Whether the two triangles, in the plane of normal n, overlap with positive area: no separating
// axis among the six edge normals (the separating axis theorem for convex polygons).
bool overlapInPlane(const std::array<DVec3, 3>& a, const std::array<DVec3, 3>& b, const DVec3& n,
                    double size) {
    for (const auto* t : {&a, &b}) {
        for (int k = 0; k < 3; ++k) {
            const DVec3 axis = glm::cross(n, (*t)[(k + 1) % 3] - (*t)[k]);
            const double length = glm::length(axis);
            if (!(length > 0.0))
                continue;
            double aLo = INFINITY, aHi = -INFINITY, bLo = INFINITY, bHi = -INFINITY;
            for (int v = 0; v < 3; ++v) {
                const double pa = glm::dot(axis, a[v]) / length;
                const double pb = glm::dot(axis, b[v]) / length;
                aLo = std::min(aLo, pa);
                aHi = std::max(aHi, pa);
                bLo = std::min(bLo, pb);
                bHi = std::max(bHi, pb);
            }
            if (std::min(aHi, bHi) - std::max(aLo, bLo) <= kRelativeTouch * size)
                return false;
        }
    }
    return true;
}

double magnitude(const std::array<DVec3, 3>& c) {
    double m = 0.0;
    for (const DVec3& v : c)
        m = std::max({m, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    return m;
}

double longestEdge(const std::array<DVec3, 3>& c) {
    return std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
}

}  // namespace

CoincidentFaces::CoincidentFaces(const RadiosityMesh& mesh) : covers_(mesh.patchCount()) {
    const int n = static_cast<int>(mesh.patchCount());
    std::vector<Box> boxes(static_cast<size_t>(n));
    for (int p = 0; p < n; ++p)
        boxes[static_cast<size_t>(p)] = boundsOf(mesh.corners(p));
    std::vector<int> order(static_cast<size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return boxes[static_cast<size_t>(a)].lo.x < boxes[static_cast<size_t>(b)].lo.x;
    });
    const auto corners = [&](int p) {
        const auto c = mesh.corners(p);
        return std::array<DVec3, 3>{toDouble(c[0]), toDouble(c[1]), toDouble(c[2])};
    };
    const auto emits = [&](int p) { return maxComponent(mesh.Le(p)) > 0.0f; };
    // Whether patch a wins over patch b facing the same way (see the header).
    const auto wins = [&](int a, int b) { return emits(a) != emits(b) ? emits(a) : a < b; };
    const auto coincident = [&](int a, int b) {
        if (mesh.sceneMesh(a) == mesh.sceneMesh(b) &&
            mesh.sceneTriangle(a) == mesh.sceneTriangle(b))
            return false;  // the patches of one triangle tile it
        const DVec3 na = toDouble(mesh.normal(a)), nb = toDouble(mesh.normal(b));
        if (!(std::abs(glm::dot(na, nb)) >= kParallelCosine))
            return false;
        const std::array<DVec3, 3> ca = corners(a), cb = corners(b);
        const double tolerance = kRelativePlaneTolerance * std::max(magnitude(ca), magnitude(cb));
        for (int v = 0; v < 3; ++v) {
            if (std::abs(glm::dot(na, cb[v] - ca[0])) > tolerance ||
                std::abs(glm::dot(nb, ca[v] - cb[0])) > tolerance)
                return false;
        }
        return overlapInPlane(ca, cb, na, std::max(longestEdge(ca), longestEdge(cb)));
    };
    const auto cover = [&](int covered, int by, bool front, bool back, bool sameFacing) {
        covers_[static_cast<size_t>(covered)].push_back(
            {by, front, back, sameFacing, mesh.corners(by), mesh.normal(by)});
    };
    // A box's slack, so that corners a few float ulps apart still overlap.
    const auto slackOf = [](const Box& b) {
        return static_cast<float>(kRelativePlaneTolerance) *
               glm::max(glm::max(glm::abs(b.lo.x), glm::abs(b.hi.x)), 1.0f);
    };
    // The candidates: the pairs whose boxes, grown by their slack, overlap (box_grid.h), each
    // taken from the later of the two in the order of the boxes' lower x, in that order, so that
    // a patch's covers come in a fixed order.
    std::vector<int> rank(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
        rank[static_cast<size_t>(order[static_cast<size_t>(i)])] = i;
    std::vector<GridBox> grown(static_cast<size_t>(n));
    for (int p = 0; p < n; ++p) {
        const Box& b = boxes[static_cast<size_t>(p)];
        const glm::dvec3 slack(slackOf(b));
        grown[static_cast<size_t>(p)] = {glm::dvec3(b.lo) - slack, glm::dvec3(b.hi) + slack};
    }
    std::vector<std::pair<int, int>> candidates;  // (rank of the later, rank of the earlier)
    for (const auto& [i, j] : overlappingPairs(grown)) {
        const int ri = rank[i], rj = rank[j];
        candidates.emplace_back(std::max(ri, rj), std::min(ri, rj));
    }
    std::sort(candidates.begin(), candidates.end());
    for (const auto& [later, earlier] : candidates) {
        const int p = order[static_cast<size_t>(later)], q = order[static_cast<size_t>(earlier)];
        const Box& b = boxes[static_cast<size_t>(p)];
        const Box& o = boxes[static_cast<size_t>(q)];
        const Vec3 pad(slackOf(b));
        if (glm::any(glm::lessThan(o.hi + pad, b.lo)) ||
            glm::any(glm::lessThan(b.hi + pad, o.lo)) || !coincident(p, q))
            continue;
        if (glm::dot(mesh.normal(p), mesh.normal(q)) > 0.0f) {
            const int winner = wins(p, q) ? p : q;
            cover(winner == p ? q : p, winner, true, true, true);
        } else {
            cover(p, q, false, true, false);  // each one's back lies on the other's front
            cover(q, p, false, true, false);
        }
    }
    for (int p = 0; p < n; ++p) {
        if (!covers_[static_cast<size_t>(p)].empty()) {
            ++hiddenPatches_;
            hiddenArea_ += mesh.area(p);
        }
    }
}

std::optional<CoincidentFaces::Side> CoincidentFaces::replacementAt(int patch, bool front,
                                                                    const Vec3& p) const {
    const float magnitude = glm::max(glm::abs(p.x), glm::max(glm::abs(p.y), glm::abs(p.z)));
    return replacement(patch, front, p, static_cast<float>(kRelativePlaneTolerance) * magnitude);
}

std::optional<CoincidentFaces::Side> CoincidentFaces::replacement(int patch, bool front,
                                                                  const Vec3& p,
                                                                  float tolerance) const {
    const DVec3 x = toDouble(p);
    for (const Cover& c : covers_[static_cast<size_t>(patch)]) {
        if (!(front ? c.front : c.back))
            continue;
        const DVec3 n = toDouble(c.normal);
        const std::array<DVec3, 3> v{toDouble(c.corners[0]), toDouble(c.corners[1]),
                                     toDouble(c.corners[2])};
        if (!(std::abs(glm::dot(n, x - v[0])) <= static_cast<double>(tolerance)))
            continue;
        // Inside: on the inner side of each edge, the corners running counter-clockwise about n.
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k)
            inside = glm::dot(n, glm::cross(v[(k + 1) % 3] - v[k], x - v[k])) >= 0.0;
        if (inside)
            return Side{c.patch, c.sameFacing ? front : !front};
    }
    return std::nullopt;
}

namespace {

// The leaf of `patch` under the point p, by p's barycentric coordinates in the patch's scene
// triangle; -1 if none.
int leafUnder(const Scene& scene, const RadiosityMesh& mesh, int patch, const Vec3& p) {
    const uint32_t m = mesh.sceneMesh(patch), t = mesh.sceneTriangle(patch);
    const Mesh& sceneMesh = scene.meshes()[m];
    const glm::uvec3 v = sceneMesh.triangles[t];
    const Vec3 &p0 = sceneMesh.positions[v.x], &p1 = sceneMesh.positions[v.y],
               &p2 = sceneMesh.positions[v.z];
    const Vec3 n = glm::cross(p1 - p0, p2 - p0);
    const float b1 = glm::dot(glm::cross(p - p0, p2 - p0), n) / glm::dot(n, n);
    const float b2 = glm::dot(glm::cross(p1 - p0, p - p0), n) / glm::dot(n, n);
    return mesh.locate(m, t, Vec3(1.0f - b1 - b2, b1, b2)).element;
}

// The walk of shownLeafSide and leafSideSeenAt: while `hidden` says so and a coincident patch
// hides the side at the point `at(e)`, on to the replacing side's leaf there.
template <typename Hidden, typename At>
std::pair<int, bool> walkToReplacingSide(const Scene& scene, const RadiosityMesh& mesh,
                                         const CoincidentFaces& coincident, int e, bool front,
                                         const Hidden& hidden, const At& at) {
    // A chain of stacked copies ends at the side that wins; kMaxCoincidentHops bounds the walk.
    for (int hop = 0; hop < kMaxCoincidentHops && hidden(e, front); ++hop) {
        const Vec3 p = at(e);
        const std::optional<CoincidentFaces::Side> side =
            coincident.replacementAt(mesh.patch(e), front, p);
        if (!side)
            break;
        const int leaf = leafUnder(scene, mesh, side->patch, p);
        if (leaf < 0)
            break;
        e = leaf;
        front = side->front;
    }
    return {e, front};
}

}  // namespace

std::pair<int, bool> shownLeafSide(const Scene& scene, const RadiosityMesh& mesh,
                                   const CoincidentFaces& coincident, int e, bool front,
                                   const std::function<bool(int element, bool front)>& exposed) {
    return walkToReplacingSide(
        scene, mesh, coincident, e, front,
        [&](int leaf, bool side) { return !exposed(leaf, side); },
        [&](int leaf) { return mesh.centroid(leaf); });
}

std::pair<int, bool> leafSideSeenAt(const Scene& scene, const RadiosityMesh& mesh,
                                    const CoincidentFaces& coincident, int e, bool front,
                                    const Vec3& p) {
    return walkToReplacingSide(
        scene, mesh, coincident, e, front, [](int, bool) { return true; }, [&](int) { return p; });
}

}  // namespace penumbra
