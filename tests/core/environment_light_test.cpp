// The environment light: its equirectangular mapping and rotation against directions worked out
// by hand from the header's formulas; its density integrates to one over the sphere (quadrature)
// and is what sampleLi() draws (chi-square); power() and irradiance against closed forms and
// against uniform sampling of the sphere; photon emission against power(); the validation of the
// image. Every statistical test has a fixed seed and states why its tolerance is right.
#include "core/environment_light.h"
#include "core/sampling.h"
#include "tests/support/chi2.h"
#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>

namespace penumbra::test {
namespace {

const Vec3 kCenter(0.5f, -0.25f, 1.0f);
constexpr float kRadius = 2.0f;

Image makeImage(int width, int height, const std::function<Color(int, int)>& pixel) {
    Image image(width, height, {"R", "G", "B"});
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                image.at(x, y, c) = pixel(x, y)[c];
    return image;
}

// A sky over black ground: blue, brightening along u, above the horizon; black below it; a
// one-pixel sun of luminance about `sun` at (17/24 W, H/4), 45 degrees above the horizon.
Image sunImage(int width, int height, float sun) {
    return makeImage(width, height, [&](int x, int y) {
        if (x == 17 * width / 24 && y == height / 4)
            return sun * Color(1.2f, 1.0f, 0.7f);
        if (y >= height / 2)
            return Color(0.0f);
        return (1.0f + float(x) / float(width)) * Color(0.4f, 0.6f, 1.0f);
    });
}

// The direction at (theta, phi) of the header's inverse mapping, phi = 2 pi u, theta = v pi.
Vec3 mapDirection(double theta, double phi) {
    return Vec3(float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)),
                float(-std::sin(theta) * std::cos(phi)));
}

// chi2Test() bins in cos theta about +z; the light's up axis is +y. A cyclic permutation of the
// axes (a rotation) takes one to the other.
Vec3 yUpToZUp(const Vec3& w) {
    return Vec3(w.z, w.x, w.y);
}
Vec3 zUpToYUp(const Vec3& w) {
    return Vec3(w.y, w.z, w.x);
}

// The mapping --------------------------------------------------------------------------------

// A 4 x 2 map whose pixels all differ; pixel (x, y) is centred at theta = pi/4 (top row) or
// 3 pi/4, phi = pi/4, 3 pi/4, 5 pi/4, 7 pi/4: by the header's formulas its direction is
// (+-1/2, +-sqrt(1/2), +-1/2) with the signs below.
Color mappingPixel(int x, int y) {
    return Color(1.0f + float(x + 4 * y), 10.0f + 2.0f * float(x), 0.5f + 3.0f * float(y));
}
const float kSignX[4] = {1.0f, 1.0f, -1.0f, -1.0f}, kSignZ[4] = {-1.0f, 1.0f, 1.0f, -1.0f};

TEST(EnvironmentLight, PixelCentresGiveTheirPixels) {
    constexpr float kScale = 2.0f;
    const EnvironmentLight light(makeImage(4, 2, mappingPixel), Mat3(1.0f), kScale, kCenter,
                                 kRadius, "map.exr");
    const float s = std::sqrt(0.5f);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            const Vec3 d(0.5f * kSignX[x], y == 0 ? s : -s, 0.5f * kSignZ[x]);
            expectColorNear(light.radiance(d), kScale * mappingPixel(x, y), 1e-5);
        }
    // The image's centre, +Z on the horizon, lies between the four middle pixels; -Z between the
    // last and first columns, across the seam (wrapping in u).
    const auto mean4 = [](int x0, int x1) {
        return 0.25f * kScale *
               (mappingPixel(x0, 0) + mappingPixel(x1, 0) + mappingPixel(x0, 1) +
                mappingPixel(x1, 1));
    };
    expectColorNear(light.radiance(Vec3(0, 0, 1)), mean4(1, 2), 1e-5);
    expectColorNear(light.radiance(Vec3(0, 0, -1)), mean4(3, 0), 1e-5);
    // Above the top row's centres the radiance is the top row's (clamped in v).
    expectColorNear(light.radiance(mapDirection(kPiD / 8.0, -kPiD / 4.0)),
                    kScale * mappingPixel(3, 0), 1e-5);
    EXPECT_EQ(light.describe(), "environment 'map.exr' 4 x 2, scale 2");
}

