// A piecewise-constant function on the unit square that can be sampled within any axis-aligned
// window of it, in proportion to the function, at a cost that does not grow with the window's
// size: the window's integral comes from a summed-area table (Crow 1984, "Summed-area tables for
// texture mapping"), whose bilinear interpolation between the grid's corners is the exact
// integral of the piecewise-constant function over a box whose corners lie anywhere; the
// marginal in x and then the conditional in y are inverted by searching those integrals
// (the method of pbrt-v4's WindowedPiecewiseConstant2D, src/pbrt/util/sampling.h). The portals'
// rectified environment (core/portals.h) samples the part of the sky seen through a window this
// way.
#pragma once

#include "core/math.h"

#include <optional>
#include <vector>

namespace penumbra {

// An axis-aligned box of the unit square, lower corner first.
struct Window {
    Vec2 lower{0.0f};
    Vec2 upper{1.0f};
};

class WindowedDistribution2D {
  public:
    WindowedDistribution2D() = default;
    // `values`: width x height cells, row-major, finite and >= 0; cell (x, y) covers
    // [x / width, (x + 1) / width] x [y / height, (y + 1) / height].
    WindowedDistribution2D(std::vector<float> values, int width, int height);

    // The integral of the function over `window`.
    double integral(const Window& window) const;

    struct Sample {
        Vec2 point;
        float pdf = 0.0f;  // density over the unit square's area, within the window
    };
    // A point of `window` drawn in proportion to the function; nothing when the window holds
    // none of it.
    std::optional<Sample> sample(Vec2 u, const Window& window) const;
    // The function's value at `point` (its cell's), whose ratio to integral(window) is the
    // density of sample() there.
    float value(Vec2 point) const;

  private:
    int width_ = 0, height_ = 0;
    std::vector<float> values_;
    // (width + 1) x (height + 1) corner sums: entry (i, j) is the integral over
    // [0, i / width] x [0, j / height].
    std::vector<double> sums_;

    double cornerSum(int i, int j) const { return sums_[size_t(j) * (width_ + 1) + size_t(i)]; }
    // The integral over [0, x] x [0, y] for any x, y in [0, 1].
    double integralFromOrigin(float x, float y) const;
};

}  // namespace penumbra
