// Candidates come from a hash grid of the triangles' bounding boxes; each pair is tested exactly:
// the part of the other triangle that lies in this one's plane (a vertex within the tolerance,
// or an edge crossing it), clipped to this triangle.
#include "radiosity/contact_lines.h"

#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// Distance from a plane under which a point counts as on it, relative to the scene's diagonal:
// modelling tools write a block standing on a floor to a few float ulps.
constexpr double kPlaneTolerance = 1e-5;
// Triangles this close to parallel are coplanar (coincident_faces.h's business), not in contact.
constexpr double kParallelCosine = 0.9999;
// The grid's cells: not smaller than this fraction of the scene's diagonal.
constexpr double kMinCellFraction = 1.0 / 256.0;
constexpr double kMaxCellsAcross = 64.0;
// Segments kept per triangle, the longest: the cut's cost grows with their square.
constexpr size_t kMaxSegments = 256;

struct HeldTriangle {
    uint32_t mesh = 0, triangle = 0;
    std::array<glm::dvec3, 3> p{};
    glm::dvec3 normal{0.0};
    double area = 0.0;
    bool twoSided = false;
    glm::dvec3 lo{0.0}, hi{0.0};
};

std::vector<HeldTriangle> heldTriangles(const Scene& scene) {
    std::vector<HeldTriangle> held;
    const std::span<const Mesh> meshes = scene.meshes();
    for (uint32_t m = 0; m < meshes.size(); ++m) {
        const Material& material = scene.materials()[meshes[m].material];
        if (!holdsMaterial(material))
            continue;
        for (uint32_t t = 0; t < meshes[m].triangles.size(); ++t) {
            HeldTriangle h;
            h.mesh = m;
            h.triangle = t;
            for (int c = 0; c < 3; ++c)
                h.p[size_t(c)] = glm::dvec3(meshes[m].positions[meshes[m].triangles[t][c]]);
            const glm::dvec3 cross = glm::cross(h.p[1] - h.p[0], h.p[2] - h.p[0]);
            h.area = 0.5 * glm::length(cross);
            if (!(h.area > 0.0) || !std::isfinite(h.area))
                continue;
            h.normal = cross / (2.0 * h.area);
            h.twoSided = material.doubleSided;
            h.lo = glm::min(h.p[0], glm::min(h.p[1], h.p[2]));
            h.hi = glm::max(h.p[0], glm::max(h.p[1], h.p[2]));
            held.push_back(h);
        }
    }
    return held;
}

// Barycentric coordinates of a point of the triangle's plane.
glm::dvec3 barycentric(const HeldTriangle& t, const glm::dvec3& x) {
    const glm::dvec3 e1 = t.p[1] - t.p[0], e2 = t.p[2] - t.p[0], d = x - t.p[0];
    const double twice = 2.0 * t.area;
    const double b1 = glm::dot(glm::cross(d, e2), t.normal) / twice;
    const double b2 = glm::dot(glm::cross(e1, d), t.normal) / twice;
    return {1.0 - b1 - b2, b1, b2};
}

// The segment in which `other` meets the plane of `t` within `tolerance`, clipped to `t`;
// false when they do not meet along a segment inside `t`, off its edges.
bool contactSegment(const HeldTriangle& t, const HeldTriangle& other, double tolerance,
                    double minLength, TriangleSegment& segment) {
    if (std::abs(glm::dot(t.normal, other.normal)) > kParallelCosine)
        return false;
    std::array<double, 3> d;
    for (int i = 0; i < 3; ++i)
        d[size_t(i)] = glm::dot(t.normal, other.p[size_t(i)] - t.p[0]);
    const double highest = std::max({d[0], d[1], d[2]});
    const double lowest = std::min({d[0], d[1], d[2]});
    // Not touching, or wholly behind a one-sided surface (which cannot see it).
    if (lowest > tolerance || highest < -tolerance || (!t.twoSided && highest <= tolerance))
        return false;
    std::vector<glm::dvec3> points;
    for (int i = 0; i < 3; ++i) {
        const size_t a = size_t(i), b = size_t(i + 1) % 3;
        if (std::abs(d[a]) <= tolerance)
            points.push_back(other.p[a] - d[a] * t.normal);
        if ((d[a] > tolerance && d[b] < -tolerance) || (d[a] < -tolerance && d[b] > tolerance))
            points.push_back(other.p[a] + d[a] / (d[a] - d[b]) * (other.p[b] - other.p[a]));
    }
    if (points.size() < 2)
        return false;
    glm::dvec3 from = points[0], to = points[1];
    for (size_t i = 0; i < points.size(); ++i) {
        for (size_t j = i + 1; j < points.size(); ++j) {
            if (glm::distance(points[i], points[j]) > glm::distance(from, to)) {
                from = points[i];
                to = points[j];
            }
        }
    }
    // Clip to the triangle: each barycentric coordinate, linear along the segment, kept >= 0.
    // An end within the tolerance of an edge (as a distance: b_k times the height over edge k)
    // is moved along the segment onto it, so that it stays on the contact line.
    const glm::dvec3 ba = barycentric(t, from), bb = barycentric(t, to);
    std::array<double, 3> height;
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3 edge = t.p[size_t(k + 2) % 3] - t.p[size_t(k + 1) % 3];
        height[size_t(k)] = 2.0 * t.area / glm::length(edge);
    }
    double t0 = 0.0, t1 = 1.0;
    for (int k = 0; k < 3; ++k) {
        const double slope = bb[k] - ba[k];
        const double slack = tolerance / height[size_t(k)];
        if (std::abs(slope) <= 1e-12) {
            if (ba[k] < -slack)
                return false;
            continue;
        }
        const double onEdge = -ba[k] / slope;  // where b_k = 0
        const double reach = slack / std::abs(slope);
        if (slope > 0.0)
            t0 = std::abs(t0 - onEdge) <= reach ? onEdge : std::max(t0, onEdge);
        else
            t1 = std::abs(t1 - onEdge) <= reach ? onEdge : std::min(t1, onEdge);
    }
    if (!(t1 > t0) || (t1 - t0) * glm::distance(from, to) < minLength)
        return false;
    std::array<glm::dvec3, 2> ends = {ba + t0 * (bb - ba), ba + t1 * (bb - ba)};
    // On an edge of the triangle: its neighbour's, already an edge of the mesh.
    for (int k = 0; k < 3; ++k) {
        if (std::abs(ends[0][k]) * height[size_t(k)] <= tolerance &&
            std::abs(ends[1][k]) * height[size_t(k)] <= tolerance)
            return false;
    }
    for (size_t e = 0; e < 2; ++e) {
        glm::dvec3& b = ends[e];
        for (int k = 0; k < 3; ++k) {
            if (b[k] * height[size_t(k)] <= tolerance)
                b[k] = 0.0;
        }
        b /= b.x + b.y + b.z;
        segment[e] = Vec3(b);
    }
    return true;
}

