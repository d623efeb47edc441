// Form factors between planar polygons, the kernel of the hierarchical radiosity pass
// (Hanrahan, Salzman and Aupperle 1991, "A Rapid Hierarchical Radiosity Algorithm"). Independent
// of meshing and of ray tracing: every value here is unoccluded, and the caller multiplies it by
// the visible fraction in [0, 1] it estimates itself.
//
// Conventions shared by the functions below:
//  - A form factor is dimensionless and Lambertian: F(i -> j) is the fraction of the power leaving
//    i diffusely that arrives at j, F = 1/A_i int_i int_j cos(theta_i) cos(theta_j) / (pi r^2).
//  - Polygons are planar and convex, given by their vertices in order (triangles and quads in
//    practice). Where a polygon is one-sided, its front is the side its normal points to, with
//    the normal given by the right-hand rule: the vertices run counter-clockwise seen from the
//    front.
//  - Computation is in double precision whatever the precision of Vec3.
#pragma once

#include "core/math.h"

#include <array>
#include <span>

namespace penumbra {

// Signed solid angle (sr) a triangle subtends at o (Van Oosterom and Strackee 1983, "The Solid
// Angle of a Plane Triangle", IEEE Trans. Biomed. Eng. 30(2)): positive when o lies in front of
// it (the corners run counter-clockwise seen from o), in (-2 pi, 2 pi). In double precision: a
// metre-sized distance to a kilometre-sized triangle must not cancel. Over the triangles of a
// closed, consistently wound surface the sum is 4 pi times the winding number of o.
double triangleSolidAngle(const Vec3& o, const std::array<Vec3, 3>& corners);

// Form factor from a differential area at p with unit normal n to a planar convex polygon,
// F(dA -> P) = 1/pi int_P cos(theta_p) cos(theta_y) / r^2 dA_y, exact by Lambert's contour
// integral. Only the part of the polygon above the tangent plane of p counts (cos theta_p > 0);
// vertices within 1e-6 radians of that plane, seen from p, count as on it, so that coplanar
// polygons given in float see nothing of each other. The polygon is two-sided here: the result
// does not depend on its winding or on which side of it p lies, so a caller with a one-sided
// emitter tests the side itself. Returns a value in [0, 1]; 0 for a degenerate polygon (fewer
// than three distinct vertices, collinear), a polygon on or below the tangent plane, or a zero
// normal. The integrand stays bounded as p approaches the polygon's edges and vertices, and
// points exactly on them (a set of measure zero for areaToAreaFormFactor) give a finite value.
double pointToPolygonFormFactor(const Vec3& p, const Vec3& n, std::span<const Vec3> polygon);

// Form factor F(from -> to) between two planar convex polygons, both one-sided: only pairs of
// points in front of each other count (cos theta_from > 0 and cos theta_to > 0), which makes the
// kernel symmetric, so A_from F(from -> to) = A_to F(to -> from) up to quadrature error. For a
// two-sided `to`, add the form factor to `to` with its vertices reversed. Coplanar polygons
// (within 1e-6 radians) give 0.
//
// The outer integral, over the part of `from` in front of `to`, is a product Gauss-Legendre rule
// with `order` points per direction: on a quad through its bilinear map, on a triangle through
// the collapsed (Duffy) map of the square, order^2 points either way (a clipped quad with five
// vertices is a fan of three triangles). The inner integral is exact (pointToPolygonFormFactor),
// so the integrand stays bounded even for polygons sharing an edge, where it is only Lipschitz;
// no subdivision is needed there. Measured accuracy against Howell's catalogue: order 8 is within
// 0.5 % for opposed rectangles down to a separation of 1/20 of their side and for perpendicular
// rectangles sharing an edge as long as the emitter is at most 5 times deeper than the receiver
// is high; thinner receivers need more (order 16 at 50 times), see
// tests/radiosity/form_factor_test.cpp. order >= 1, else std::invalid_argument.
double areaToAreaFormFactor(std::span<const Vec3> from, std::span<const Vec3> to, int order);

// Cheap unoccluded estimate of F(dA_p -> A_q) for the refinement oracle: the element A_q (centre q,
// unit normal nq, area areaQ) is replaced by a disc of the same area facing p, seen from the
// differential area at p (unit normal np):
//     F ~ areaQ cos(theta_p) cos(theta_q) / (pi r^2 + areaQ),
// the disc approximation of the form factor from a sample point to a source in Wallace, Elmquist
// and Haines 1989, "A Ray Tracing Algorithm for Progressive Radiosity". One-sided at both ends:
// 0 when either cosine is <= 0.
// Domain of validity: exact when p is on the axis of an actual disc parallel to dA_p (then it is
// a^2 / (a^2 + h^2)); in the far field, r^2 >> areaQ, it tends to the point-to-point kernel
// areaQ cos cos / (pi r^2) with a relative error O(areaQ / r^2) for compact (not elongated)
// elements (measured for a tilted square seen off-axis: 2.6 % at r = 4 sqrt(areaQ), 0.16 % at
// r = 16 sqrt(areaQ)). In the near field it ignores the element's shape and the variation of the
// cosines across it, so it is only a bounded (<= 1) order-of-magnitude estimate there; never use it
// for transport between adjacent or close elements.
double diskApproximationFormFactor(const Vec3& p, const Vec3& np, const Vec3& q, const Vec3& nq,
                                   double areaQ);

}  // namespace penumbra
