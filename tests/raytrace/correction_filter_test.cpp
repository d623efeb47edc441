// The reconstruction filter of the hybrid's correction (raytrace/correction_filter.h): it keeps a
// constant, averages noise down as a Gaussian of its width does (the effective number of pixels of
// a normalised 2D Gaussian of standard deviation sigma is 4 pi sigma^2), never mixes two surfaces
// whose normals differ, and its width follows sigma_1 N^(-1/6). Per pixel, the width SURE chooses
// beats the fixed width against the true image the test made. Under a time limit, the
// renderer's estimate of the reconstruction's cost counts the pixel pairs it weighs, and a
// limit narrows the filter just enough to fit.
#include "raytrace/correction_filter.h"

#include "core/camera.h"
#include "core/math.h"
#include "core/sampler.h"
#include "raytrace/image_renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <tuple>

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

// A true correction `truth` plus independent Gaussian noise of standard deviation `noise` (its
// mean's variance known exactly), on the flat guide.
struct NoisyCorrection {
    Image truth{kSize, kSize, {"R", "G", "B"}};
    Image mean{kSize, kSize, {"R", "G", "B"}};
    Image variance{kSize, kSize, {"R", "G", "B"}};

    NoisyCorrection(const std::function<float(int, int)>& value, float noise, unsigned seed) {
        std::mt19937 random(seed);
        std::normal_distribution<float> normal(0.0f, noise);
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                for (int c = 0; c < 3; ++c) {
                    truth.at(x, y, c) = value(x, y);
                    mean.at(x, y, c) = value(x, y) + normal(random);
                    variance.at(x, y, c) = noise * noise;
                }
            }
        }
    }
    NoisyImage view() const { return {mean, variance}; }

    // Mean squared error of a reconstruction against the truth, away from the image's border.
    double error(const Image& reconstruction) const {
        double sum = 0.0;
        int n = 0;
        for (int y = 4; y < kSize - 4; ++y)
            for (int x = 4; x < kSize - 4; ++x, ++n)
                for (int c = 0; c < 3; ++c)
                    sum += sqr(double(reconstruction.at(x, y, c)) - truth.at(x, y, c));
        return sum / n;
    }
};

// Noise over a constant: no width can add bias, so the widest candidate wins nearly everywhere,
// and the error is below the fixed width's. (The risks of the two widest candidates differ by
// about 3 v / (4 pi sigma^2) x 3/4 of a pixel's noise; averaged over the ~200 pixels of the
// widest filter, a SURE estimate's own noise is of that size, so a few pixels in a hundred still
// take sigma: their error is 4 times the widest's, not an error of their own.)
TEST(CorrectionFilter, ChoosesTheWidestWidthForNoiseOverAConstant) {
    const Guide guide;
    const NoisyCorrection image([](int, int) { return 0.2f; }, 1.0f, 7);
    const float sigma = 2.0f;
    const std::vector<float> widths = chooseFilterWidths(image.view(), guide.view(), sigma);
    int widest = 0, interior = 0;  // away from the border, where the windows are whole
    for (int y = 8; y < kSize - 8; ++y)
        for (int x = 8; x < kSize - 8; ++x, ++interior)
            widest += widths[size_t(y) * kSize + x] == 2.0f * sigma;
    EXPECT_GT(widest, 0.9 * interior);
    // 1 / (4 pi (2 sigma)^2) against 1 / (4 pi sigma^2) if all took the widest: a quarter.
    const double chosen = image.error(filterCorrection(image.mean, guide.view(), widths));
    const double fixed = image.error(filterCorrection(image.mean, guide.view(), sigma));
    EXPECT_LT(chosen, 0.5 * fixed);
}

// A narrow peak on one surface (no guide feature marks it) under faint noise: the filter of width
// sigma would spread it (bias), so the pixels on and next to it keep it narrower, and the error
// against the truth is below the fixed width's.
TEST(CorrectionFilter, KeepsANarrowPeakSharperThanTheFixedWidth) {
    const Guide guide;
    const auto peak = [](int x, int y) {
        return 4.0f * std::exp(-0.5f * float(sqr(x - 32) + sqr(y - 32)) / 1.5f);
    };
    const NoisyCorrection image(peak, 0.05f, 11);
    const float sigma = 3.0f;
    const std::vector<float> widths = chooseFilterWidths(image.view(), guide.view(), sigma);
    EXPECT_LT(widths[32 * kSize + 32], sigma);
    const double chosen = image.error(filterCorrection(image.mean, guide.view(), widths));
    const double fixed = image.error(filterCorrection(image.mean, guide.view(), sigma));
    EXPECT_LT(chosen, 0.5 * fixed);
}