TEST(EnvironmentLight, RotationMovesTheMapAboutUp) {
    // R_y(90) = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]] takes the map's direction (a, b, c) to the
    // world's (c, b, -a): the map's -Z (the image's left edge) to -X.
    const Mat3 worldToLocal = environmentRotation(90.0f);
    const Vec3 centre = worldToLocal * Vec3(-1.0f, 0.0f, 0.0f);
    EXPECT_NEAR(centre.x, 0.0f, 1e-6f);
    EXPECT_NEAR(centre.y, 0.0f, 1e-6f);
    EXPECT_NEAR(centre.z, -1.0f, 1e-6f);
    const Vec3 up = worldToLocal * Vec3(0.0f, 1.0f, 0.0f);
    EXPECT_NEAR(glm::length(up - Vec3(0.0f, 1.0f, 0.0f)), 0.0f, 1e-6f);

    const EnvironmentLight light(makeImage(4, 2, mappingPixel), worldToLocal, 1.0f, kCenter,
                                 kRadius, "map.exr");
    const float s = std::sqrt(0.5f);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            const Vec3 local(0.5f * kSignX[x], y == 0 ? s : -s, 0.5f * kSignZ[x]);
            const Vec3 world(local.z, local.y, -local.x);
            expectColorNear(light.radiance(world), mappingPixel(x, y), 1e-5);
        }
}

TEST(EnvironmentLight, ReadsRgbByNameElseGrey) {
    Image bgr(2, 1, {"B", "G", "R"});
    Image grey(2, 1, {"Y"});
    for (int x = 0; x < 2; ++x) {
        bgr.at(x, 0, 0) = 3.0f;
        bgr.at(x, 0, 1) = 2.0f;
        bgr.at(x, 0, 2) = 1.0f;
        grey.at(x, 0, 0) = 5.0f;
    }
    const Vec3 d = glm::normalize(Vec3(0.3f, 0.4f, -0.5f));
    expectColorNear(EnvironmentLight(bgr, Mat3(1.0f), 1.0f, kCenter, kRadius, "").radiance(d),
                    Color(1.0f, 2.0f, 3.0f), 1e-6);
    expectColorNear(EnvironmentLight(grey, Mat3(1.0f), 1.0f, kCenter, kRadius, "").radiance(d),
                    Color(5.0f), 1e-6);
}

TEST(EnvironmentLight, RefusesAnEmptyImageOrRadius) {
    const Image empty(0, 0, {"R"});
    const Image one = makeImage(1, 1, [](int, int) { return Color(1.0f); });
    EXPECT_THROW(EnvironmentLight(empty, Mat3(1.0f), 1.0f, kCenter, kRadius, ""),
                 std::invalid_argument);
    EXPECT_THROW(EnvironmentLight(one, Mat3(1.0f), 1.0f, kCenter, 0.0f, ""), std::invalid_argument);
}

// A constant map -----------------------------------------------------------------------------

