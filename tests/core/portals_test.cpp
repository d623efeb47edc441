// Portals: the density of PortalSet against the solid angle of a rectangle (closed form), and the
// environment light with portals against the irradiance of a uniform sky (pi L), which a wrong
// mixture of the portal, map and sun densities would miss.
#include "core/portals.h"
#include "core/environment_light.h"
#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace penumbra::test {
namespace {

// A 2 x 1 m window 3 m above the origin, facing down, and one beside it.
Portal window(float x) {
    return Portal{Vec3(x - 1.0f, 3.0f, -0.5f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f)};
}

// The solid angle of a rectangle of half-sides a and b seen from distance h on its axis:
// 4 arcsin(a b / sqrt((a² + h²)(b² + h²))).
double rectangleSolidAngle(double a, double b, double h) {
    return 4.0 * std::asin(a * b / std::sqrt((a * a + h * h) * (b * b + h * h)));
}

TEST(Portals, TheDensityIntegratesToTheWindowsSolidAngle) {
    // E[1 / pdf] over the directions sample() draws is the solid angle they cover: exactly that
    // of the window, when sample() and pdf() agree.
    const PortalSet portals({window(0.0f)});
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    double sum = 0.0, sumSquares = 0.0;
    constexpr int kCount = 200000;
    for (int i = 0; i < kCount; ++i) {
        const std::optional<Vec3> d = portals.sample(Vec3(0.0f), Vec2(uniform(rng), uniform(rng)));
        ASSERT_TRUE(d);
        const double inverse = 1.0 / double(portals.pdf(Vec3(0.0f), *d));
        sum += inverse;
        sumSquares += inverse * inverse;
    }
    const double mean = sum / kCount;
    const double se = std::sqrt((sumSquares / kCount - mean * mean) / kCount);
    const double expected = rectangleSolidAngle(1.0, 0.5, 3.0);
    std::printf("[ measured ] solid angle %.6f +- %.6f sr, closed form %.6f sr\n", mean, se,
                expected);
    EXPECT_NEAR(mean, expected, 4.0 * se + 1e-5 * expected);
    // Directions that miss every portal have no density; the portal seen from behind has.
    EXPECT_EQ(portals.pdf(Vec3(0.0f), Vec3(0.0f, -1.0f, 0.0f)), 0.0f);
    EXPECT_GT(portals.pdf(Vec3(0.0f, 6.0f, 0.0f), Vec3(0.0f, -1.0f, 0.0f)), 0.0f);
    EXPECT_THROW(PortalSet({Portal{Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f), Vec3(2.0f, 0.0f, 0.0f)}}),
                 std::invalid_argument);
}

TEST(Portals, EnvironmentWithPortalsStaysUnbiased) {
    // A uniform sky of radiance L above the horizon: an upward receiver gets pi L whatever share
    // of the samples the two windows take, and every sample carries the density pdfDirection()
    // gives from its receiver.
    constexpr float kL = 2.0f;
    Image sky(32, 16, {"R", "G", "B"});
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            for (int c = 0; c < 3; ++c)
                sky.at(x, y, c) = y < 8 ? kL : 0.0f;
    const EnvironmentLight light(sky, Mat3(1.0f), 1.0f, Vec3(0.0f), 10.0f, "", std::nullopt,
                                 PortalSet({window(0.0f), window(3.0f)}));
    const LightSampleContext ctx{Vec3(0.2f, 0.0f, 0.1f), Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f)};
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    double sum = 0.0, sumSquares = 0.0;
    constexpr int kCount = 400000;
    for (int i = 0; i < kCount; ++i) {
        const std::optional<LightLiSample> s =
            light.sampleLi(ctx, Vec2(uniform(rng), uniform(rng)));
        if (!s)
            continue;
        ASSERT_EQ(s->pdf, light.pdfDirection(ctx.p, s->wi));
        const double f = double(s->L.g) * std::max(0.0f, s->wi.y) / double(s->pdf);
        sum += f;
        sumSquares += f * f;
    }
    const double mean = sum / kCount;
    const double se = std::sqrt((sumSquares / kCount - mean * mean) / kCount);
    // The bilinear blend of the horizon's two rows takes (pi / 16)² / 24 = 1.6e-3 of E.
    const double expected = kPiD * kL * (1.0 - 1.6e-3);
    std::printf("[ measured ] E = %.5f +- %.5f, pi L = %.5f\n", mean, se, kPiD * kL);
    EXPECT_NEAR(mean, expected, 4.0 * se + 1e-3 * expected);
}

}  // namespace
}  // namespace penumbra::test
