// The density of a heterogeneous medium (smoke, a cloud, uneven haze): a scalar field sampled on
// a regular lattice of nodes that spans an axis-aligned box, trilinear between the nodes and zero
// outside the box. A medium (core/medium.h) multiplies it by its coefficients sigma_a, sigma_s.
//
// Along a ray p(t) = o + t d each factor of the trilinear weights is linear in t, so within one
// lattice cell the density is a cubic polynomial in t. Two-point Gauss-Legendre quadrature is
// exact for cubics (Abramowitz and Stegun 1964, 25.4.29), so the integral of the density along a
// ray (its optical depth, once scaled by sigma_t) is exact cell by cell, up to rounding, and the
// distance at which that integral reaches a given value is found by a safeguarded Newton
// iteration on it. This is regular tracking done exactly (the "regular tracking" of Novák et
// al. 2018, "Monte Carlo Methods for Volumetric Light Transport Simulation"): transmittance
// without noise and free-flight densities that can be evaluated, which keeps the spectral and
// equiangular multiple importance sampling of the medium unbiased.
#pragma once

#include "core/math.h"
#include "core/ray.h"

#include <glm/vec3.hpp>

#include <optional>
#include <vector>

namespace penumbra {

class DensityGrid {
  public:
    // `nodes` values per axis (>= 2 each), x fastest, then y, then z; node (0,0,0) at box.lo and
    // the last node at box.hi. Values must be finite and >= 0 (the loaders check).
    DensityGrid(const Bounds3& box, const glm::ivec3& nodes, std::vector<float> values);

    const Bounds3& box() const { return box_; }
    const glm::ivec3& nodes() const { return nodes_; }
    float maxValue() const { return maxValue_; }
    float node(int x, int y, int z) const { return values_[index(x, y, z)]; }

    // The trilinear density at p; zero outside the box.
    float at(const Vec3& p) const;

    // The integral of the density along the ray from t0 to t1 (ray.d unit, so in metres times
    // density; t0 <= t1, both inside the box's span of the ray).
    float integral(const Ray& ray, float t0, float t1) const;

    // The ray parameter t in [t0, t1] at which integral(ray, t0, t) reaches `target` (> 0);
    // nothing when integral(ray, t0, t1) stays below it.
    std::optional<float> invertIntegral(const Ray& ray, float t0, float t1, float target) const;

  private:
    size_t index(int x, int y, int z) const {
        return (size_t(z) * size_t(nodes_.y) + size_t(y)) * size_t(nodes_.x) + size_t(x);
    }
    // The eight node values of one cell, and the density at a point given in the grid's
    // coordinates (node units), trilinear in that cell.
    struct Cell {
        glm::ivec3 index;
        float corners[8];  // x fastest, then y, then z
        float at(const Vec3& g) const;
    };
    Cell cellAt(const glm::ivec3& index) const;
    // Calls visit(ta, tb, cell) for each piece [ta, tb] of [t0, t1] inside one lattice cell, in
    // order, until visit returns false (a 3-D DDA: Amanatides and Woo 1987); cells whose nodes
    // are all zero are stepped over without a call, and a block of such cells, 32^3 or else 8^3,
    // is crossed in one step (the DDA starts again where the ray leaves it), so that the empty
    // space of a sparse grid (a cloud in a large box) costs a step per block, not per cell.
    template <typename Visit>
    void forEachCell(const Ray& ray, float t0, float t1, Visit&& visit) const;
    // The exact integral over a piece within one cell (the Gauss-Legendre rule of the header).
    float cellIntegral(const Ray& ray, float ta, float tb, const Cell& cell) const;
    Vec3 gridPoint(const Ray& ray, float t) const {
        return (ray.o + t * ray.d - box_.lo) / cellSize_;
    }

    Bounds3 box_;
    glm::ivec3 nodes_;
    Vec3 cellSize_;
    std::vector<float> values_;
    std::vector<bool> emptyCells_;  // per cell, indexed as the nodes: all eight nodes zero
    // Which blocks of `size`^3 cells hold only empty cells (the last block on an axis partial).
    struct EmptyBlocks {
        EmptyBlocks(int size, const glm::ivec3& cells);
        size_t index(const glm::ivec3& cell) const {
            const glm::ivec3 b = cell / size;
            return (size_t(b.z) * size_t(blocks.y) + size_t(b.y)) * size_t(blocks.x) + size_t(b.x);
        }
        bool holds(const glm::ivec3& cell) const { return empty[index(cell)]; }
        int size;
        glm::ivec3 blocks;
        std::vector<bool> empty;
    };
    EmptyBlocks coarseBlocks_{32, nodes_ - 1}, fineBlocks_{8, nodes_ - 1};
    float maxValue_ = 0.0f;
};

}  // namespace penumbra