// The choice is a multiple of sigma (0, 1/2, 1 or 2, the last capped at kWidestChosenSigma), so
// it vanishes as sigma does; where no pixel's variance is known (one sample each) it is sigma.
TEST(CorrectionFilter, ChoosesAmongMultiplesOfSigmaAndSigmaWhereNoVarianceIsKnown) {
    const Guide guide;
    NoisyCorrection image([](int x, int) { return x < kSize / 2 ? 0.0f : 1.0f; }, 0.3f, 3);
    for (const float sigma : {1.0f, 6.0f}) {
        const std::vector<float> widths = chooseFilterWidths(image.view(), guide.view(), sigma);
        const float widest = std::max(sigma, std::min(2.0f * sigma, kWidestChosenSigma));
        for (const float w : widths)
            EXPECT_TRUE(w == 0.0f || w == 0.5f * sigma || w == sigma || w == widest) << w;
    }
    for (float& v : image.variance.pixels())
        v = -1.0f;
    for (const float w : chooseFilterWidths(image.view(), guide.view(), 3.0f))
        EXPECT_EQ(w, 3.0f);
}

TEST(CorrectionFilter, WidthShrinksAsTheSixthRootOfTheSamples) {
    EXPECT_FLOAT_EQ(correctionFilterSigma(8.0f, 1.0), 8.0f);
    EXPECT_NEAR(correctionFilterSigma(8.0f, 64.0), 4.0f, 1e-5f);
    EXPECT_NEAR(correctionFilterSigma(8.0f, 4096.0), 2.0f, 1e-5f);
    EXPECT_FLOAT_EQ(correctionFilterSigma(8.0f, 0.0), 8.0f);  // before the first sample
}

// reconstructionVisits against the pairs counted window by window: the widest candidate,
// max(sigma, min(2 sigma, kWidestChosenSigma)), reaches ceil(2 x its width) pixels each way,
// clipped at the borders; two sweeps choose the widths, one per layer filters.
TEST(CorrectionFilter, CountsThePixelPairsItsSweepsWeigh) {
    for (const auto& [width, height, sigma] :
         {std::tuple{40, 24, 3.0f}, std::tuple{7, 50, 8.0f}, std::tuple{64, 64, 0.7f}}) {
        const float widest = std::max(sigma, std::min(2.0f * sigma, kWidestChosenSigma));
        const int reach = static_cast<int>(std::ceil(2.0f * widest));
        double pairs = 0.0;
        for (int y = 0; y < height; ++y) {
            for (int x = 0; x < width; ++x) {
                for (int qy = y - reach; qy <= y + reach; ++qy)
                    for (int qx = x - reach; qx <= x + reach; ++qx)
                        pairs += qx >= 0 && qx < width && qy >= 0 && qy < height;
            }
        }
        EXPECT_DOUBLE_EQ(reconstructionVisits(width, height, sigma, 3), 5.0 * pairs)
            << width << " x " << height << ", sigma " << sigma;
    }
    EXPECT_EQ(reconstructionVisits(64, 64, 0.2f, 1), 0.0);  // no filter below a quarter pixel
    const double seconds = secondsPerReconstructionVisit();
    EXPECT_GT(seconds, 0.0);
    EXPECT_LT(seconds, 1e-5);
}

// A renderer with a correction kept apart (sigma 8 at one sample) estimates its reconstruction
// by the pairs counted above; a limit narrows the filter by fifths until the estimate fits (one
// fifth less would not), and a limit of nothing leaves the per-pixel means as they are.
TEST(CorrectionFilter, ATimeLimitNarrowsTheRenderersFilterJustEnough) {
    RenderSettings settings;
    settings.width = 48;
    settings.height = 32;
    const Camera camera(CameraDesc{}, settings.width, settings.height);
    ImageRenderer renderer(
        camera, settings,
        [](const Ray&, Sampler& sampler, FirstHit*, PathCounters&) {
            const Color correction(sampler.get1D());
            PathRadiance L;
            L[PathComponent::Indirect] = correction;
            L.corrections[static_cast<size_t>(PathComponent::Indirect)] = correction;
            return L;
        },
        8.0f);
    renderer.renderSamplePass();
    const double full = renderer.reconstructionSeconds();
    EXPECT_DOUBLE_EQ(full, reconstructionVisits(48, 32, 8.0f, 1) * secondsPerReconstructionVisit());

    renderer.limitReconstruction(full / 4.0);
    const float narrowed = renderer.correctionSigma();
    EXPECT_LT(narrowed, 8.0f);
    EXPECT_LE(renderer.reconstructionSeconds(), full / 4.0);
    EXPECT_GT(reconstructionVisits(48, 32, narrowed / 0.8f, 1) * secondsPerReconstructionVisit(),
              full / 4.0);

    renderer.limitReconstruction(0.0);
    EXPECT_EQ(renderer.reconstructionSeconds(), 0.0);
    const Image raw = renderer.film().resolve();
    const Image shown = renderer.resolve();
    EXPECT_TRUE(std::equal(raw.pixels().begin(), raw.pixels().end(), shown.pixels().begin()));
}

}  // namespace
}  // namespace penumbra::test
