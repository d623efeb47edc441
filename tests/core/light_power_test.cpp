// Emitted power: Light::power() against closed forms (a point light's 4 pi I, a directional
// light's E pi R², an area light's pi A Le, with a texture's average), and against quadrature: a
// spot's intensity, measured through sampleLi(), integrated over the sphere, and an area light's
// flux through a sphere around it as sampleLi() delivers it. Every statistical test has a fixed
// seed, and states why its tolerance is right.
#include "core/punctual_lights.h"
#include "core/sampling.h"
#include "core/triangle_light.h"
#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <ostream>
#include <random>
#include <string>
#include <vector>

namespace penumbra::test {
namespace {

// The closed forms below are single float products, so 1e-6 relative is rounding only.
constexpr float kProductTolerance = 1e-6f;

TEST(LightPower, PointLightIsFourPiI) {
    const PointLight light(punctual(PunctualType::Point, 120.0f, Color(1.0f, 0.5f, 0.25f)));
    expectColorNear(light.power(), 4.0f * kPi * 120.0f * Color(1.0f, 0.5f, 0.25f),
                    kProductTolerance);
}

struct SpotCone {
    const char* name;
    float inner, outer;  // radians
};

// How ctest names a case (`# GetParam() = ...`): by its cone, not by the bytes of the struct,
// which hold a pointer and so change from build to build.
void PrintTo(const SpotCone& cone, std::ostream* out) {
    *out << cone.name << " (" << cone.inner << ", " << cone.outer << " rad)";
}

class SpotPower : public testing::TestWithParam<SpotCone> {};

// Flux = integral of the intensity over the sphere, the intensity measured through sampleLi()
// from receivers at distance r (Li r² = I(w) for range 0), integrated in coordinates around the
// spot axis: x = cos theta by composite 3-point Gauss-Legendre, split where the falloff has a
// kink (the two cones, and the end of the spec's ramp when the cones are closer than 0.001 in
// cos), and phi by the midpoint rule.
TEST_P(SpotPower, MatchesTheIntegralOfItsIntensity) {
    const SpotCone& cone = GetParam();
    PunctualLightDesc desc = punctual(PunctualType::Spot, 80.0f, Color(1.0f, 0.6f, 0.2f));
    desc.innerConeAngle = cone.inner;
    desc.outerConeAngle = cone.outer;
    const SpotLight light(desc);

    const double cosOuter = std::cos(double(cone.outer)), cosInner = std::cos(double(cone.inner));
    std::vector<double> breaks = {-1.0, 1.0, cosOuter, cosInner, cosOuter + 0.001};
    std::erase_if(breaks, [](double x) { return x < -1.0 || x > 1.0; });
    std::sort(breaks.begin(), breaks.end());

    static const double kNodes[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    static const double kWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    constexpr int kPanels = 200, kPhi = 32;
    constexpr double kRadius = 2.0;
    const Frame frame = Frame::fromNormal(desc.direction);
    glm::dvec3 flux(0.0);
    for (size_t k = 0; k + 1 < breaks.size(); ++k) {
        const double h = (breaks[k + 1] - breaks[k]) / kPanels;
        for (int panel = 0; panel < kPanels; ++panel) {
            for (int node = 0; node < 3; ++node) {
                const double x = breaks[k] + h * (panel + 0.5 + 0.5 * kNodes[node]);
                const double sinTheta = std::sqrt(std::max(0.0, 1.0 - x * x));
                for (int j = 0; j < kPhi; ++j) {
                    const double phi = 2.0 * kPiD * (j + 0.5) / kPhi;
                    const Vec3 w = frame.toWorld(Vec3(float(sinTheta * std::cos(phi)),
                                                      float(sinTheta * std::sin(phi)), float(x)));
                    const LightSampleContext ctx{desc.position + float(kRadius) * w};
                    const std::optional<LightLiSample> s = light.sampleLi(ctx, Vec2(0.5f));
                    if (s) {
                        flux += glm::dvec3(s->L) * (kRadius * kRadius) * (0.5 * h) *
                                kWeights[node] * (2.0 * kPiD / kPhi);
                    }
                }
            }
        }
    }
    std::printf("[ measured ] power %.7g, quadrature %.7g (luminance), relative difference %.2g\n",
                luminance(light.power()), luminance(Color(flux)),
                relativeError(luminance(light.power()), luminance(Color(flux))));
    // The quadrature is exact for the piecewise-quadratic falloff in x; what is left is float
    // rounding of cos theta in intensity(), ~6e-8 against a ramp 1 / max(0.001, delta) wide:
    // measured <= 1e-6 relative for the wider cones (1e-5 allowed), 1.3e-3 for the 1-degree
    // cone, whose whole cap is 1.5e-4 wide in cos (3e-3 allowed).
    const double tolerance = (1.0 - cosOuter) < 0.01 ? 3e-3 : 1e-5;
    expectColorNear(light.power(), Color(flux), tolerance);
}

INSTANTIATE_TEST_SUITE_P(Cones, SpotPower,
                         testing::Values(SpotCone{"Default", 0.0f, kPi / 4.0f},
                                         SpotCone{"Soft", 0.3f, 0.5f}, SpotCone{"Wide", 0.2f, 1.5f},
                                         // cones closer than the spec's 0.001 in cos
                                         SpotCone{"NearlyHard", 0.5f, 0.5005f},
                                         // the whole cone inside 0.001 in cos
                                         SpotCone{"Narrow", 0.0f, 0.0175f}),
                         [](const testing::TestParamInfo<SpotCone>& info) {
                             return std::string(info.param.name);
                         });

TEST(LightPower, DirectionalLightIsEPiR2) {
    const DirectionalLight light(punctual(PunctualType::Directional, 3.0f, Color(1.0f, 0.9f, 0.8f)),
                                 Vec3(1.0f), 2.5f);
    expectColorNear(light.power(), 3.0f * kPi * 2.5f * 2.5f * Color(1.0f, 0.9f, 0.8f),
                    kProductTolerance);
}

TEST(LightPower, TriangleLightIsPiALe) {
    const Color Le(2.0f, 1.0f, 0.5f);
    EXPECT_NEAR(makeEmitter(false)->light->area(), 0.4f, 1e-7f);
    expectColorNear(makeEmitter(false)->light->power(), kPi * 0.4f * Le, kProductTolerance);
    expectColorNear(makeEmitter(true)->light->power(), 2.0f * kPi * 0.4f * Le, kProductTolerance);
}

TEST(LightPower, TexturedTriangleLightUsesTheTextureAverage) {
    const auto e = makeEmitter(false);
    addEmissionTexture(*e);
    e->light.emplace(e->mesh, 0, e->material, e->textures);
    expectColorNear(e->light->power(),
                    kPi * 0.4f * Color(2.0f, 1.0f, 0.5f) * Color(0.4f, 0.25f, 0.6f),
                    kProductTolerance);
}

// Power against the flux that sampleLi() delivers through a sphere around the triangle:
// Phi = integral over the sphere of the irradiance on its inner side, E(x) = integral of
// L cos theta_x, estimated with one light sample per uniformly chosen receiver. This checks
// the L and pdf of sampleLi() against power() end to end.
TEST(LightPower, TriangleLightFluxThroughAnEnclosingSphere) {
    for (bool doubleSided : {false, true}) {
        const auto e = makeEmitter(doubleSided);
        const Vec3 center = (e->vertex(0) + e->vertex(1) + e->vertex(2)) / 3.0f;
        constexpr double kRadius = 3.0;
        constexpr int kSamples = 1000000;
        std::mt19937 rng(doubleSided ? 53 : 59);
        std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
        glm::dvec3 sum(0.0), sum2(0.0);
        for (int i = 0; i < kSamples; ++i) {
            const Vec3 outward = sampleUniformSphere(Vec2(uniform(rng), uniform(rng)));
            const LightSampleContext ctx{center + float(kRadius) * outward, Vec3(0.0f), -outward};
            const std::optional<LightLiSample> s =
                e->light->sampleLi(ctx, Vec2(uniform(rng), uniform(rng)));
            if (!s)
                continue;
            const glm::dvec3 x = glm::dvec3(s->L) * double(glm::dot(s->wi, -outward)) /
                                 double(s->pdf) * (4.0 * kPiD * kRadius * kRadius);
            sum += x;
            sum2 += x * x;
        }
        const glm::dvec3 mean = sum / double(kSamples);
        const glm::dvec3 standardError =
            glm::sqrt((sum2 / double(kSamples) - mean * mean) / double(kSamples - 1));
        const Color power = e->light->power();
        std::printf("[ measured ] %s: power %.5f, flux %.5f +- %.5f (red)\n",
                    doubleSided ? "double-sided" : "one-sided", power.r, mean.r, standardError.r);
        // 4 standard errors of a mean of 1e6 samples (normal to high accuracy), measured at
        // 0.1 % of the flux.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], power[c], 4.0 * standardError[c]) << "channel " << c;
    }
}

}  // namespace
}  // namespace penumbra::test
