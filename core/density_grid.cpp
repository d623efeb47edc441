#include "core/density_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace penumbra {

DensityGrid::DensityGrid(const Bounds3& box, const glm::ivec3& nodes, std::vector<float> values)
    : box_(box),
      nodes_(nodes),
      cellSize_(box.diagonal() / Vec3(nodes - 1)),
      values_(std::move(values)),
      emptyCells_(values_.size(), false) {
    for (float v : values_)
        maxValue_ = std::max(maxValue_, v);
    for (int z = 0; z + 1 < nodes_.z; ++z)
        for (int y = 0; y + 1 < nodes_.y; ++y)
            for (int x = 0; x + 1 < nodes_.x; ++x) {
                const Cell c = cellAt({x, y, z});
                const bool empty = std::all_of(std::begin(c.corners), std::end(c.corners),
                                               [](float v) { return v == 0.0f; });
                emptyCells_[index(x, y, z)] = empty;
                if (!empty) {
                    for (EmptyBlocks* blocks : {&coarseBlocks_, &fineBlocks_})
                        blocks->empty[blocks->index({x, y, z})] = false;
                }
            }
}

DensityGrid::EmptyBlocks::EmptyBlocks(int size, const glm::ivec3& cells)
    : size(size),
      blocks((cells - 1) / size + 1),
      empty(size_t(blocks.x) * size_t(blocks.y) * size_t(blocks.z), true) {}

DensityGrid::Cell DensityGrid::cellAt(const glm::ivec3& index) const {
    Cell c{index, {}};
    for (int k = 0; k < 8; ++k)
        c.corners[k] = node(index.x + (k & 1), index.y + ((k >> 1) & 1), index.z + (k >> 2));
    return c;
}

float DensityGrid::Cell::at(const Vec3& g) const {
    // p's place in the cell, clamped: a point rounding put a hair outside it keeps the
    // cell's values.
    const Vec3 f = glm::clamp(g - Vec3(index), Vec3(0.0f), Vec3(1.0f));
    const auto lerp = [](float a, float b, float s) { return a + s * (b - a); };
    const float y0 =
        lerp(lerp(corners[0], corners[1], f.x), lerp(corners[2], corners[3], f.x), f.y);
    const float y1 =
        lerp(lerp(corners[4], corners[5], f.x), lerp(corners[6], corners[7], f.x), f.y);
    return lerp(y0, y1, f.z);
}

float DensityGrid::at(const Vec3& p) const {
    const Vec3 g = (p - box_.lo) / cellSize_;
    if (!(g.x >= 0.0f && g.y >= 0.0f && g.z >= 0.0f) ||
        !(g.x <= float(nodes_.x - 1) && g.y <= float(nodes_.y - 1) && g.z <= float(nodes_.z - 1)))
        return 0.0f;
    // The cell holding p (the last cell for a point on the far faces).
    return cellAt(glm::min(glm::ivec3(g), nodes_ - 2)).at(g);
}

float DensityGrid::cellIntegral(const Ray& ray, float ta, float tb, const Cell& cell) const {
    // Two-point Gauss-Legendre: nodes at the midpoint -+ half / sqrt(3), weights half each.
    const float mid = 0.5f * (ta + tb), half = 0.5f * (tb - ta);
    const float offset = half * 0.57735026919f;
    return half * (cell.at(gridPoint(ray, mid - offset)) + cell.at(gridPoint(ray, mid + offset)));
}

