// Warps and the alias table: closed-form properties.
#include "core/sampling.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace penumbra {
namespace {

TEST(AliasTable, FrequenciesMatchWeightsAndZeroWeightsAreNeverChosen) {
    const std::vector<float> weights = {1.0f, 0.0f, 3.0f, 6.0f};
    const AliasTable table(weights);
    EXPECT_FLOAT_EQ(table.pmf(0), 0.1f);
    EXPECT_FLOAT_EQ(table.pmf(1), 0.0f);
    EXPECT_FLOAT_EQ(table.pmf(2), 0.3f);
    EXPECT_FLOAT_EQ(table.pmf(3), 0.6f);
    // A stratified sweep of u reproduces the pmf up to the sweep resolution.
    constexpr int kSteps = 100000;
    std::vector<int> counts(weights.size(), 0);
    for (int i = 0; i < kSteps; ++i)
        counts[table.sample((i + 0.5f) / kSteps)]++;
    EXPECT_EQ(counts[1], 0);
    for (size_t i = 0; i < weights.size(); ++i) {
        EXPECT_NEAR(counts[i] / double(kSteps), table.pmf(i), 1e-3) << "index " << i;
    }
}

TEST(AliasTable, AllZeroWeightsGiveAnEmptyTable) {
    const std::vector<float> weights = {0.0f, 0.0f};
    EXPECT_TRUE(AliasTable(weights).empty());
}

TEST(Warps, CosineHemisphereStaysOnTheUnitUpperHemisphere) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    double meanCos = 0.0;
    constexpr int kSamples = 200000;
    for (int i = 0; i < kSamples; ++i) {
        const Vec3 w = sampleCosineHemisphere({uniform(rng), uniform(rng)});
        ASSERT_NEAR(glm::length(w), 1.0f, 1e-5f);
        ASSERT_GE(w.z, 0.0f);
        meanCos += w.z;
    }
    // E[cos theta] under pdf cos/pi is 2/3; the standard error at 2e5 samples is ~5e-4.
    EXPECT_NEAR(meanCos / kSamples, 2.0 / 3.0, 3e-3);
}

TEST(Warps, UniformTriangleIsHeitzsMap) {
    // Heitz 2019, Eq. 3, as written there: two cases split by the diagonal u.x = u.y. Every u a
    // sampler gives is a multiple of 2^-24 (core/sampler.cpp, toUnitFloat).
    for (int i = 0; i < 97; ++i) {
        for (int j = 0; j < 97; ++j) {
            const Vec2 u(float(i * 172933) * 0x1p-24f, float(j * 172933) * 0x1p-24f);
            float b0, b1;
            if (u.x < u.y) {
                b0 = u.x / 2.0f;
                b1 = u.y - b0;
            } else {
                b1 = u.y / 2.0f;
                b0 = u.x - b1;
            }
            const Vec3 b = sampleUniformTriangle(u);
            ASSERT_EQ(b.x, b0) << u.x << " " << u.y;
            ASSERT_EQ(b.y, b1) << u.x << " " << u.y;
            ASSERT_EQ(b.z, 1.0f - b0 - b1) << u.x << " " << u.y;
        }
    }
}

TEST(Warps, UniformTriangleBarycentricsHaveMeanOneThird) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    Vec3 mean(0.0f);
    constexpr int kSamples = 200000;
    for (int i = 0; i < kSamples; ++i) {
        const Vec3 b = sampleUniformTriangle({uniform(rng), uniform(rng)});
        ASSERT_GE(glm::min(b.x, glm::min(b.y, b.z)), -1e-6f);
        ASSERT_NEAR(b.x + b.y + b.z, 1.0f, 1e-6f);
        mean += b;
    }
    mean /= float(kSamples);
    // Each barycentric has variance 1/18; standard error ~5e-4.
    EXPECT_NEAR(mean.x, 1.0f / 3.0f, 3e-3f);
    EXPECT_NEAR(mean.y, 1.0f / 3.0f, 3e-3f);
}

// The cdf of weights 1, 0, 3 is 0, 1/4, 1/4, 1 by hand; u = 0.1 falls 0.4 into entry 0, u = 0.5
// a third into entry 2, and entry 1 (weight 0) is never found.
TEST(Cdf, FillsAndInvertsByHand) {
    const std::vector<double> weights = {1.0, 0.0, 3.0};
    std::vector<double> cdf(4);
    EXPECT_EQ(fillCdf(std::span<const double>(weights), cdf), 4.0);
    EXPECT_EQ(cdf, (std::vector<double>{0.0, 0.25, 0.25, 1.0}));
    const CdfEntry first = invertCdf(std::span<const double>(cdf), 0.1);
    EXPECT_EQ(first.index, 0u);
    EXPECT_NEAR(first.remainder, 0.4, 1e-12);
    const CdfEntry last = invertCdf(std::span<const double>(cdf), 0.5);
    EXPECT_EQ(last.index, 2u);
    EXPECT_NEAR(last.remainder, 1.0 / 3.0, 1e-12);
    EXPECT_EQ(invertCdf(std::span<const double>(cdf), 0.25).index, 2u);
    // No weight at all: a uniform cdf, so that a caller that gives it no probability still
    // draws valid entries.
    const std::vector<float> none(4, 0.0f);
    std::vector<float> uniform(5);
    EXPECT_EQ(fillCdf(std::span<const float>(none), uniform), 0.0);
    EXPECT_EQ(uniform, (std::vector<float>{0.0f, 0.25f, 0.5f, 0.75f, 1.0f}));
    EXPECT_EQ(invertCdf(std::span<const float>(uniform), 0.99).index, 3u);
}

}  // namespace
}  // namespace penumbra
