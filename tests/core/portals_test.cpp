// Portals: the rectified sampling of PortalSet against the solid angle of a rectangle (closed
// form) and of a parallelogram (uniform area sampling, another estimator), a chi-square test of
// its directions against its density under a sky with a bright spot, and the environment light
// with portals against the irradiance of a uniform sky (pi L), which a wrong mixture of the
// portal, map and sun densities would miss.
#include "core/portals.h"
#include "core/environment_light.h"
#include "tests/support/chi2.h"
#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <vector>

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

float constantLuminance(const Vec3&) {
    return 1.0f;
}

struct Moments {
    double mean, standardError;
};

// The mean of 1 / pdf over the directions sample() draws from `from`: the solid angle they cover,
// exactly that of the portals' windows when sample() and pdf() agree.
Moments coveredSolidAngle(const PortalSet& portals, const Vec3& from, const Portal& portal,
                          int count) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const double shown = portals.luminanceShown(from);
    const Vec3 n = glm::normalize(glm::cross(portal.edge1, portal.edge2));
    double sum = 0.0, sumSquares = 0.0;
    for (int i = 0; i < count; ++i) {
        const std::optional<Vec3> d = portals.sample(from, Vec2(uniform(rng), uniform(rng)), shown);
        EXPECT_TRUE(d);
        if (!d)
            continue;
        // It crosses the portal: its plane ahead, within the edges.
        const float t = glm::dot(portal.corner - from, n) / glm::dot(*d, n);
        EXPECT_GT(t, 0.0f);
        const Vec3 q = from + t * *d - portal.corner;
        const Vec3 along = glm::cross(portal.edge1, portal.edge2);
        const float a = glm::dot(glm::cross(q, portal.edge2), along) / glm::dot(along, along);
        const float b = glm::dot(glm::cross(portal.edge1, q), along) / glm::dot(along, along);
        EXPECT_TRUE(a > -1e-4f && a < 1.0001f && b > -1e-4f && b < 1.0001f) << a << " " << b;
        const double inverse = 1.0 / double(portals.pdf(from, *d, shown));
        sum += inverse;
        sumSquares += inverse * inverse;
    }
    const double mean = sum / count;
    return Moments{mean, std::sqrt((sumSquares / count - mean * mean) / count)};
}

TEST(Portals, TheDensityIntegratesToTheWindowsSolidAngle) {
    const Portal portal = window(0.0f);
    const PortalSet portals({portal}, constantLuminance, PortalSet::kResolution, 2);
    const Moments covered = coveredSolidAngle(portals, Vec3(0.0f), portal, 200000);
    const double expected = rectangleSolidAngle(1.0, 0.5, 3.0);
    const double shown = portals.luminanceShown(Vec3(0.0f));
    std::printf(
        "[ measured ] solid angle %.6f +- %.6f sr, closed form %.6f sr; luminance shown "
        "%.6f (a luminance of 1)\n",
        covered.mean, covered.standardError, expected, shown);
    EXPECT_NEAR(covered.mean, expected, 4.0 * covered.standardError + 1e-5 * expected);
    // The luminance shown is the coarse image's integral over the window: the solid angle, but
    // for the coarse cells the window's edges cut, whose mean over the whole cell stands for the
    // part inside (a sixteenth of the image across). It only weighs the portals against each
    // other, so a few percent cost noise, not correctness.
    EXPECT_NEAR(shown, expected, 0.05 * expected);
    // Directions that miss every portal have no density; the portal seen from behind has.
    EXPECT_EQ(portals.pdf(Vec3(0.0f), Vec3(0.0f, -1.0f, 0.0f), shown), 0.0f);
    const Vec3 above(0.0f, 6.0f, 0.0f);
    EXPECT_GT(portals.pdf(above, Vec3(0.0f, -1.0f, 0.0f), portals.luminanceShown(above)), 0.0f);
    EXPECT_THROW(PortalSet({Portal{Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f), Vec3(2.0f, 0.0f, 0.0f)}},
                           constantLuminance),
                 std::invalid_argument);
}

