// The reconstruction filter of the hybrid's correction (raytrace/correction_filter.h): it keeps a
// constant, averages noise down as a Gaussian of its width does (the effective number of pixels of
// a normalised 2D Gaussian of standard deviation sigma is 4 pi sigma^2), never mixes two surfaces
// whose normals differ, and its width follows sigma_1 N^(-1/6).
#include "raytrace/correction_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace penumbra::test {
namespace {

constexpr int kSize = 64;

// Guide images of one flat surface facing +z at depth 2 with albedo 0.5, or with the right half
// turned to face +x.
struct Guide {
    Image normal{kSize, kSize, {"X", "Y", "Z"}};
    Image depth{kSize, kSize, {"Z"}};
    Image albedo{kSize, kSize, {"R", "G", "B"}};

    explicit Guide(bool creased = false) {
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                const bool right = creased && x >= kSize / 2;
                normal.at(x, y, right ? 0 : 2) = 1.0f;
                depth.at(x, y, 0) = 2.0f;
                for (int c = 0; c < 3; ++c)
                    albedo.at(x, y, c) = 0.5f;
            }
        }
    }
    FilterGuide view() const { return {normal, depth, albedo}; }
};

Image filled(float value) {
    Image image(kSize, kSize, {"R", "G", "B"});
    for (float& v : image.pixels())
        v = value;
    return image;
}

TEST(CorrectionFilter, KeepsAConstant) {
    const Guide guide;
    const Image filtered = filterCorrection(filled(-0.3f), guide.view(), 4.0f);
    for (const float v : filtered.pixels())
        EXPECT_NEAR(v, -0.3f, 1e-6f);
}

TEST(CorrectionFilter, BelowAQuarterPixelChangesNothing) {
    const Guide guide;
    Image image = filled(0.0f);
    image.at(3, 4, 1) = 7.0f;
    const Image filtered = filterCorrection(image, guide.view(), 0.2f);
    EXPECT_EQ(filtered.at(3, 4, 1), 7.0f);
    EXPECT_EQ(filtered.at(4, 4, 1), 0.0f);
}

// Independent noise of variance 1 on one surface: away from the borders, the filtered variance is
// about 1 / (4 pi sigma^2) (the sum of the squared normalised Gaussian weights).
TEST(CorrectionFilter, AveragesNoiseDownAsAGaussianOfItsWidth) {
    const Guide guide;
    Image noise(kSize, kSize, {"R", "G", "B"});
    std::mt19937 random(5);
    std::normal_distribution<float> normal;
    for (float& v : noise.pixels())
        v = normal(random);
    const float sigma = 3.0f;
    const Image filtered = filterCorrection(noise, guide.view(), sigma);
    double sum = 0.0, sumSquares = 0.0;
    int n = 0;
    for (int y = 8; y < kSize - 8; ++y) {
        for (int x = 8; x < kSize - 8; ++x) {
            const double v = filtered.at(x, y, 0);
            sum += v;
            sumSquares += v * v;
            ++n;
        }
    }
    const double variance = sumSquares / n - (sum / n) * (sum / n);
    const double expected = 1.0 / (4.0 * std::numbers::pi * sigma * sigma);
    // The window ends at 2 sigma, which leaves out 14 % of the weight and makes the variance a
    // little larger; the sample variance of 2304 correlated pixels is itself within about 20 %.
    EXPECT_GT(variance, 0.7 * expected);
    EXPECT_LT(variance, 1.6 * expected);
}

// Two halves at a crease (normals 90 degrees apart) with different corrections stay apart.
TEST(CorrectionFilter, DoesNotMixSurfacesAcrossACrease) {
    const Guide guide(true);
    Image image(kSize, kSize, {"R", "G", "B"});
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            image.at(x, y, 0) = x < kSize / 2 ? 1.0f : -1.0f;
    const Image filtered = filterCorrection(image, guide.view(), 6.0f);
    EXPECT_NEAR(filtered.at(kSize / 2 - 1, 10, 0), 1.0f, 1e-4f);
    EXPECT_NEAR(filtered.at(kSize / 2, 10, 0), -1.0f, 1e-4f);
}

TEST(CorrectionFilter, WidthShrinksAsTheSixthRootOfTheSamples) {
    EXPECT_FLOAT_EQ(correctionFilterSigma(8.0f, 1.0), 8.0f);
    EXPECT_NEAR(correctionFilterSigma(8.0f, 64.0), 4.0f, 1e-5f);
    EXPECT_NEAR(correctionFilterSigma(8.0f, 4096.0), 2.0f, 1e-5f);
    EXPECT_FLOAT_EQ(correctionFilterSigma(8.0f, 0.0), 8.0f);  // before the first sample
}

}  // namespace
}  // namespace penumbra::test