// A hash grid of boxes: the ids of the triangles whose box overlaps each cell.
class BoxGrid {
  public:
    explicit BoxGrid(double cell) : cell_(cell) {}
    template <typename Visit>
    void forCells(const glm::dvec3& lo, const glm::dvec3& hi, const Visit& visit) const {
        const glm::ivec3 a = glm::ivec3(glm::floor(lo / cell_));
        const glm::ivec3 b = glm::ivec3(glm::floor(hi / cell_));
        for (int z = a.z; z <= b.z; ++z)
            for (int y = a.y; y <= b.y; ++y)
                for (int x = a.x; x <= b.x; ++x)
                    visit(key(x, y, z));
    }
    void insert(uint32_t id, const glm::dvec3& lo, const glm::dvec3& hi) {
        forCells(lo, hi, [&](uint64_t k) { cells_[k].push_back(id); });
    }
    const std::vector<uint32_t>* at(uint64_t k) const {
        const auto it = cells_.find(k);
        return it == cells_.end() ? nullptr : &it->second;
    }

  private:
    static uint64_t key(int x, int y, int z) {
        const auto bits = [](int v) { return uint64_t(uint32_t(v) & 0x1fffffu); };
        return (bits(x) << 42) | (bits(y) << 21) | bits(z);
    }
    double cell_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace

ContactLines::ContactLines(const Scene& scene, float minTriangleArea, float minSegmentLength) {
    const std::vector<HeldTriangle> held = heldTriangles(scene);
    if (held.empty())
        return;
    const double diagonal = glm::length(glm::dvec3(scene.bounds().diagonal()));
    const double tolerance = kPlaneTolerance * diagonal;
    // Cells about a triangle wide, but no box across more than kMaxCellsAcross of them.
    double meanExtent = 0.0, largestExtent = 0.0;
    for (const HeldTriangle& h : held) {
        const glm::dvec3 extent = h.hi - h.lo;
        meanExtent += glm::length(extent);
        largestExtent = std::max({largestExtent, extent.x, extent.y, extent.z});
    }
    meanExtent /= double(held.size());
    BoxGrid grid(
        std::max({meanExtent, kMinCellFraction * diagonal, largestExtent / kMaxCellsAcross}));
    const glm::dvec3 pad(tolerance);
    for (uint32_t i = 0; i < held.size(); ++i)
        grid.insert(i, held[i].lo - pad, held[i].hi + pad);

    std::vector<uint32_t> seen(held.size(), UINT32_MAX);
    for (uint32_t i = 0; i < held.size(); ++i) {
        const HeldTriangle& t = held[i];
        if (t.area < double(minTriangleArea))
            continue;
        std::vector<TriangleSegment> found;
        grid.forCells(t.lo - pad, t.hi + pad, [&](uint64_t cell) {
            const std::vector<uint32_t>* ids = grid.at(cell);
            if (!ids)
                return;
            for (const uint32_t j : *ids) {
                if (j == i || seen[j] == i)
                    continue;
                seen[j] = i;
                TriangleSegment s;
                if (contactSegment(t, held[j], tolerance, double(minSegmentLength), s))
                    found.push_back(s);
            }
        });
        if (found.size() > kMaxSegments) {  // the longest ones
            const auto length = [&](const TriangleSegment& s) {
                return glm::length(t.p[0] * double(s[0].x - s[1].x) +
                                   t.p[1] * double(s[0].y - s[1].y) +
                                   t.p[2] * double(s[0].z - s[1].z));
            };
            std::nth_element(found.begin(), found.begin() + kMaxSegments, found.end(),
                             [&](const auto& a, const auto& b) { return length(a) > length(b); });
            found.resize(kMaxSegments);
        }
        if (!found.empty())
            segments_[key(t.mesh, t.triangle)] = std::move(found);
    }
}

std::span<const TriangleSegment> ContactLines::on(uint32_t mesh, uint32_t triangle) const {
    const auto it = segments_.find(key(mesh, triangle));
    if (it == segments_.end())
        return {};
    return it->second;
}

}  // namespace penumbra
