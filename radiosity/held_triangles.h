// What the finders of discontinuity lines share (contact_lines.h, shadow_lines.h): the scene
// triangles the radiosity mesh holds, in double precision; a segment of a triangle's plane
// clipped to the triangle as a cut (triangle_pieces.h) takes it; their boxes for a grid of the
// candidates near a region (box_grid.h); the longest segments kept when a triangle has too many;
// and the segments found, by triangle, as the mesh reads them.
#pragma once

#include "core/math.h"
#include "radiosity/box_grid.h"
#include "radiosity/triangle_pieces.h"

#include <array>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

namespace penumbra {

class Scene;

// Distance under which a point counts as on a plane, and two corners as one, relative to the
// scene's diagonal: modelling tools write a block standing on a floor to a few float ulps.
inline constexpr double kOnPlaneFraction = 1e-5;
// Segments a finder keeps per triangle, the longest: the cut's cost grows with their square.
inline constexpr size_t kMaxSegmentsPerTriangle = 256;

// A scene triangle's key in a hash map.
inline uint64_t triangleKey(uint32_t mesh, uint32_t triangle) {
    return (uint64_t(mesh) << 32) | triangle;
}

struct HeldTriangle {
    uint32_t mesh = 0, triangle = 0;
    std::array<glm::dvec3, 3> p{};
    glm::dvec3 normal{0.0};  // unit, the side the corners' counter-clockwise winding faces
    double area = 0.0;
    bool twoSided = false;
    glm::dvec3 lo{0.0}, hi{0.0};  // bounding box
};

// The triangles of positive area of every material the radiosity mesh holds (holdsMaterial).
std::vector<HeldTriangle> heldTriangles(const Scene& scene);

// Barycentric coordinates of a point of the triangle's plane.
glm::dvec3 barycentric(const HeldTriangle& t, const glm::dvec3& x);

// Where the triangle with corners p meets the plane through `origin` with unit `normal`: its
// corners within `tolerance` of the plane (projected on it) and its edges' crossings, the
// farthest two of them as [from, to]; false when they are fewer than two.
bool planeCrossing(const std::array<glm::dvec3, 3>& p, const glm::dvec3& normal,
                   const glm::dvec3& origin, double tolerance, glm::dvec3& from, glm::dvec3& to);

// The part of segment [from, to] (points of t's plane) inside t, as the barycentric coordinates
// of its ends: false when that part is shorter than minLength or lies on one of t's own edges
// (its neighbour's, already an edge of the mesh). An end within `tolerance` (metres) of an edge
// is moved along the segment onto it, so that a line that ends on the edge stays on it.
bool clipToTriangle(const HeldTriangle& t, const glm::dvec3& from, const glm::dvec3& to,
                    double tolerance, double minLength, TriangleSegment& segment);

// Keeps the `count` longest of `segments` (all when there are no more).
void keepLongest(const HeldTriangle& t, std::vector<TriangleSegment>& segments, size_t count);

// Segments found on the scene's triangles, by triangle.
class SegmentsByTriangle {
  public:
    // The segments on triangle `triangle` of scene mesh `mesh`, in its barycentric coordinates;
    // empty if none.
    std::span<const TriangleSegment> on(uint32_t mesh, uint32_t triangle) const;
    size_t triangleCount() const { return segments_.size(); }  // triangles with a segment

  protected:
    // Sets the segments of t, unless there are none.
    void set(const HeldTriangle& t, std::vector<TriangleSegment> segments);

  private:
    std::unordered_map<uint64_t, std::vector<TriangleSegment>> segments_;
};

// The triangles' boxes, for a grid of them (box_grid.h).
std::vector<GridBox> boxesOf(const std::vector<HeldTriangle>& triangles);

}  // namespace penumbra