TEST(EnvironmentLight, ConstantMapIsUniform) {
    const Color c(0.8f, 1.0f, 1.3f);
    const EnvironmentLight light(makeImage(256, 128, [&](int, int) { return c; }),
                                 environmentRotation(25.0f), 1.0f, kCenter, kRadius, "");
    // Phi = pi R² * 4 pi c. The piecewise-constant integral is exact for a constant map, up to
    // float rounding of the pixels' sum (1e-6).
    expectColorNear(light.power(), float(kPiD * kRadius * kRadius * 4.0 * kPiD) * c, 1e-4);

    // The density of a constant map is sin(theta at the row's centre) / sin(theta) times
    // 1 / (4 pi): within a row of 1.4 degrees that ratio is within (pi / 256) cot(theta) of 1,
    // under 1.7 % where |cos theta| < 0.8.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    double worstRadiance = 0.0, worstPdf = 0.0;
    for (int i = 0; i < 10000; ++i) {
        const Vec3 w = sampleUniformSphere(Vec2(uniform(rng), uniform(rng)));
        worstRadiance = std::max(worstRadiance, relativeError(light.radiance(w).g, c.g));
        if (std::abs(w.y) < 0.8f)
            worstPdf = std::max(worstPdf,
                                relativeError(light.pdfDirection(kCenter, w), 1.0 / (4.0 * kPiD)));
    }
    std::printf("[ measured ] worst relative radiance error %.3g, pdf error %.3g\n", worstRadiance,
                worstPdf);
    EXPECT_LT(worstRadiance, 1e-5);
    EXPECT_LT(worstPdf, 0.02);

    // The sampled directions are uniform on the sphere: the rows' probabilities sin(theta_c) dtheta
    // are proportional to their solid angles 2 sin(theta_c) sin(dtheta / 2), and only the
    // distribution within a row differs, by 1e-4 of a bin's count, far below the noise.
    const LightSampleContext ctx{Vec3(0.0f)};
    const auto sample = [&](const Vec3& u) -> std::optional<Vec3> {
        const std::optional<LightLiSample> s = light.sampleLi(ctx, Vec2(u.x, u.y));
        return s ? std::optional<Vec3>(yUpToZUp(s->wi)) : std::nullopt;
    };
    Chi2Options options;
    options.seed = 5;
    options.testCount = 2;  // with the chi-square test of a non-uniform map below
    const Chi2Result result = chi2Test(
        sample, [](const Vec3&) { return float(1.0 / (4.0 * kPiD)); }, options);
    std::printf("[ measured ] uniform: chi-square %.1f, %d dof, p = %.3f\n", result.statistic,
                result.dof, result.pValue);
    EXPECT_TRUE(result.passed) << result.report;
    EXPECT_GE(result.dof, 150);
}

// A sun over black ground -------------------------------------------------------------

TEST(EnvironmentLight, PdfIntegratesToOne) {
    // The midpoint rule over a (theta, phi) grid of 50 x 50 nodes per pixel cell. The rotation
    // by 90 degrees shifts phi by a whole number of cells, so no node lies near a cell's edge, and
    // pdf sin(theta) is constant over each cell: the rule is exact up to float rounding (1e-6).
    // A wrong Jacobian (sin theta, 2 pi²) or normalisation fails it by far more than 1e-4.
    constexpr int kWidth = 24, kHeight = 12, kNodes = 50;
    const EnvironmentLight light(sunImage(kWidth, kHeight, 1e4f), environmentRotation(90.0f), 1.0f,
                                 kCenter, kRadius, "");
    const int nTheta = kHeight * kNodes, nPhi = kWidth * kNodes;
    const double dTheta = kPiD / nTheta, dPhi = 2.0 * kPiD / nPhi;
    double integral = 0.0, upper = 0.0;
    for (int i = 0; i < nTheta; ++i) {
        const double theta = (i + 0.5) * dTheta;
        double row = 0.0;
        for (int j = 0; j < nPhi; ++j)
            row += light.pdfDirection(kCenter, mapDirection(theta, -kPiD + (j + 0.5) * dPhi));
        integral += row * std::sin(theta) * dTheta * dPhi;
        if (theta < 0.5 * kPiD + kPiD / kHeight)  // down to the first row below the horizon
            upper += row * std::sin(theta) * dTheta * dPhi;
    }
    std::printf("[ measured ] integral of the pdf %.7f, above the first black row %.7f\n", integral,
                upper);
    EXPECT_NEAR(integral, 1.0, 1e-4);
    // Nothing is sampled where the map and its neighbours are black.
    EXPECT_NEAR(upper, 1.0, 1e-6);
}

