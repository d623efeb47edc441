// Candidates come from a hash grid of the triangles' bounding boxes; each pair is tested exactly:
// the part of the other triangle that lies in this one's plane (a vertex within the tolerance,
// or an edge crossing it), clipped to this triangle.
#include "radiosity/contact_lines.h"

#include "core/scene.h"
#include "radiosity/held_triangles.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// Triangles this close to parallel are coplanar (coincident_faces.h's business), not in contact.
constexpr double kParallelCosine = 0.9999;

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
    glm::dvec3 from, to;
    return planeCrossing(other.p, t.normal, t.p[0], tolerance, from, to) &&
           clipToTriangle(t, from, to, tolerance, minLength, segment);
}

}  // namespace

ContactLines::ContactLines(const Scene& scene, float minTriangleArea, float minSegmentLength) {
    const std::vector<HeldTriangle> held = heldTriangles(scene);
    if (held.empty())
        return;
    const double diagonal = glm::length(glm::dvec3(scene.bounds().diagonal()));
    const double tolerance = kOnPlaneFraction * diagonal;
    const glm::dvec3 pad(tolerance);
    const BoxGrid grid(boxesOf(held), diagonal, tolerance);
    for (uint32_t i = 0; i < held.size(); ++i) {
        const HeldTriangle& t = held[i];
        if (t.area < double(minTriangleArea))
            continue;
        std::vector<TriangleSegment> found;
        grid.forNear(t.lo - pad, t.hi + pad, [&](uint32_t j) {
            TriangleSegment s;
            if (j != i && contactSegment(t, held[j], tolerance, double(minSegmentLength), s))
                found.push_back(s);
        });
        keepLongest(t, found, kMaxSegmentsPerTriangle);
        set(t, std::move(found));
    }
}

}  // namespace penumbra
