// The candidates a hash grid of boxes gives (radiosity/box_grid.h) against every pair tested
// directly: boxes from a millimetre to tens of metres, as a room's patches are (a floor's and a
// lamp's), flat ones (a wall's patches), ones that touch and ones far from the origin.
#include "radiosity/box_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace penumbra::test {
namespace {

bool overlap(const GridBox& a, const GridBox& b) {
    return glm::all(glm::lessThanEqual(a.lo, b.hi)) && glm::all(glm::lessThanEqual(b.lo, a.hi));
}

std::vector<GridBox> mixedBoxes() {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<GridBox> boxes;
    for (int i = 0; i < 3000; ++i) {
        const glm::dvec3 lo(10.0 * unit(rng), 3.0 * unit(rng), 10.0 * unit(rng));
        // Sizes spread over four decades, a third of them flat along one axis.
        glm::dvec3 size(std::pow(10.0, -3.0 + 4.0 * unit(rng)) *
                        glm::dvec3(unit(rng), unit(rng), unit(rng)));
        if (i % 3 == 0)
            size[i % 2] = 0.0;
        boxes.push_back({lo, lo + size});
    }
    // A box that ends exactly where the next begins counts as overlapping.
    boxes.push_back({glm::dvec3(20.0), glm::dvec3(21.0)});
    boxes.push_back({glm::dvec3(21.0, 20.0, 20.0), glm::dvec3(22.0, 21.0, 21.0)});
    // Two small boxes a million kilometres away, past an int's range of the finest cells.
    boxes.push_back({glm::dvec3(1e9), glm::dvec3(1e9 + 0.01)});
    boxes.push_back({glm::dvec3(1e9 + 0.005), glm::dvec3(1e9 + 0.02)});
    return boxes;
}

TEST(BoxGrid, OverlappingPairsAreEveryOverlappingPairOnce) {
    const std::vector<GridBox> boxes = mixedBoxes();
    std::set<std::pair<uint32_t, uint32_t>> expected;
    for (uint32_t i = 0; i < boxes.size(); ++i)
        for (uint32_t j = i + 1; j < boxes.size(); ++j)
            if (overlap(boxes[i], boxes[j]))
                expected.insert({i, j});
    std::set<std::pair<uint32_t, uint32_t>> found;
    for (const auto& [i, j] : overlappingPairs(boxes)) {
        ASSERT_NE(i, j);
        const bool added = found.insert({std::min(i, j), std::max(i, j)}).second;
        EXPECT_TRUE(added) << "pair " << i << ", " << j << " twice";
    }
    EXPECT_GT(expected.size(), 1000u);
    EXPECT_EQ(found, expected);
    EXPECT_TRUE(found.count({uint32_t(boxes.size() - 4), uint32_t(boxes.size() - 3)}));
    EXPECT_TRUE(found.count({uint32_t(boxes.size() - 2), uint32_t(boxes.size() - 1)}));
}

TEST(BoxGrid, ForNearVisitsEveryOverlappingBox) {
    const std::vector<GridBox> boxes = mixedBoxes();
    const BoxGrid grid(boxes, 15.0, 0.0);
    for (uint32_t i = 0; i < boxes.size(); i += 37) {
        std::set<uint32_t> visited;
        grid.forNear(boxes[i].lo, boxes[i].hi, [&](uint32_t j) { visited.insert(j); });
        for (uint32_t j = 0; j < boxes.size(); ++j) {
            if (overlap(boxes[i], boxes[j])) {
                EXPECT_TRUE(visited.count(j)) << i << " misses " << j;
            }
        }
    }
}

}  // namespace
}  // namespace penumbra::test
