#include "radiosity/box_grid.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace penumbra {

namespace {

// The grid's cells: not smaller than this fraction of the scene's diagonal.
constexpr double kMinCellFraction = 1.0 / 256.0;
constexpr double kMaxCellsAcross = 64.0;

constexpr uint32_t kNotSeen = std::numeric_limits<uint32_t>::max();
// The levels of overlappingPairs's grid: 2^24 between the largest box and the finest cell.
constexpr int kMaxLevels = 25;

}  // namespace

BoxGrid::BoxGrid(const std::vector<GridBox>& boxes, double diagonal, double pad)
    : seen_(boxes.size(), 0) {
    double meanExtent = 0.0, largestExtent = 0.0;
    for (const GridBox& b : boxes) {
        const glm::dvec3 extent = b.hi - b.lo;
        meanExtent += glm::length(extent);
        largestExtent = std::max({largestExtent, extent.x, extent.y, extent.z});
    }
    meanExtent /= double(std::max<size_t>(boxes.size(), 1));
    cell_ = std::max({meanExtent, kMinCellFraction * diagonal, largestExtent / kMaxCellsAcross});
    for (uint32_t i = 0; i < boxes.size(); ++i) {
        forCells(boxes[i].lo - glm::dvec3(pad), boxes[i].hi + glm::dvec3(pad),
                 [&](uint64_t k) { cells_[k].push_back(i); });
    }
}

std::vector<std::pair<uint32_t, uint32_t>> overlappingPairs(const std::vector<GridBox>& boxes) {
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    if (boxes.empty())
        return pairs;
    const auto largestExtent = [](const GridBox& b) {
        const glm::dvec3 e = b.hi - b.lo;
        return std::max({e.x, e.y, e.z});
    };
    std::vector<double> extents;
    extents.reserve(boxes.size());
    for (const GridBox& b : boxes)
        extents.push_back(largestExtent(b));
    std::vector<double> sorted = extents;
    const auto middle = sorted.begin() + std::ptrdiff_t(sorted.size() / 2);
    std::nth_element(sorted.begin(), middle, sorted.end());
    const double largest = *std::max_element(extents.begin(), extents.end());
    // Level k's cells are base * 2^k wide, base the median extent (at most kMaxLevels levels); a
    // box goes to the first level whose cells are at least as wide as it, so that it overlaps at
    // most two of them along each axis.
    const double base = std::max(
        {*middle, std::ldexp(largest, -(kMaxLevels - 1)), std::numeric_limits<double>::min()});
    std::vector<int> level(boxes.size(), 0);
    std::vector<char> held(kMaxLevels + 1, 0);
    for (size_t i = 0; i < boxes.size(); ++i) {
        while (base * std::ldexp(1.0, level[i]) < extents[i])
            ++level[i];
        held[size_t(level[i])] = 1;
    }
    std::vector<int> levels;  // the levels that hold a box, finest first
    for (int l = 0; l <= kMaxLevels; ++l) {
        if (held[size_t(l)])
            levels.push_back(l);
    }
    const auto key = [](int l, const glm::ivec3& c) {
        const auto bits = [](int v) { return uint64_t(uint32_t(v) & 0x7ffffu); };
        return (uint64_t(l) << 57) | (bits(c.x) << 38) | (bits(c.y) << 19) | bits(c.z);
    };
    const auto forCells = [&](int l, const GridBox& b, const auto& visit) {
        const double cell = base * std::ldexp(1.0, l);
        const glm::ivec3 lo = gridCell(b.lo, cell);
        const glm::ivec3 hi = gridCell(b.hi, cell);
        for (int z = lo.z; z <= hi.z; ++z)
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x)
                    visit(key(l, glm::ivec3(x, y, z)));
    };
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
    cells.reserve(2 * boxes.size());
    for (uint32_t i = 0; i < boxes.size(); ++i)
        forCells(level[i], boxes[i], [&](uint64_t k) { cells[k].push_back(i); });
    // Each box looks for the boxes of its own level and coarser ones; a pair of one level is
    // taken from its later box.
    std::vector<uint32_t> seen(boxes.size(), kNotSeen);
    for (uint32_t i = 0; i < boxes.size(); ++i) {
        for (auto l = std::lower_bound(levels.begin(), levels.end(), level[i]); l != levels.end();
             ++l) {
            forCells(*l, boxes[i], [&](uint64_t k) {
                const auto it = cells.find(k);
                if (it == cells.end())
                    return;
                for (const uint32_t j : it->second) {
                    if (seen[j] == i || (level[j] == level[i] && j >= i))
                        continue;
                    seen[j] = i;
                    const GridBox& a = boxes[i];
                    const GridBox& b = boxes[j];
                    if (glm::all(glm::lessThanEqual(a.lo, b.hi)) &&
                        glm::all(glm::lessThanEqual(b.lo, a.hi)))
                        pairs.emplace_back(i, j);
                }
            });
        }
    }
    return pairs;
}

}  // namespace penumbra
