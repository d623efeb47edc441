// Image-difference metrics (core/image_metrics.h) against closed forms and an independent
// brute-force SSIM, and the heat map's colours and legend (core/heatmap.h).
#include "core/image_metrics.h"
#include "core/errors.h"
#include "core/heatmap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

namespace penumbra {
namespace {

constexpr double kEps = 1e-2;  // the default eps of relMSE

Image makeImage(int width, int height, std::vector<std::string> channels,
                const std::function<float(int, int, int)>& value) {
    Image image(width, height, std::move(channels));
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < image.channels(); ++c)
                image.at(x, y, c) = value(x, y, c);
        }
    }
    return image;
}

// A deterministic textured RGB image with values in [0.05, 2.05): HDR, no two pixels alike.
Image texture(int width, int height) {
    return makeImage(width, height, {"R", "G", "B"}, [](int x, int y, int c) {
        return 0.05f + float(std::fmod(0.37 * x + 0.61 * y * y + 0.23 * c + 0.11 * x * y, 2.0));
    });
}

const MetricValues& row(const MetricReport& report, const std::string& name) {
    const int index = report.rowIndex(name);
    EXPECT_GE(index, 0) << "no row " << name;
    return report.rows.at(size_t(index));
}

TEST(ImageMetrics, IdenticalImagesHaveNoError) {
    const Image image = texture(23, 17);
    const MetricReport report = computeMetrics(image, image, nullptr, {});
    ASSERT_EQ(report.rowNames, (std::vector<std::string>{"R", "G", "B", "luminance", "all"}));
    for (const MetricValues& values : report.rows) {
        EXPECT_EQ(values[Metric::Rmse], 0.0);
        EXPECT_EQ(values[Metric::RelMse], 0.0);
        EXPECT_EQ(values[Metric::Mae], 0.0);
        EXPECT_EQ(values[Metric::Mre], 0.0);
        EXPECT_EQ(values[Metric::Psnr], std::numeric_limits<double>::infinity());
        EXPECT_NEAR(values[Metric::Ssim], 1.0, 1e-12);
    }
    EXPECT_EQ(report.comparedPixels, 23u * 17u);
    EXPECT_EQ(report.testNonFinite + report.referenceNonFinite, 0u);
}

TEST(ImageMetrics, ConstantOffsetGivesClosedForms) {
    // y = 0.5, x = 0.75 everywhere (both exact in float): every per-pixel term is the same.
    const Image reference = makeImage(8, 6, {"R", "G", "B"}, [](int, int, int) { return 0.5f; });
    const Image test = makeImage(8, 6, {"R", "G", "B"}, [](int, int, int) { return 0.75f; });
    MetricOptions options;
    options.ssimInput = SsimInput::Display;
    const MetricReport report = computeMetrics(test, reference, nullptr, options);
    for (const MetricValues& values : report.rows) {
        EXPECT_DOUBLE_EQ(values[Metric::Rmse], 0.25);
        EXPECT_DOUBLE_EQ(values[Metric::Mae], 0.25);
        EXPECT_NEAR(values[Metric::RelMse], 0.0625 / (0.25 + kEps), 1e-12);  // sum of 48 terms
        EXPECT_NEAR(values[Metric::Mre], 0.25 / std::sqrt(0.25 + kEps), 1e-12);
        // Peak = the reference's maximum, 0.5: 10 log10(0.25 / 0.0625) = 6.0206 dB.
        EXPECT_NEAR(values[Metric::Psnr], 10.0 * std::log10(4.0), 1e-12);
        // Constant images: sigma = 0, so SSIM = (2 x y + C1) / (x^2 + y^2 + C1), C1 = 1e-4.
        EXPECT_NEAR(values[Metric::Ssim], (2 * 0.75 * 0.5 + 1e-4) / (0.75 * 0.75 + 0.25 + 1e-4),
                    1e-12);
    }
    EXPECT_DOUBLE_EQ(report.peak, 0.5);

    // HDR input: SSIM on v / (1 + v).
    const MetricReport hdr = computeMetrics(test, reference, nullptr, {});
    const double xt = 0.75 / 1.75, yt = 0.5 / 1.5;
    EXPECT_NEAR(row(hdr, "all")[Metric::Ssim], (2 * xt * yt + 1e-4) / (xt * xt + yt * yt + 1e-4),
                1e-12);
}

