// Portals: the openings (windows, skylights) through which an interior sees its environment, so
// that the environment light samples the directions that can reach a point inside instead of the
// whole sky, most of which the walls hide (Bitterli, Novák and Jarosz 2015, "Portal-Masked
// Environment Map Sampling"). This is the simple strategy that paper starts from: a point uniform
// on a portal's area and the direction towards it, density r² / (A |cos theta|) in solid angle;
// not its rectified parametrisation, which also follows the map's brightness through the portal.
// The environment light mixes it with its own sampling, so a portal that misses an opening costs
// noise, never correctness.
#pragma once

#include "core/math.h"

#include <array>
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
    // Throws std::invalid_argument for a portal of no area.
    explicit PortalSet(std::vector<Portal> portals);

    bool empty() const { return portals_.empty(); }
    const std::vector<Portal>& portals() const { return portals_; }

    // A unit direction from `from` towards a point uniform on a portal chosen in proportion to
    // its area; nothing when `from` lies in the portal's plane.
    std::optional<Vec3> sample(const Vec3& from, Vec2 u) const;
    // The solid-angle density with which sample() draws unit direction `towards` from `from`: the
    // sum over the portals the ray crosses of their choice probability times t² / (A |cos|).
    float pdf(const Vec3& from, const Vec3& towards) const;

  private:
    std::vector<Portal> portals_;
    std::vector<float> areaCdf_;  // portals_.size() + 1 entries
    float totalArea_ = 0.0f;
};

}  // namespace penumbra