TEST(EnvironmentLight, SampleLiFollowsPdfDirection) {
    const EnvironmentLight light(sunImage(24, 12, 20.0f), environmentRotation(30.0f), 1.0f, kCenter,
                                 kRadius, "");
    const LightSampleContext ctx{Vec3(0.3f, 0.1f, -0.2f)};
    // Every sample's own figures, exactly as pdfDirection() and radiance() give them.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < 20000; ++i) {
        const std::optional<LightLiSample> s =
            light.sampleLi(ctx, Vec2(uniform(rng), uniform(rng)));
        if (!s)
            continue;
        ASSERT_EQ(s->pdf, light.pdfDirection(kCenter, s->wi));
        ASSERT_EQ(s->L, light.radiance(s->wi));
        ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-5f);
        ASSERT_GT(glm::length(s->pLight - kCenter), kRadius);
        ASSERT_NEAR(glm::dot(glm::normalize(s->pLight - ctx.p), s->wi), 1.0f, 1e-5f);
        ASSERT_EQ(s->nLight, Vec3(0.0f));
    }

    // sampleLi() drops the directions where the bilinear radiance is black (the lower half of
    // the first row below the horizon, whose density its bright neighbours make positive): the
    // density of what it returns is pdfDirection() where radiance() > 0. The sky holds a quarter
    // of the samples, the sun's 3 x 3 cells the rest.
    const auto sample = [&](const Vec3& u) -> std::optional<Vec3> {
        const std::optional<LightLiSample> s = light.sampleLi(ctx, Vec2(u.x, u.y));
        return s ? std::optional<Vec3>(yUpToZUp(s->wi)) : std::nullopt;
    };
    const auto pdf = [&](const Vec3& w) -> float {
        const Vec3 world = zUpToYUp(w);
        return maxComponent(light.radiance(world)) > 0.0f ? light.pdfDirection(kCenter, world)
                                                          : 0.0f;
    };
    Chi2Options options;
    options.seed = 11;
    options.testCount = 2;
    const Chi2Result result = chi2Test(sample, pdf, options);
    std::printf("[ measured ] sun: chi-square %.1f, %d dof, p = %.3f\n", result.statistic,
                result.dof, result.pValue);
    EXPECT_TRUE(result.passed) << result.report;
    // The upper hemisphere's 100 cells and the 20 just below the horizon expect samples; the
    // rest, which expect none, are pooled.
    EXPECT_GE(result.dof, 90);
}

// Irradiance ---------------------------------------------------------------------------------

struct Irradiance {
    glm::dvec3 mean{0.0}, standardError{0.0};
};

// E = integral of L max(0, n . w) d omega by Monte Carlo, with directions and their densities
// drawn by `sample` (nothing for a sample that contributes zero).
Irradiance irradiance(const Vec3& n, int count, uint32_t seed,
                      const std::function<std::optional<LightLiSample>(Vec2)>& sample) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    glm::dvec3 sum(0.0), sumSquares(0.0);
    for (int i = 0; i < count; ++i) {
        const std::optional<LightLiSample> s = sample(Vec2(uniform(rng), uniform(rng)));
        if (!s || !(s->pdf > 0.0f))
            continue;
        const glm::dvec3 f =
            glm::dvec3(s->L) * double(std::max(0.0f, glm::dot(n, s->wi))) / double(s->pdf);
        sum += f;
        sumSquares += f * f;
    }
    Irradiance e;
    e.mean = sum / double(count);
    const glm::dvec3 variance = (sumSquares - sum * e.mean) / double(count - 1);
    e.standardError = glm::sqrt(glm::max(variance, 0.0) / double(count));
    return e;
}