TEST(ImageMetrics, ScaleGivesRelativeMseOfItsSquare) {
    // x = (1 + a) y: relMSE = mean a^2 y^2 / (y^2 + eps), computed here independently.
    const double a = 0.1;
    const Image reference = texture(31, 9);
    Image test = reference;
    for (float& v : test.pixels())
        v = float(v * (1.0 + a));
    double expected = 0.0, expectedRed = 0.0;
    for (int y = 0; y < 9; ++y) {
        for (int x = 0; x < 31; ++x) {
            for (int c = 0; c < 3; ++c) {
                const double r = reference.at(x, y, c), t = test.at(x, y, c);
                const double term = (t - r) * (t - r) / (r * r + kEps);
                expected += term;
                expectedRed += c == 0 ? term : 0.0;
                // The closed form, up to float rounding of x.
                EXPECT_NEAR(term, a * a * r * r / (r * r + kEps), 1e-6);
            }
        }
    }
    const MetricReport report = computeMetrics(test, reference, nullptr, {});
    EXPECT_NEAR(row(report, "all")[Metric::RelMse], expected / (31 * 9 * 3), 1e-12);
    EXPECT_NEAR(row(report, "R")[Metric::RelMse], expectedRed / (31 * 9), 1e-12);
    // MRE is the mean of the square roots of relMSE's terms: MRE^2 <= relMSE (Jensen), close to
    // a here since y^2 >> eps for most pixels.
    const double mre = row(report, "all")[Metric::Mre];
    EXPECT_LE(mre * mre, row(report, "all")[Metric::RelMse]);
    EXPECT_NEAR(mre, a, 0.02);
}

TEST(ImageMetrics, LuminanceUsesRec709Weights) {
    const Image reference = texture(12, 10);
    Image test = reference;
    for (int y = 0; y < 10; ++y) {
        for (int x = 0; x < 12; ++x) {
            test.at(x, y, 0) += 0.5f;   // red only
            test.at(x, y, 2) -= 0.25f;  // and blue
        }
    }
    const MetricReport report = computeMetrics(test, reference, nullptr, {});
    EXPECT_NEAR(row(report, "luminance")[Metric::Mae], 0.2126 * 0.5 - 0.0722 * 0.25, 1e-6);
    EXPECT_NEAR(row(report, "G")[Metric::Rmse], 0.0, 1e-12);
    EXPECT_NEAR(row(report, "R")[Metric::Rmse], 0.5, 1e-6);
    // "all" pools the channels: MSE (0.25 + 0 + 0.0625) / 3.
    EXPECT_NEAR(row(report, "all")[Metric::Rmse], std::sqrt(0.3125 / 3.0), 1e-6);
}

// SSIM by the definition (Wang et al. 2004, eq. 13-16), with a direct 2D Gaussian window
// renormalised inside the image: an independent check of the separable implementation.
double bruteForceSsim(const Image& test, const Image& reference, int channel) {
    double total = 0.0;
    for (int py = 0; py < test.height(); ++py) {
        for (int px = 0; px < test.width(); ++px) {
            double w = 0, mx = 0, my = 0;
            for (int y = std::max(0, py - 5); y <= std::min(test.height() - 1, py + 5); ++y) {
                for (int x = std::max(0, px - 5); x <= std::min(test.width() - 1, px + 5); ++x) {
                    const double g =
                        std::exp(-((x - px) * (x - px) + (y - py) * (y - py)) / (2 * 1.5 * 1.5));
                    w += g;
                    mx += g * test.at(x, y, channel);
                    my += g * reference.at(x, y, channel);
                }
            }
            mx /= w;
            my /= w;
            double vx = 0, vy = 0, cxy = 0;
            for (int y = std::max(0, py - 5); y <= std::min(test.height() - 1, py + 5); ++y) {
                for (int x = std::max(0, px - 5); x <= std::min(test.width() - 1, px + 5); ++x) {
                    const double g =
                        std::exp(-((x - px) * (x - px) + (y - py) * (y - py)) / (2 * 1.5 * 1.5)) /
                        w;
                    const double dx = test.at(x, y, channel) - mx;
                    const double dy = reference.at(x, y, channel) - my;
                    vx += g * dx * dx;
                    vy += g * dy * dy;
                    cxy += g * dx * dy;
                }
            }
            total += (2 * mx * my + 1e-4) * (2 * cxy + 9e-4) /
                     ((mx * mx + my * my + 1e-4) * (vx + vy + 9e-4));
        }
    }
    return total / (test.width() * test.height());
}

