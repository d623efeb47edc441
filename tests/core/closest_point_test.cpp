// The closest point of a triangle against the nearest of a dense barycentric grid over it (an
// oracle that knows nothing of Voronoi regions), and against points whose answer is known.
#include "core/closest_point.h"

#include <gtest/gtest.h>

#include <random>

namespace penumbra {
namespace {

// The nearest to p of a (n + 1)(n + 2) / 2-point barycentric grid over the triangle.
float gridDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
    float best = std::numeric_limits<float>::infinity();
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; i + j <= n; ++j) {
            const float u = static_cast<float>(i) / n, v = static_cast<float>(j) / n;
            best = std::min(best, glm::distance(p, a + u * (b - a) + v * (c - a)));
        }
    }
    return best;
}

TEST(ClosestPointOnTriangle, KnownRegions) {
    const Vec3 a(0.0f), b(1.0f, 0.0f, 0.0f), c(0.0f, 1.0f, 0.0f);
    // Over the face: the projection.
    EXPECT_EQ(closestPointOnTriangle(Vec3(0.25f, 0.25f, 2.0f), a, b, c), Vec3(0.25f, 0.25f, 0.0f));
    // Beyond each vertex.
    EXPECT_EQ(closestPointOnTriangle(Vec3(-1.0f, -1.0f, 1.0f), a, b, c), a);
    EXPECT_EQ(closestPointOnTriangle(Vec3(2.0f, -0.5f, 0.0f), a, b, c), b);
    EXPECT_EQ(closestPointOnTriangle(Vec3(-0.5f, 2.0f, -3.0f), a, b, c), c);
    // Beyond the hypotenuse: its point at the perpendicular.
    const Vec3 q = closestPointOnTriangle(Vec3(1.0f, 1.0f, 0.0f), a, b, c);
    EXPECT_NEAR(q.x, 0.5f, 1e-6f);
    EXPECT_NEAR(q.y, 0.5f, 1e-6f);
}

// Random triangles, slivers among them, and random points: the distance to the closest point is
// the grid's smallest to within the grid's spacing, and never larger (the point lies on the
// triangle, so no point of it can be nearer than the true minimum).
TEST(ClosestPointOnTriangle, MatchesADenseGrid) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    const auto point = [&] { return Vec3(u(rng), u(rng), u(rng)); };
    constexpr int kGrid = 400;
    for (int t = 0; t < 200; ++t) {
        const Vec3 a = point(), b = point();
        // One in four a sliver: c a thousandth of the edge's length off the edge ab.
        const Vec3 c = t % 4 == 0 ? 0.5f * (a + b) + 1e-3f * point() : point();
        const float edge =
            std::max({glm::distance(a, b), glm::distance(b, c), glm::distance(c, a)});
        const Vec3 p = 2.0f * point();
        const Vec3 q = closestPointOnTriangle(p, a, b, c);
        const float exact = glm::distance(p, q), grid = gridDistance(p, a, b, c, kGrid);
        EXPECT_LE(exact, grid + 1e-5f) << "triangle " << t;
        EXPECT_GE(exact, grid - edge / kGrid) << "triangle " << t;
    }
}

}  // namespace
}  // namespace penumbra