TEST(EnvironmentLight, IrradianceUnderAUniformSkyIsPiL) {
    // c above the horizon and 0 below: E = pi c on an upward-facing receiver. The bilinear
    // blending of the two rows at the horizon takes (pi / H)² / 24 = 4e-4 of E (H = 32).
    const Color c(1.0f, 0.9f, 0.7f);
    const EnvironmentLight light(
        makeImage(64, 32, [&](int, int y) { return y < 16 ? c : Color(0.0f); }),
        environmentRotation(37.0f), 1.0f, kCenter, kRadius, "");
    const LightSampleContext ctx{kCenter, Vec3(0.0f), Vec3(0.0f, 1.0f, 0.0f)};
    const Irradiance e =
        irradiance(ctx.n, 100000, 13, [&](Vec2 u) { return light.sampleLi(ctx, u); });
    std::printf("[ measured ] E = (%.5f %.5f %.5f), pi c = (%.5f %.5f %.5f), se %.2g relative\n",
                e.mean.x, e.mean.y, e.mean.z, kPiD * c.r, kPiD * c.g, kPiD * c.b,
                e.standardError.x / e.mean.x);
    // 1 %: over 4 standard errors (measured 0.22 %) plus the 0.04 % of the horizon.
    expectColorNear(Color(e.mean), float(kPiD) * c, 0.01);
    EXPECT_LT(e.standardError.y / e.mean.y, 0.003);
}

TEST(EnvironmentLight, IrradianceAgreesWithUniformSampling) {
    const EnvironmentLight light(sunImage(24, 12, 20.0f), environmentRotation(-60.0f), 1.0f,
                                 kCenter, kRadius, "");
    const LightSampleContext ctx{kCenter, Vec3(0.0f), glm::normalize(Vec3(0.3f, 1.0f, -0.2f))};
    const Irradiance importance =
        irradiance(ctx.n, 200000, 17, [&](Vec2 u) { return light.sampleLi(ctx, u); });
    // The other estimator: directions uniform on the sphere, pdf 1 / (4 pi).
    const Irradiance uniform =
        irradiance(ctx.n, 1000000, 19, [&](Vec2 u) -> std::optional<LightLiSample> {
            const Vec3 w = sampleUniformSphere(u);
            return LightLiSample{light.radiance(w), w, float(1.0 / (4.0 * kPiD))};
        });
    for (int c = 0; c < 3; ++c) {
        const double sigma = std::hypot(importance.standardError[c], uniform.standardError[c]);
        std::printf("[ measured ] channel %d: importance %.5f +- %.5f, uniform %.5f +- %.5f\n", c,
                    importance.mean[c], importance.standardError[c], uniform.mean[c],
                    uniform.standardError[c]);
        // 4 combined standard errors: a correct pair differs by more with probability 6e-5.
        EXPECT_NEAR(importance.mean[c], uniform.mean[c], 4.0 * sigma);
        // The bound above is only meaningful if the estimates are precise.
        EXPECT_LT(sigma, 0.01 * uniform.mean[c]);
    }
}

// Photons ------------------------------------------------------------------------------------