template <typename Visit>
void DensityGrid::forEachCell(const Ray& ray, float t0, float t1, Visit&& visit) const {
    // The direction of the steps and their length in t on each axis.
    Vec3 tStep;
    glm::ivec3 step;
    for (int axis = 0; axis < 3; ++axis) {
        const float d = ray.d[axis];
        step[axis] = d > 0.0f ? 1 : (d < 0.0f ? -1 : 0);
        tStep[axis] = d != 0.0f ? cellSize_[axis] / std::abs(d) : INFINITY;
    }
    // The parameter at which the ray crosses the lattice plane `plane` (in node units) of `axis`.
    const auto crossing = [&](int axis, int plane) {
        return (box_.lo[axis] + float(plane) * cellSize_[axis] - ray.o[axis]) / ray.d[axis];
    };
    // The cell of the start, then the parameters at which the ray crosses the next lattice plane
    // on each axis.
    const Vec3 g = (ray.o + t0 * ray.d - box_.lo) / cellSize_;
    glm::ivec3 current = glm::clamp(glm::ivec3(glm::floor(g)), glm::ivec3(0), nodes_ - 2);
    Vec3 tNext;
    const auto planesAhead = [&] {
        for (int axis = 0; axis < 3; ++axis)
            tNext[axis] =
                step[axis] == 0 ? INFINITY : crossing(axis, current[axis] + (step[axis] > 0));
    };
    planesAhead();
    float t = t0;
    while (t < t1) {
        const EmptyBlocks* across = nullptr;
        if (emptyCells_[index(current.x, current.y, current.z)])
            across = coarseBlocks_.holds(current)
                         ? &coarseBlocks_
                         : (fineBlocks_.holds(current) ? &fineBlocks_ : nullptr);
        if (across) {
            // Across the empty block: to the first of its faces ahead the ray crosses, and into
            // the cell behind that face.
            const int size = across->size;
            const glm::ivec3 first = (current / size) * size;
            float exit = INFINITY;
            int exitAxis = 0;
            for (int axis = 0; axis < 3; ++axis) {
                if (step[axis] == 0)
                    continue;
                const int plane =
                    step[axis] > 0 ? std::min(first[axis] + size, nodes_[axis] - 1) : first[axis];
                const float at = crossing(axis, plane);
                if (at < exit) {
                    exit = at;
                    exitAxis = axis;
                }
            }
            if (!(exit < t1))
                return;
            t = std::max(t, exit);
            // The cell there; along each axis the DDA never steps back (rounding at a corner
            // must not return it to the block it left), and across the exit face it steps on.
            const Vec3 there = (ray.o + t * ray.d - box_.lo) / cellSize_;
            const glm::ivec3 found =
                glm::clamp(glm::ivec3(glm::floor(there)), glm::ivec3(0), nodes_ - 2);
            for (int axis = 0; axis < 3; ++axis) {
                if (step[axis] > 0)
                    current[axis] = std::max(current[axis], found[axis]);
                else if (step[axis] < 0)
                    current[axis] = std::min(current[axis], found[axis]);
            }
            current[exitAxis] = step[exitAxis] > 0
                                    ? std::min(first[exitAxis] + size, nodes_[exitAxis] - 1)
                                    : first[exitAxis] - 1;
            if (current[exitAxis] < 0 || current[exitAxis] > nodes_[exitAxis] - 2)
                return;
            planesAhead();
            continue;
        }
        const int axis =
            tNext.x < tNext.y ? (tNext.x < tNext.z ? 0 : 2) : (tNext.y < tNext.z ? 1 : 2);
        // Rounding may put the first crossing a hair before t: the piece is then empty.
        const float end = std::max(t, std::min(tNext[axis], t1));
        if (!emptyCells_[index(current.x, current.y, current.z)] && !visit(t, end, cellAt(current)))
            return;
        t = end;
        current[axis] += step[axis];
        if (current[axis] < 0 || current[axis] > nodes_[axis] - 2)
            return;
        tNext[axis] += tStep[axis];
    }
}

float DensityGrid::integral(const Ray& ray, float t0, float t1) const {
    float sum = 0.0f;
    forEachCell(ray, t0, t1, [&](float ta, float tb, const Cell& cell) {
        sum += cellIntegral(ray, ta, tb, cell);
        return true;
    });
    return sum;
}

std::optional<float> DensityGrid::invertIntegral(const Ray& ray, float t0, float t1,
                                                 float target) const {
    std::optional<float> found;
    float remaining = target;
    forEachCell(ray, t0, t1, [&](float ta, float tb, const Cell& cell) {
        const float piece = cellIntegral(ray, ta, tb, cell);
        if (piece < remaining) {
            remaining -= piece;
            return true;
        }
        if (!(remaining > 0.0f)) {
            found = ta;
            return false;
        }
        // Within this cell F(t) = integral from ta to t is a monotone quartic: Newton's method on
        // F(t) = remaining, kept inside the bracket [lo, hi] by bisection where a step leaves it
        // (Press et al., "Numerical Recipes", 3rd ed., section 9.4, rtsafe).
        float lo = ta, hi = tb;
        float t = ta + (tb - ta) * (remaining / piece);
        for (int iteration = 0; iteration < 32; ++iteration) {
            const float error = cellIntegral(ray, ta, t, cell) - remaining;
            if (error > 0.0f)
                hi = t;
            else
                lo = t;
            if (std::abs(error) <= 1e-6f * piece || hi - lo <= 1e-7f * (std::abs(t) + 1.0f))
                break;
            const float slope = cell.at(gridPoint(ray, t));
            const float newton = slope > 0.0f ? t - error / slope : NAN;
            t = (newton > lo && newton < hi) ? newton : 0.5f * (lo + hi);
        }
        found = t;
        return false;
    });
    return found;
}

}  // namespace penumbra
