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

}  // namespace
}  // namespace penumbra