TEST(ImageMetrics, SsimMatchesTheDefinition) {
    // Display values in [0, 1]: a pattern and a distorted copy (blurred contrast, noise-like
    // offsets), so that luminance, contrast and structure terms all differ from 1.
    const Image reference = makeImage(19, 14, {"Y"}, [](int x, int y, int) {
        return float(0.5 + 0.4 * std::sin(0.9 * x) * std::cos(0.7 * y));
    });
    const Image test = makeImage(19, 14, {"Y"}, [](int x, int y, int) {
        return float(0.45 + 0.25 * std::sin(0.9 * x + 0.3) * std::cos(0.7 * y) +
                     0.05 * std::fmod(x * 7 + y * 3, 5) / 5.0);
    });
    MetricOptions options;
    options.ssimInput = SsimInput::Display;
    const MetricReport report = computeMetrics(test, reference, nullptr, options);
    ASSERT_EQ(report.rowNames, (std::vector<std::string>{"Y", "all"}));
    const double expected = bruteForceSsim(test, reference, 0);
    EXPECT_LT(expected, 0.95);  // a real distortion, not a trivial pair
    EXPECT_NEAR(row(report, "Y")[Metric::Ssim], expected, 1e-9);
}

TEST(ImageMetrics, MaskGivesMeanOfRegionMeans) {
    // 4 x 2: mask 0 on the left half (4 pixels), 1 on the right half (4 pixels). Errors: the
    // left half all off by 0.5; on the right only one pixel, by 1.0.
    const Image reference = makeImage(4, 2, {"Y"}, [](int, int, int) { return 1.0f; });
    const Image test = makeImage(4, 2, {"Y"}, [](int x, int y, int) {
        return x < 2 ? 1.5f : (x == 3 && y == 1 ? 2.0f : 1.0f);
    });
    const Image mask = makeImage(4, 2, {"Y"}, [](int x, int, int) { return x < 2 ? 0.0f : 1.0f; });
    const MetricReport report = computeMetrics(test, reference, &mask, {});
    ASSERT_EQ(report.regions.size(), 2u);
    EXPECT_EQ(report.regions[0].maskValue, 0.0f);
    EXPECT_EQ(report.regions[1].maskValue, 1.0f);
    EXPECT_EQ(report.regions[0].pixels, 4u);
    EXPECT_EQ(report.regions[1].pixels, 4u);
    // Region MAEs 0.5 and 0.25; region MSEs 0.25 and 0.25; relMSE 0.25/1.01 and 0.25/1.01.
    EXPECT_DOUBLE_EQ(report.regions[0].rows[0][Metric::Mae], 0.5);
    EXPECT_DOUBLE_EQ(report.regions[1].rows[0][Metric::Mae], 0.25);
    EXPECT_DOUBLE_EQ(row(report, "all")[Metric::Mae], 0.375);
    EXPECT_DOUBLE_EQ(row(report, "all")[Metric::Rmse], 0.5);
    EXPECT_DOUBLE_EQ(row(report, "all")[Metric::RelMse], 0.25 / (1.0 + kEps));

    // Unequal regions count equally: a 1-pixel region weighs as much as a 7-pixel one.
    const Image corner =
        makeImage(4, 2, {"Y"}, [](int x, int y, int) { return x == 3 && y == 1 ? 1.0f : 0.0f; });
    const MetricReport unequal = computeMetrics(test, reference, &corner, {});
    ASSERT_EQ(unequal.regions.size(), 2u);
    EXPECT_EQ(unequal.regions[1].pixels, 1u);
    // Regions: 7 pixels with MAE 4 x 0.5 / 7, and the corner with MAE 1.
    EXPECT_DOUBLE_EQ(row(unequal, "all")[Metric::Mae], (2.0 / 7.0 + 1.0) / 2.0);
}