TEST(Portals, AParallelogramCoversItsSolidAngle) {
    // Edges 60 degrees apart, seen from off its centre: the solid angle by uniform area sampling,
    // E[A cos / r²], against E[1 / pdf] over the rectified samples.
    const Portal portal{Vec3(-0.4f, 1.2f, -0.3f), Vec3(1.5f, 0.0f, 0.0f), Vec3(0.6f, 0.0f, 1.04f)};
    const Vec3 from(0.3f, 0.1f, 0.2f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const Vec3 n = glm::normalize(glm::cross(portal.edge1, portal.edge2));
    double sum = 0.0, sumSquares = 0.0;
    constexpr int kCount = 400000;
    for (int i = 0; i < kCount; ++i) {
        const Vec3 q = portal.corner + uniform(rng) * portal.edge1 + uniform(rng) * portal.edge2;
        const Vec3 toward = q - from;
        const double r2 = glm::dot(toward, toward);
        const double f = portal.area() * std::abs(glm::dot(toward, n)) / (r2 * std::sqrt(r2));
        sum += f;
        sumSquares += f * f;
    }
    const double areaMean = sum / kCount;
    const double areaError = std::sqrt((sumSquares / kCount - areaMean * areaMean) / kCount);
    const PortalSet portals({portal}, constantLuminance);
    const Moments covered = coveredSolidAngle(portals, from, portal, 200000);
    std::printf(
        "[ measured ] parallelogram: %.5f +- %.5f sr by the portal's samples, %.5f +- "
        "%.5f sr by its area\n",
        covered.mean, covered.standardError, areaMean, areaError);
    EXPECT_NEAR(covered.mean, areaMean,
                4.0 * std::hypot(covered.standardError, areaError) + 1e-5 * areaMean);
}

// The chi-square test of the directions sample() draws from `from` against pdf(), on bins fine
// enough (4.5 degrees) that a portal a metre or so away covers a hundred of them.
void expectDirectionsFollowPdf(const PortalSet& portals, const Vec3& from, uint32_t seed,
                               const char* what) {
    const double shown = portals.luminanceShown(from);
    Chi2Options options;
    options.thetaBins = 40;
    options.phiBins = 80;
    options.sampleCount = 400000;
    options.seed = seed;
    const Chi2Result result =
        chi2Test([&](const Vec3& u) { return portals.sample(from, Vec2(u.x, u.y), shown); },
                 [&](const Vec3& w) { return portals.pdf(from, w, shown); }, options);
    std::printf("[ measured ] %s: chi-square %.1f, %d dof, p = %.3f\n", what, result.statistic,
                result.dof, result.pValue);
    EXPECT_TRUE(result.passed) << result.report;
    EXPECT_GE(result.dof, 100);
}

TEST(Portals, DirectionsFollowTheSkysLuminance) {
    // A sky of luminance 1 with a spot 20 degrees wide of 300 seen through a 2 x 1 m window 0.5 m
    // above the point (chi2Test's z up): the directions against pdf(), the density against the
    // luminance.
    const Portal portal{Vec3(-1.2f, -0.5f, 0.5f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f)};
    const Vec3 spot = glm::normalize(Vec3(0.5f, 0.2f, 1.0f));
    const auto luminance = [&](const Vec3& d) {
        return glm::dot(d, spot) > std::cos(glm::radians(10.0f)) ? 300.0f : 1.0f;
    };
    const PortalSet portals({portal}, luminance, PortalSet::kResolution, 2);
    const Vec3 from(0.0f);
    const double shown = portals.luminanceShown(from);
    expectDirectionsFollowPdf(portals, from, 7, "one portal");

    // Away from the spot's rim, where cells mix both values, luminance / pdf is the same for
    // every direction (the image's integral over the window), up to the variation of the solid
    // angle per unit area within a cell: the gradient of its logarithm, 2 / (1 - |s|) plus the
    // |w|^-3 term in each of s and t, is about 7 in all where the spot is (s = 0.33, t = 0.17);
    // times half a cell's width in s or t, 1 / 64, 11 % between a cell's corner and its mean.
    // 14 % bounds it. A cell spans up to 2.6 degrees there: directions within 3 degrees of the
    // spot's rim are left out.
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<double> ratios;
    int inSpot = 0;
    constexpr int kCount = 20000;
    for (int i = 0; i < kCount; ++i) {
        const auto d = portals.sample(from, Vec2(uniform(rng), uniform(rng)), shown);
        ASSERT_TRUE(d);
        const float angle = glm::degrees(std::acos(std::min(1.0f, glm::dot(*d, spot))));
        inSpot += angle < 10.0f;
        if (std::abs(angle - 10.0f) >= 3.0f)
            ratios.push_back(luminance(*d) / double(portals.pdf(from, *d, shown)));
    }
    std::sort(ratios.begin(), ratios.end());
    const double median = ratios[ratios.size() / 2];
    const double worst = std::max(median / ratios.front(), ratios.back() / median) - 1.0;
    std::printf("[ measured ] luminance / pdf %.5f, at worst %.4f off; %d of %d in the spot\n",
                median, worst, inSpot, kCount);
    EXPECT_LT(worst, 0.14);
    // The spot holds 300 x 0.095 sr of the luminance shown, the rest of the window under 2 pi:
    // over half of it, so over half the samples.
    EXPECT_GT(inSpot, kCount / 2);
}

TEST(Portals, TwoPortalsFollowTheirDensity) {
    // A roof light and a window in a wall at right angles to it, seen from between them under a
    // sky brighter towards +x: which portal, then where in it, against pdf().
    const std::vector<Portal> windows = {
        Portal{Vec3(-1.2f, -0.5f, 0.5f), Vec3(2.0f, 0.0f, 0.0f), Vec3(0.0f, 1.0f, 0.0f)},
        Portal{Vec3(0.9f, -0.6f, -0.4f), Vec3(0.0f, 1.2f, 0.0f), Vec3(0.0f, 0.0f, 0.8f)}};
    const PortalSet portals(windows,
                            [](const Vec3& d) { return 1.0f + 4.0f * std::max(d.x, 0.0f); });
    const Vec3 from(0.1f, 0.05f, 0.0f);
    expectDirectionsFollowPdf(portals, from, 8, "two portals");
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
                                 {window(0.0f), window(3.0f)});
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
