// Portals: the openings (windows, skylights) through which an interior sees its environment, so
// that the environment light samples the directions that can reach a point inside instead of the
// whole sky, most of which the walls hide. This is the rectified parametrisation of Bitterli,
// Novák and Jarosz 2015, "Portal-Masked Environment Map Sampling": each portal gets, for each side
// of its plane, an image of the environment seen through it, in coordinates where the directions
// from any point through the portal form an axis-aligned rectangle. Sampling that rectangle in
// proportion to the image's luminance times the Jacobian draws directions through the portal in
// proportion to the sky's luminance there (a bright region of the sky seen through a window gets
// the samples it deserves), in constant time by a summed-area table
// (core/windowed_distribution.h). The environment light mixes it with its own sampling, so a
// portal that misses an opening costs noise, never correctness.
//
// The rectified coordinates. A portal has the unit normal n = normalize(edge1 x edge2) and the
// unit edge directions e1, e2 (not necessarily perpendicular); on side sigma (+1 or -1: the
// directions with sigma (d . n) > 0) a direction d is the ray through the point
// X e1 + Y e2 + sigma n of the plane one unit ahead, and (X, Y) maps to the unit square by
// s = X / (1 + |X|), u = (s + 1) / 2 (likewise Y to v), so that the whole half-space of
// directions fits in it. From a point at height h before the plane, with coordinates (a, b) in
// units of the edges, the portal is X in [-a, 1 - a] |edge1| / h, Y in [-b, 1 - b] |edge2| / h:
// a rectangle. The solid angle per unit (u, v) is
//     d omega / du dv = 4 sin(phi) / (|w|³ (1 - |s|)² (1 - |t|)²),  w = X e1 + Y e2 + sigma n,
// with phi the angle between the edges and t the s of Y (the area element sin(phi) dX dY of the
// plane, seen at distance |w| at the cosine 1 / |w|, times dX / ds = 1 / (1 - |s|)²).
#pragma once

#include "core/math.h"
#include "core/windowed_distribution.h"

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

// A parallelogram: the corner and its two edges (the fourth corner is corner + edge1 + edge2).
struct Portal {
    Vec3 corner{0.0f};
    Vec3 edge1{0.0f};
    Vec3 edge2{0.0f};

    float area() const { return glm::length(glm::cross(edge1, edge2)); }
};

// The three corners of a portal written "X0,Y0,Z0,X1,Y1,Z1,X2,Y2,Z2" (a corner and its two
// neighbours, as --portal and a pass script's `portals` take them), in double for rebasing.
// Throws std::invalid_argument quoting the text unless it is nine finite numbers whose corners
// span an area.
std::array<glm::dvec3, 3> parsePortalCorners(const std::string& text);

class PortalSet {
  public:
    PortalSet() = default;
    // `luminance`: the environment's luminance (cd/m²) arriving along a unit world direction,
    // read at resolution x resolution points of each side of each portal (with supersampling x
    // supersampling points per cell, averaged, so that a small bright spot is not missed between
    // them). Throws std::invalid_argument for a portal of no area.
    PortalSet(std::vector<Portal> portals, const std::function<float(const Vec3&)>& luminance,
              int resolution = kResolution, int supersampling = 1);

    // Cells across each portal side's image: the rational map packs the half-space so that a cell
    // at the centre spans 2 / resolution in X, 1.8 degrees, and less towards the rim. Finer
    // images sampled no better per sample on the daylit room (128: the same error x samples) and
    // cost more per sample, their summed-area tables competing with the map for the cache.
    static constexpr int kResolution = 64;

    bool empty() const { return rectified_.empty(); }

    // The luminance of the environment all portals show `from`, as their coarse images
    // (kCoarseResolution cells across, each the mean of the image's cells in it) see it: the sum
    // over the portals of the integral of their coarse image over the window of the side `from`
    // looks through (cd/m² sr, the luminance integrated over the solid angle of the portal, walls
    // not counted). The coarse images are small enough to stay in the cache, so that choosing a
    // portal costs little however many there are; within the chosen one the full image decides.
    // Zero when they show `from` nothing; sample() and pdf() take it so that it is computed once
    // per point.
    double luminanceShown(const Vec3& from) const;
    // A unit direction from `from` through one of the portals, the portal chosen in proportion to
    // its share of luminanceShown(), the direction within it in proportion to its image; nothing
    // when `shown` (luminanceShown(from)) is zero or, rarely, where the density is zero.
    std::optional<Vec3> sample(const Vec3& from, Vec2 u, double shown) const;
    // The solid-angle density with which sample() draws unit direction `towards` from `from`:
    // the sum over the portals the ray crosses of their share of `shown` times their image's
    // density there per unit solid angle.
    float pdf(const Vec3& from, const Vec3& towards, double shown) const;

    static constexpr int kCoarseResolution = 16;

  private:
    // A portal's frame and its two images and coarse images, side +1 first.
    struct Rectified {
        Portal portal;
        Vec3 normal{0.0f}, unit1{0.0f}, unit2{0.0f};
        float length1 = 0.0f, length2 = 0.0f, sinAngle = 0.0f;
        // The dual basis of the edges: a point's coordinates in units of them are its offset
        // from the corner dotted with these.
        Vec3 dual1{0.0f}, dual2{0.0f};
        WindowedDistribution2D sides[2];
        WindowedDistribution2D coarse[2];
    };
    std::vector<Rectified> rectified_;

    // The side of `r` the point `from` looks through, and its window; nothing in the plane.
    static std::optional<std::pair<int, Window>> window(const Rectified& r, const Vec3& from);
};

}  // namespace penumbra