TEST(EnvironmentLight, PhotonFluxIsPowerFromTheDisc) {
    // power() integrates the pixels as constant over their cells, the photons the bilinear
    // radiance; for the sun, one pixel 7.5 degrees tall, the two differ by (dtheta)² / 24 =
    // 7e-4 of its share.
    const EnvironmentLight light(sunImage(48, 24, 20.0f), environmentRotation(10.0f), 1.0f, kCenter,
                                 kRadius, "");
    constexpr int kCount = 400000;
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    glm::dvec3 sum(0.0), sumSquares(0.0);
    double worstPlane = 0.0, worstRadius = 0.0;
    for (int i = 0; i < kCount; ++i) {
        const Vec2 uPosition(uniform(rng), uniform(rng)), uDirection(uniform(rng), uniform(rng));
        const std::optional<LightLeSample> s = light.sampleLe(uPosition, uDirection);
        if (!s)
            continue;
        const glm::dvec3 flux(s->flux());
        sum += flux;
        sumSquares += flux * flux;
        EXPECT_EQ(light.emittedLe(*s, s->w), s->L);
        // The origin lies on the disc of radius R perpendicular to w, R behind the centre.
        const Vec3 q = s->p - (kCenter - s->w * kRadius);
        worstPlane = std::max(worstPlane, double(std::abs(glm::dot(q, s->w))));
        worstRadius = std::max(worstRadius, double(glm::length(q)));
    }
    const glm::dvec3 mean = sum / double(kCount);
    const glm::dvec3 se = glm::sqrt((sumSquares / double(kCount) - mean * mean) / double(kCount));
    const Color power = light.power();
    std::printf(
        "[ measured ] mean flux (%.3f %.3f %.3f) +- %.2g relative, power (%.3f %.3f %.3f);"
        " disc: off-plane %.2g m, radius %.6f m\n",
        mean.x, mean.y, mean.z, se.y / mean.y, power.r, power.g, power.b, worstPlane, worstRadius);
    // 1 %: over 4 standard errors (measured 0.1 %) plus the 0.1 % between the integrals.
    expectColorNear(Color(mean), power, 0.01);
    EXPECT_LT(se.y / mean.y, 0.002);
    EXPECT_LT(worstPlane, 1e-5 * kRadius);
    EXPECT_LE(worstRadius, kRadius * (1.0 + 1e-6));
}

TEST(EnvironmentLight, BlackMapEmitsNothing) {
    const EnvironmentLight light(makeImage(8, 4, [](int, int) { return Color(0.0f); }), Mat3(1.0f),
                                 1.0f, kCenter, kRadius, "");
    EXPECT_EQ(light.power(), Color(0.0f));
    EXPECT_EQ(light.pdfDirection(kCenter, glm::normalize(Vec3(0.2f, 0.5f, 0.1f))), 0.0f);
    EXPECT_FALSE(light.sampleLi(LightSampleContext{Vec3(0.0f)}, Vec2(0.3f, 0.6f)));
    EXPECT_FALSE(light.sampleLe(Vec2(0.5f), Vec2(0.3f, 0.6f)));
}

// The sun's disc -------------------------------------------------------------------------

// A sun 35 degrees above the horizon, E_n = 80 000 lux.
SunDisc testSun() {
    SunDisc sun;
    sun.direction = glm::normalize(Vec3(0.4f, std::tan(glm::radians(35.0f)), -0.9165f));
    sun.directNormalIlluminance = 80000.0f;
    return sun;
}

TEST(EnvironmentLight, SunAloneLightsAPlaneWithEnCosTheta) {
    // Black map: every sample is in the disc. E = E_n cos(theta) up to the variation of the
    // cosine over the disc (its radius is 0.0046 rad: at most 0.5 % of E at 60 degrees from the
    // normal, 1e-5 facing it).
    const SunDisc sun = testSun();
    const EnvironmentLight light(makeImage(16, 8, [](int, int) { return Color(0.0f); }), Mat3(1.0f),
                                 1.0f, kCenter, kRadius, "", sun);
    const float angles[] = {0.0f, 30.0f, 60.0f};
    for (float degrees : angles) {
        // A normal turned from the sun's direction by `degrees`.
        const Vec3 side = glm::normalize(glm::cross(sun.direction, Vec3(0.0f, 1.0f, 0.0f)));
        const Vec3 n = glm::normalize(std::cos(glm::radians(degrees)) * sun.direction +
                                      std::sin(glm::radians(degrees)) * side);
        const LightSampleContext ctx{kCenter, Vec3(0.0f), n};
        const Irradiance e =
            irradiance(n, 20000, 29, [&](Vec2 u) { return light.sampleLi(ctx, u); });
        const double expected = sun.directNormalIlluminance * std::cos(glm::radians(degrees));
        std::printf("[ measured ] %2.0f degrees: E = %.2f lux, E_n cos = %.2f\n", degrees, e.mean.y,
                    expected);
        EXPECT_NEAR(e.mean.y, expected, 1e-3 * sun.directNormalIlluminance);
    }
    // Inside the disc the radiance is E_n over its solid angle, outside it nothing.
    EXPECT_NEAR(light.radiance(sun.direction).g, sun.directNormalIlluminance / sun.solidAngle(),
                1e-3f * sun.radiance());
    const Vec3 offDisc = glm::normalize(sun.direction + Vec3(0.0f, 0.01f, 0.0f));
    EXPECT_EQ(light.radiance(offDisc), Color(0.0f));
    EXPECT_EQ(light.power(), Color(kPi * sqr(kRadius) * sun.directNormalIlluminance));
}

