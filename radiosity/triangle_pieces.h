// A scene triangle cut into pieces along segments inside it, so that no piece straddles a
// segment: the first step of discontinuity meshing (Heckbert 1992, "Discontinuity Meshing for
// Radiosity"; Lischinski, Tampieri and Greenberg 1992), which puts element edges on the lines
// where the radiance is discontinuous instead of ever smaller elements beside them. The pieces
// are a constrained Delaunay triangulation of the triangle and the segments, refined
// (Ruppert 1995, "A Delaunay Refinement Algorithm for Quality 2-Dimensional Mesh Generation")
// until no angle is below about 20 degrees where it can be: slivers make poor radiosity
// elements.
//
// Only triangle_pieces.cpp sees CGAL (CONTRIBUTING.md, "Layering").
#pragma once

#include "core/math.h"

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

// A segment inside a triangle: its end points' barycentric coordinates in the triangle.
using TriangleSegment = std::array<Vec3, 2>;

struct TrianglePieces {
    // Barycentric coordinates of the pieces' corners in the triangle; points 0, 1, 2 are the
    // triangle's own corners, exactly (1, 0, 0), (0, 1, 0), (0, 0, 1).
    std::vector<Vec3> points;
    // Indices into points, counter-clockwise seen from the triangle's front (the side its own
    // corners' counter-clockwise winding faces). A single piece when nothing cut the triangle.
    std::vector<std::array<uint32_t, 3>> pieces;
    // Per piece, bit k set when its edge from corner k to corner k + 1 lies on one of the
    // segments (inside the triangle, not on its own edges): a line where the light may step.
    std::vector<uint8_t> cutEdges;
};

// Cuts the triangle with world-space corners `corners` along `segments` (clipped to it by the
// caller). Features finer than `resolution` (metres; at least a millionth of the triangle's
// least height, at most a quarter of it) are joined: end points closer than it are merged, and
// an end point closer than it to another segment or to an edge is put on it. Whatever the
// segments (crossing, overlapping, a rounding error apart), the pieces cover the triangle once
// and none has a segment through its inside: the lines are snap rounded to a grid a millionth of
// the least height fine before they are triangulated. The refinement stops after a bounded
// number of steps, so that a segment meeting an edge at a tiny angle cannot make it run away; a
// piece may then keep a small angle.
TrianglePieces cutTriangle(const std::array<Vec3, 3>& corners,
                           std::span<const TriangleSegment> segments, float resolution);

}  // namespace penumbra