TEST(ImageMetrics, DownsamplingAveragesBlocksExactly) {
    // 5 x 3 with values x + 10 y: 2 x 2 blocks give a 3 x 2 image; the edge blocks average the
    // pixels they cover.
    const Image image = makeImage(5, 3, {"V"}, [](int x, int y, int) { return float(x + 10 * y); });
    const Image blocks = downsampleBlocks(image, 2);
    ASSERT_EQ(blocks.width(), 3);
    ASSERT_EQ(blocks.height(), 2);
    EXPECT_EQ(blocks.at(0, 0, 0), (0 + 1 + 10 + 11) / 4.0f);
    EXPECT_EQ(blocks.at(1, 0, 0), (2 + 3 + 12 + 13) / 4.0f);
    EXPECT_EQ(blocks.at(2, 0, 0), (4 + 14) / 2.0f);
    EXPECT_EQ(blocks.at(0, 1, 0), (20 + 21) / 2.0f);
    EXPECT_EQ(blocks.at(2, 1, 0), 24.0f);

    // Zero-mean noise that cancels within each 2 x 2 block disappears from the metrics.
    const Image reference = texture(16, 8);
    Image test = reference;
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 16; ++x) {
            for (int c = 0; c < 3; ++c)
                test.at(x, y, c) += (x + y) % 2 ? 0.125f : -0.125f;
        }
    }
    MetricOptions options;
    EXPECT_NEAR(row(computeMetrics(test, reference, nullptr, options), "all")[Metric::Rmse], 0.125,
                1e-6);
    options.downsample = 2;
    const MetricReport blocked = computeMetrics(test, reference, nullptr, options);
    EXPECT_EQ(blocked.width, 8);
    EXPECT_EQ(blocked.height, 4);
    EXPECT_NEAR(row(blocked, "all")[Metric::Rmse], 0.0, 1e-6);
}

TEST(ImageMetrics, MaskBlocksThatStraddleRegionsAreLeftOut) {
    const Image image = texture(6, 4);
    // Region boundary at x = 3: with 2 x 2 blocks, the blocks of columns 2-3 are mixed.
    const Image mask = makeImage(6, 4, {"Y"}, [](int x, int, int) { return x < 3 ? 0.0f : 1.0f; });
    MetricOptions options;
    options.downsample = 2;
    const MetricReport report = computeMetrics(image, image, &mask, options);
    EXPECT_EQ(report.mixedBlocks, 2u);
    ASSERT_EQ(report.regions.size(), 2u);
    EXPECT_EQ(report.regions[0].pixels, 2u);
    EXPECT_EQ(report.regions[1].pixels, 2u);
}

TEST(ImageMetrics, NonFinitePixelsAreCountedAndLeftOut) {
    const Image reference = texture(10, 10);
    Image test = reference;
    for (int x = 0; x < 10; ++x)
        test.at(x, 5, 1) += 0.25f;  // a known error on row 5
    Image poisonedTest = test, poisonedReference = reference;
    poisonedTest.at(2, 3, 0) = std::numeric_limits<float>::quiet_NaN();
    poisonedTest.at(2, 4, 1) = std::numeric_limits<float>::infinity();
    poisonedReference.at(7, 7, 2) = -std::numeric_limits<float>::infinity();
    Image errorMap;
    const MetricReport report =
        computeMetrics(poisonedTest, poisonedReference, nullptr, {}, &errorMap);
    EXPECT_EQ(report.testNonFinite, 2u);
    EXPECT_EQ(report.referenceNonFinite, 1u);
    EXPECT_EQ(report.comparedPixels, 97u);
    // The rest is compared as usual: ten pixels off by 0.25 in G among the 97.
    EXPECT_NEAR(row(report, "G")[Metric::Mae], 10 * 0.25 / 97.0, 1e-7);
    EXPECT_TRUE(std::isfinite(row(report, "all")[Metric::Ssim]));
    // The error map: NaN where left out, the relMSE term elsewhere.
    EXPECT_TRUE(std::isnan(errorMap.at(2, 3, 0)));
    EXPECT_TRUE(std::isnan(errorMap.at(7, 7, 0)));
    EXPECT_EQ(errorMap.at(0, 0, 0), 0.0f);
    const double g = reference.at(4, 5, 1);
    EXPECT_NEAR(errorMap.at(4, 5, 0), 0.0625 / (g * g + kEps) / 3.0, 1e-6);
}

