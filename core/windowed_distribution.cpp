#include "core/windowed_distribution.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace penumbra {

namespace {

// Where a non-decreasing function, linear between the grid lines k / cells and known there as
// at(k), reaches `target`, within [lower, upper] whose grid cells are first to last: the cell by
// bisection over its grid lines, then the point linear within it. Returns the cell and the point.
template <typename AtGridLine>
std::pair<int, float> invertOnGrid(int first, int last, int cells, float lower, float upper,
                                   AtGridLine at, double target) {
    while (first < last) {
        const int middle = first + (last - first) / 2;
        if (at(middle + 1) > target)
            last = middle;
        else
            first = middle + 1;
    }
    const double atLower = at(first), span = at(first + 1) - atLower;
    const double t = span > 0.0 ? std::clamp((target - atLower) / span, 0.0, 1.0) : 0.0;
    const float point = (float(first) + float(t)) / float(cells);
    return {first, std::clamp(point, lower, upper)};
}

}  // namespace

WindowedDistribution2D::WindowedDistribution2D(std::vector<float> values, int width, int height)
    : width_(width), height_(height), values_(std::move(values)) {
    if (width <= 0 || height <= 0 || values_.size() != size_t(width) * size_t(height))
        throw std::invalid_argument("WindowedDistribution2D: values must be width x height");
    sums_.assign(size_t(width + 1) * size_t(height + 1), 0.0);
    const double cellArea = 1.0 / (double(width) * double(height));
    for (int j = 1; j <= height; ++j) {
        double row = 0.0;
        for (int i = 1; i <= width; ++i) {
            row += double(values_[size_t(j - 1) * width + size_t(i - 1)]) * cellArea;
            sums_[size_t(j) * (width + 1) + size_t(i)] = cornerSum(i, j - 1) + row;
        }
    }
}

double WindowedDistribution2D::integralFromOrigin(float x, float y) const {
    // Bilinear between the four corner sums around (x, y): exact for a piecewise-constant
    // function, the cross term being the cell's own value times the part of it covered.
    const float gx = std::clamp(x, 0.0f, 1.0f) * float(width_);
    const float gy = std::clamp(y, 0.0f, 1.0f) * float(height_);
    const int i = std::min(int(gx), width_ - 1), j = std::min(int(gy), height_ - 1);
    const double fx = double(gx) - i, fy = double(gy) - j;
    return (1.0 - fx) * (1.0 - fy) * cornerSum(i, j) + fx * (1.0 - fy) * cornerSum(i + 1, j) +
           (1.0 - fx) * fy * cornerSum(i, j + 1) + fx * fy * cornerSum(i + 1, j + 1);
}

double WindowedDistribution2D::integral(const Window& w) const {
    const double sum =
        integralFromOrigin(w.upper.x, w.upper.y) - integralFromOrigin(w.lower.x, w.upper.y) -
        integralFromOrigin(w.upper.x, w.lower.y) + integralFromOrigin(w.lower.x, w.lower.y);
    return std::max(sum, 0.0);
}

float WindowedDistribution2D::value(Vec2 point) const {
    const int i = std::clamp(int(point.x * float(width_)), 0, width_ - 1);
    const int j = std::clamp(int(point.y * float(height_)), 0, height_ - 1);
    return values_[size_t(j) * width_ + size_t(i)];
}

std::optional<WindowedDistribution2D::Sample> WindowedDistribution2D::sample(
    Vec2 u, const Window& window) const {
    // The corner sums interpolated in y alone: along a grid column i, at height y.
    struct Height {
        int row;
        double fraction;
    };
    const auto height = [&](float y) {
        const float g = std::clamp(y, 0.0f, 1.0f) * float(height_);
        const int j = std::min(int(g), height_ - 1);
        return Height{j, double(g) - j};
    };
    const auto along = [&](int i, Height h) {
        return (1.0 - h.fraction) * cornerSum(i, h.row) + h.fraction * cornerSum(i, h.row + 1);
    };

    // The marginal in x: F(x), the integral over [0, x] x [lower.y, upper.y], is linear in x
    // within each column; the column where F passes F(lower.x) + u.x of the window's integral is
    // found among the grid's column boundaries, where F needs no interpolation in x.
    const Height bottom = height(window.lower.y), top = height(window.upper.y);
    const auto marginalAt = [&](int i) { return along(i, top) - along(i, bottom); };
    const auto marginal = [&](float x) {
        const float g = std::clamp(x, 0.0f, 1.0f) * float(width_);
        const int i = std::min(int(g), width_ - 1);
        const double f = double(g) - i;
        return (1.0 - f) * marginalAt(i) + f * marginalAt(i + 1);
    };
    const double start = marginal(window.lower.x);
    const double total = marginal(window.upper.x) - start;
    if (!(total > 0.0))
        return std::nullopt;
    const double targetX = start + double(u.x) * total;
    const int firstColumn = std::clamp(int(window.lower.x * float(width_)), 0, width_ - 1);
    const int lastColumn =
        std::clamp(int(std::ceil(window.upper.x * float(width_))) - 1, firstColumn, width_ - 1);
    const auto [column, x] = invertOnGrid(firstColumn, lastColumn, width_, window.lower.x,
                                          window.upper.x, marginalAt, targetX);

    // The conditional in y within that column: G(y), the integral over the column's width and
    // [0, y], likewise linear within each row, at row boundaries a difference of two corner sums.
    const auto conditionalAt = [&](int j) {
        return cornerSum(column + 1, j) - cornerSum(column, j);
    };
    const auto conditional = [&](Height h) { return along(column + 1, h) - along(column, h); };
    const double stripStart = conditional(bottom);
    const double stripTotal = conditional(top) - stripStart;
    if (!(stripTotal > 0.0))
        return std::nullopt;
    const double targetY = stripStart + double(u.y) * stripTotal;
    const int firstRow = bottom.row;
    const int lastRow =
        std::clamp(int(std::ceil(window.upper.y * float(height_))) - 1, firstRow, height_ - 1);
    const auto [row, y] = invertOnGrid(firstRow, lastRow, height_, window.lower.y, window.upper.y,
                                       conditionalAt, targetY);

    const float density = values_[size_t(row) * width_ + size_t(column)];
    if (!(density > 0.0f))
        return std::nullopt;
    return Sample{Vec2(x, y), float(double(density) / total)};
}

}  // namespace penumbra