// A sky map with and without the sun, and a receiver tilted from the zenith.
struct SunOverSky {
    SunDisc sun = testSun();
    Image sky = sunImage(24, 12, 20.0f);
    EnvironmentLight withSun{sky, environmentRotation(30.0f), 1.0f, kCenter, kRadius, "", sun};
    EnvironmentLight skyOnly{sky, environmentRotation(30.0f), 1.0f, kCenter, kRadius, ""};
    LightSampleContext ctx{kCenter, Vec3(0.0f), glm::normalize(Vec3(0.2f, 1.0f, 0.3f))};
};

TEST(EnvironmentLight, SunAndSkyAddUp) {
    // The mixture of the sky's distribution and the disc: its samples carry the density and
    // radiance pdfDirection() and radiance() give, and the irradiance it estimates is the sky's
    // (from a light without the sun) plus E_n cos(theta).
    const SunOverSky scene;
    const SunDisc& sun = scene.sun;
    const EnvironmentLight &withSun = scene.withSun, &skyOnly = scene.skyOnly;
    const LightSampleContext& ctx = scene.ctx;
    std::mt19937 rng(31);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    int inDisc = 0;
    for (int i = 0; i < 20000; ++i) {
        const std::optional<LightLiSample> s =
            withSun.sampleLi(ctx, Vec2(uniform(rng), uniform(rng)));
        if (!s)
            continue;
        ASSERT_EQ(s->pdf, withSun.pdfDirection(ctx.p, s->wi));
        ASSERT_EQ(s->L, withSun.radiance(s->wi));
        inDisc += sun.contains(s->wi);
    }
    // The disc's share of the samples is its share of the luminous power.
    const double skyIntegral = luminance(skyOnly.power()) / (kPiD * sqr(kRadius));
    const double share = sun.directNormalIlluminance / (sun.directNormalIlluminance + skyIntegral);
    EXPECT_NEAR(inDisc / 20000.0, share, 4.0 * std::sqrt(share * (1.0 - share) / 20000.0));

    const Irradiance both =
        irradiance(ctx.n, 200000, 37, [&](Vec2 u) { return withSun.sampleLi(ctx, u); });
    const Irradiance skyAlone =
        irradiance(ctx.n, 200000, 41, [&](Vec2 u) { return skyOnly.sampleLi(ctx, u); });
    const double sunPart = sun.directNormalIlluminance * glm::dot(ctx.n, sun.direction);
    const double sigma = std::hypot(both.standardError.y, skyAlone.standardError.y);
    std::printf("[ measured ] sun and sky %.2f +- %.2f, sky %.2f + sun %.2f\n", both.mean.y,
                both.standardError.y, skyAlone.mean.y, sunPart);
    // 4 combined standard errors, plus the cosine's variation over the disc (1e-5 of the sun's).
    EXPECT_NEAR(both.mean.y, skyAlone.mean.y + sunPart, 4.0 * sigma + 1e-4 * sunPart);
    EXPECT_LT(sigma, 0.01 * (skyAlone.mean.y + sunPart));
}