TEST(ImageMetrics, RefusesImagesThatCannotBeCompared) {
    MetricOptions options;
    options.testName = "a.exr";
    options.referenceName = "b.exr";
    const auto message = [&](const Image& test, const Image& reference, const Image* mask) {
        try {
            computeMetrics(test, reference, mask, options);
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_EQ(message(texture(4, 4), texture(4, 5), nullptr),
              "a.exr (4 x 4) and b.exr (4 x 5) differ in size");
    const Image grey = makeImage(4, 4, {"Y"}, [](int, int, int) { return 0.5f; });
    EXPECT_EQ(message(grey, texture(4, 4), nullptr), "a.exr: no channel \"R\" (channels: Y)");
    const Image smallMask = makeImage(2, 2, {"Y"}, [](int, int, int) { return 0.0f; });
    options.maskName = "m.png";
    EXPECT_EQ(message(texture(4, 4), texture(4, 4), &smallMask),
              "m.png (2 x 2) and b.exr (4 x 4) differ in size");
    options.channels = {"R", "A"};
    EXPECT_EQ(message(texture(4, 4), texture(4, 4), nullptr),
              "a.exr: no channel \"A\" (channels: R, G, B)");
}

TEST(Heatmap, ColoursFollowTheErrorAndTheLegendHasABar) {
    // One pixel with error 1, one NaN, the rest 1e-5 (below the scale's low end 1e-4).
    Image error = makeImage(40, 30, {"relmse"}, [](int, int, int) { return 1e-5f; });
    error.at(10, 20, 0) = 1.0f;
    error.at(11, 20, 0) = std::numeric_limits<float>::quiet_NaN();
    HeatmapLegend legend;
    const Image picture = renderHeatmap(error, "test", legend);
    EXPECT_EQ(picture.width(), kFalseColourMinWidth);
    EXPECT_EQ(picture.height(), 30 + kFalseColourLegendHeight);
    EXPECT_DOUBLE_EQ(legend.high, 1.0);
    EXPECT_NEAR(legend.low, 1e-4, 1e-12);
    EXPECT_EQ(legend.nonFinite, 1u);
    // Viridis in linear RGB (OpenImageIO's table): first entry (0.0580, 0.0004, 0.0887), last
    // (0.9847, 0.7997, 0.0182).
    const float first[3] = {0.0580f, 0.0004f, 0.0887f}, last[3] = {0.9847f, 0.7997f, 0.0182f};
    const int barY = 30 + kFalseColourBarTop + kFalseColourBarHeight / 2;
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(picture.at(0, 0, c), first[c], 2e-3) << c;
        EXPECT_NEAR(picture.at(10, 20, c), last[c], 2e-3) << c;
        EXPECT_NEAR(picture.at(kFalseColourMargin, barY, c), first[c], 2e-2) << c;
        EXPECT_NEAR(picture.at(kFalseColourMinWidth - kFalseColourMargin - 1, barY, c), last[c],
                    2e-2)
            << c;
    }
    EXPECT_EQ(picture.at(11, 20, 0), 1.0f);
    EXPECT_EQ(picture.at(11, 20, 1), 0.0f);
    EXPECT_EQ(picture.at(11, 20, 2), 1.0f);
    // Labels: where the font was found, white text appears in the strip below the bar.
    if (legend.labelled) {
        float brightest = 0.0f;
        for (int y = 30 + kFalseColourBarTop + kFalseColourBarHeight; y < picture.height(); ++y) {
            for (int x = 0; x < picture.width(); ++x)
                brightest = std::max(brightest, picture.at(x, y, 1));
        }
        EXPECT_GT(brightest, 0.9f);
    }
}

}  // namespace
}  // namespace penumbra
