// Power-proportional light selection (PowerLightSampler): its pmf against the lights' luminance
// of power() exactly, a stratified sweep of u against the pmf, random choices against it
// (chi-square), and lights without power never chosen. Every statistical test has a fixed seed,
// and states why its tolerance is right.
#include "core/light_sampler.h"
#include "core/punctual_lights.h"
#include "core/triangle_light.h"
#include "tests/support/chi2.h"
#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <random>
#include <vector>

namespace penumbra::test {
namespace {

// Eight lights (a power of two, so that u * 8 is exact in the sweep below), two without power.
struct LightSet {
    std::unique_ptr<Emitter> emitter = makeEmitter(true);
    std::vector<std::unique_ptr<Light>> lights;

    LightSet() {
        lights.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 0.0f)));
        lights.push_back(std::make_unique<PointLight>(
            punctual(PunctualType::Point, 10.0f, Color(1.0f, 0.5f, 0.2f))));
        lights.push_back(std::make_unique<SpotLight>(punctual(PunctualType::Spot, 50.0f)));
        lights.push_back(std::make_unique<DirectionalLight>(
            punctual(PunctualType::Directional, 3.0f, Color(0.2f, 0.3f, 1.0f)), Vec3(0.0f), 2.0f));
        lights.push_back(std::make_unique<TriangleLight>(emitter->mesh, 0, emitter->material,
                                                         emitter->textures));
        lights.push_back(std::make_unique<PointLight>(
            punctual(PunctualType::Point, 1.0f, Color(0.0f))));  // black: no power
        lights.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 0.02f)));
        lights.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 200.0f)));
    }

    std::vector<double> expectedPmf() const {
        std::vector<double> pmf;
        double total = 0.0;
        for (const auto& light : lights) {
            pmf.push_back(luminance(light->power()));
            total += pmf.back();
        }
        for (double& p : pmf)
            p /= total;
        return pmf;
    }
};

TEST(PowerLightSampler, PmfIsProportionalToLuminanceOfPower) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const std::vector<double> expected = set.expectedPmf();
    double sum = 0.0;
    for (uint32_t i = 0; i < set.lights.size(); ++i) {
        // The pmf is computed in double and stored as float: 1e-6 relative.
        EXPECT_NEAR(sampler.pmf(i), expected[i], 1e-6 * expected[i]) << i;
        sum += sampler.pmf(i);
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    EXPECT_EQ(sampler.pmf(0), 0.0f);
    EXPECT_EQ(sampler.pmf(5), 0.0f);
}

TEST(PowerLightSampler, StratifiedSweepReproducesThePmf) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const size_t n = set.lights.size();
    // u = (k + 1/2) / (n K): every alias-table bin receives exactly K evenly spaced values, so
    // each bin's split between its own light and its alias is exact to 1/K of the bin, and a
    // light, touched by at most n bins of weight 1/n, is off by at most 1/K. The float
    // thresholds add 1e-7.
    constexpr int kPerBin = 1 << 17;
    const int count = int(n) * kPerBin;
    std::vector<double> frequency(n, 0.0);
    for (int k = 0; k < count; ++k) {
        const std::optional<PowerLightSampler::Choice> choice =
            sampler.sample((float(k) + 0.5f) / float(count));
        ASSERT_TRUE(choice);
        EXPECT_EQ(choice->pmf, sampler.pmf(choice->light));
        frequency[choice->light] += 1.0 / count;
    }
    for (uint32_t i = 0; i < n; ++i)
        EXPECT_NEAR(frequency[i], sampler.pmf(i), 1.0 / kPerBin + 1e-6) << i;
    EXPECT_EQ(frequency[0], 0.0);
    EXPECT_EQ(frequency[5], 0.0);
}

TEST(PowerLightSampler, RandomSamplesPassChiSquare) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const size_t n = set.lights.size();
    constexpr int kSamples = 1000000;
    std::mt19937 rng(71);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<double> observed(n, 0.0);
    for (int i = 0; i < kSamples; ++i)
        observed[sampler.sample(uniform(rng))->light] += 1.0;
    // Pearson's statistic over the lights with power (all expect >= 5 samples); the others
    // must never be chosen. 1 % level, a single test.
    double statistic = 0.0;
    int dof = -1;
    for (uint32_t i = 0; i < n; ++i) {
        const double expected = kSamples * double(sampler.pmf(i));
        if (expected == 0.0) {
            EXPECT_EQ(observed[i], 0.0) << i;
            continue;
        }
        ASSERT_GE(expected, 5.0);
        statistic += (observed[i] - expected) * (observed[i] - expected) / expected;
        ++dof;
    }
    const double pValue = regularizedGammaQ(0.5 * dof, 0.5 * statistic);
    std::printf("[ measured ] chi-square %.2f, %d dof, p = %.3f\n", statistic, dof, pValue);
    EXPECT_GE(pValue, 0.01);
}

TEST(PowerLightSampler, ZeroPowerLightsAreNeverChosenEvenAtBinEdges) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const float n = float(set.lights.size());
    std::vector<float> us = {0.0f, 0.99999994f, std::nextafter(1.0f, 0.0f)};
    for (int k = 1; k < int(n); ++k) {
        us.push_back(float(k) / n);
        us.push_back(std::nextafter(float(k) / n, 0.0f));
        us.push_back(std::nextafter(float(k) / n, 1.0f));
    }
    for (float u : us) {
        const std::optional<PowerLightSampler::Choice> choice = sampler.sample(u);
        ASSERT_TRUE(choice);
        EXPECT_GT(choice->pmf, 0.0f) << u;
    }
}

TEST(PowerLightSampler, NoLightsOrNoPowerGivesNothing) {
    const std::vector<std::unique_ptr<Light>> none;
    const PowerLightSampler empty(none);
    EXPECT_FALSE(empty.sample(0.5f));

    std::vector<std::unique_ptr<Light>> dark;
    dark.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 0.0f)));
    dark.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 5.0f, Color(0.0f))));
    const PowerLightSampler sampler(dark);
    EXPECT_FALSE(sampler.sample(0.0f));
    EXPECT_FALSE(sampler.sample(0.7f));
    EXPECT_EQ(sampler.pmf(0), 0.0f);
}

}  // namespace
}  // namespace penumbra::test
