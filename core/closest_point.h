// The point of a triangle closest to a given point, for distance bounds that a bounding sphere
// makes too loose (a sliver three metres long and a millimetre wide "touches" everything within
// a metre and a half of its centroid).
#pragma once

#include "core/math.h"

namespace penumbra {

// The point of triangle (a, b, c) nearest to p, by the Voronoi regions of its vertices, edges
// and face (Ericson 2005, "Real-Time Collision Detection", section 5.1.5). For a triangle of
// non-zero area; one of zero area gives one of its points, not necessarily the nearest.
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace penumbra