TEST(EnvironmentLight, ThePartsSampleApart) {
    // What a render filed by light group draws: the map's part alone follows the map's density
    // (chi-square), carries the map's radiance and estimates the irradiance of a light without
    // the sun; the sun's part alone stays in the disc and gives E_n cos(theta).
    const SunOverSky scene;
    const SunDisc& sun = scene.sun;
    const EnvironmentLight &withSun = scene.withSun, &skyOnly = scene.skyOnly;
    const LightSampleContext& ctx = scene.ctx;
    std::mt19937 rng(43);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < 20000; ++i) {
        const Vec2 u(uniform(rng), uniform(rng));
        for (const EnvironmentPart part : {EnvironmentPart::Map, EnvironmentPart::Sun}) {
            const std::optional<LightLiSample> s = withSun.sampleLi(ctx, u, part);
            if (!s)
                continue;
            ASSERT_EQ(s->pdf, withSun.pdfDirection(ctx.p, s->wi, part));
            ASSERT_EQ(s->L, withSun.radiance(s->wi, part));
            ASSERT_EQ(sun.contains(s->wi), part == EnvironmentPart::Sun);
        }
    }
    ASSERT_EQ(withSun.radiance(sun.direction, EnvironmentPart::Map) +
                  withSun.radiance(sun.direction, EnvironmentPart::Sun),
              withSun.radiance(sun.direction));

    const auto sample = [&](const Vec3& u) -> std::optional<Vec3> {
        const std::optional<LightLiSample> s =
            withSun.sampleLi(ctx, Vec2(u.x, u.y), EnvironmentPart::Map);
        return s ? std::optional<Vec3>(yUpToZUp(s->wi)) : std::nullopt;
    };
    const auto pdf = [&](const Vec3& w) -> float {
        const Vec3 world = zUpToYUp(w);
        return maxComponent(withSun.radiance(world, EnvironmentPart::Map)) > 0.0f
                   ? withSun.pdfDirection(ctx.p, world, EnvironmentPart::Map)
                   : 0.0f;
    };
    Chi2Options options;
    options.seed = 13;
    options.testCount = 2;
    const Chi2Result result = chi2Test(sample, pdf, options);
    EXPECT_TRUE(result.passed) << result.report;

    const Irradiance map = irradiance(
        ctx.n, 200000, 47, [&](Vec2 u) { return withSun.sampleLi(ctx, u, EnvironmentPart::Map); });
    const Irradiance skyAlone =
        irradiance(ctx.n, 200000, 41, [&](Vec2 u) { return skyOnly.sampleLi(ctx, u); });
    EXPECT_NEAR(map.mean.y, skyAlone.mean.y,
                4.0 * std::hypot(map.standardError.y, skyAlone.standardError.y));
    const Irradiance disc = irradiance(
        ctx.n, 20000, 53, [&](Vec2 u) { return withSun.sampleLi(ctx, u, EnvironmentPart::Sun); });
    const double sunPart = sun.directNormalIlluminance * glm::dot(ctx.n, sun.direction);
    // The cosine's variation over the disc (SunAloneLightsAPlaneWithEnCosTheta's bound).
    EXPECT_NEAR(disc.mean.y, sunPart, 1e-3 * sun.directNormalIlluminance);
    // Without a sun, its part draws nothing.
    EXPECT_FALSE(skyOnly.sampleLi(ctx, Vec2(0.5f), EnvironmentPart::Sun));
}

// Validation ---------------------------------------------------------------------------------

TEST(EnvironmentLight, FindsBadPixels) {
    const Image good = makeImage(3, 2, [](int x, int y) { return Color(float(x + y)); });
    EXPECT_EQ(findBadEnvironmentPixel(good), "");
    const auto withValue = [&](float value) {
        Image bad = good;
        bad.at(2, 1, 1) = value;
        return findBadEnvironmentPixel(bad);
    };
    EXPECT_EQ(withValue(std::numeric_limits<float>::quiet_NaN()), "pixel (2, 1) channel G: nan");
    EXPECT_EQ(withValue(std::numeric_limits<float>::infinity()), "pixel (2, 1) channel G: inf");
    EXPECT_EQ(withValue(-0.25f), "pixel (2, 1) channel G: -0.25");
}

}  // namespace
}  // namespace penumbra::test
