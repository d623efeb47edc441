// Histogram adjustment (core/histogram_adjustment.h) against the paper it implements, Ward Larson,
// Rushmeier and Piatko 1997: Table 1 and Eq. 15 evaluated by hand and the values its text quotes,
// its contrast ceilings (Eq. 5a, 7a) measured on the tone curve, naive histogram equalization
// (Eq. 4) worked out here as the case the ceilings must fix, and closed forms for the linear
// operator, the hue and the acuity blur.
#include "core/histogram_adjustment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace penumbra {
namespace {

using Rgb = std::array<float, 3>;

Image makeImage(int width, int height, const std::function<Rgb(int, int)>& colour) {
    Image image(width, height, {"R", "G", "B"});
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                image.at(x, y, c) = colour(x, y)[size_t(c)];
    return image;
}

double luminance(const Image& image, int x, int y) {
    return 0.2126 * image.at(x, y, 0) + 0.7152 * image.at(x, y, 1) + 0.0722 * image.at(x, y, 2);
}

// The display luminance a display of black Ld_min and white Ld_max shows for value v.
double shown(double v, const HistogramAdjustmentSettings& s) {
    return s.displayMinimum + v * (s.displayMaximum - s.displayMinimum);
}

// A scene of 7 decades, 1e-3 to 1e4 cd/m², with two crowded bands, a dim room at 0.01 to 0.015
// and a bright window at 300 to 450 cd/m², each 20% of the samples in 2.5% of the range:
// naive equalization spreads each band over far more of the display than a linear map would.
std::vector<float> bimodalScene() {
    std::vector<float> samples = {1e-3f, 1e4f};
    for (int k = 0; k < 400; ++k) {
        samples.push_back(0.01f * std::pow(1.5f, k / 400.0f));
        samples.push_back(300.0f * std::pow(1.5f, k / 400.0f));
    }
    for (int k = 0; k < 1200; ++k)
        samples.push_back(std::pow(10.0f, -3.0f + 7.0f * k / 1200.0f));
    return samples;
}
constexpr double kSceneMinimum = 1e-3, kSceneMaximum = 1e4;

// The slope dLd/dLw at the centre of each of the curve's bins over [kSceneMinimum,
// kSceneMaximum], by a central difference well inside the bin (the curve is Lw^g there).
template <typename Check>
void forEachBin(const HistogramToneCurve& curve, Check check) {
    const double bmin = std::log(kSceneMinimum), bmax = std::log(kSceneMaximum);
    const double db = (bmax - bmin) / HistogramToneCurve::kBins, h = 0.05 * db;
    for (int i = 0; i < HistogramToneCurve::kBins; ++i) {
        const double b = bmin + (i + 0.5) * db;
        const double slope = (curve.displayLuminance(float(std::exp(b + h))) -
                              curve.displayLuminance(float(std::exp(b - h)))) /
                             (std::exp(b + h) - std::exp(b - h));
        check(i, std::exp(b), double(curve.displayLuminance(float(std::exp(b)))), slope);
    }
}

// How far the paper's iteration lets the curve over its ceiling (§4.4). It stops once a pass trims
// at most 2.5% of the original count T_0, and the curve is that of the trimmed histogram, whose
// total T is lower by up to 0.025 T_0 than the total the last ceilings were computed with: the
// slope in a capped bin, proportional to f(b) / T (Eq. 3), exceeds its linear ceiling (Eq. 5c) by
// the factor 1 + eps at most, eps = 0.025 T_0 / T = 0.025 / keptFraction(). The human ceiling
// (Eq. 7c) was also computed at the Ld of the untrimmed P(b), which the last trims move by at most
// eps (P is a share of T), so Ld by a factor exp(eps log(Ld_max / Ld_min)); since Ld / ΔL_t(Ld)
// does not decrease with Ld, the bound is loose by at most that factor too.
double linearCeilingSlack(const HistogramToneCurve& curve) {
    return 1.0 + 0.025 / curve.keptFraction();
}
double humanCeilingSlack(const HistogramToneCurve& curve, const HistogramAdjustmentSettings& s) {
    const double eps = 0.025 / curve.keptFraction();
    return (1.0 + eps) * std::exp(eps * std::log(s.displayMaximum / s.displayMinimum));
}

TEST(HistogramAdjustmentTest, DetectionThresholdMatchesTable1WorkedByHand) {
    // log10 ΔL_t from the row of Table 1 for log10 L_a:
    //   1e-5  row 1: -2.86                                                  -> 1.380384e-3
    //   1e-2  row 2: (0.405 (-2) + 1.6)^2.18 - 2.86 = 0.79^2.18 - 2.86
    //                = 0.598173 - 2.86 = -2.261827                          -> 5.472343e-3
    //   1e-1  row 3: -1 - 0.395 = -1.395                                    -> 4.027170e-2
    //   1     row 4: 0.65^2.7 - 0.72 = 0.312512 - 0.72 = -0.407488          -> 0.3913015
    //   10    row 4: 0.899^2.7 - 0.72 = 0.750155 - 0.72 = 0.030155          -> 1.071902
    //   1000  row 5: 3 - 1.255 = 1.745                                      -> 55.59043
    const std::array<std::array<double, 2>, 6> table = {{{1e-5, 1.380384e-3},
                                                         {1e-2, 5.472343e-3},
                                                         {1e-1, 4.027170e-2},
                                                         {1.0, 0.3913015},
                                                         {10.0, 1.071902},
                                                         {1000.0, 55.59043}}};
    for (const auto& [La, expected] : table)
        EXPECT_NEAR(detectionThreshold(float(La)), expected, 1e-5 * expected) << "L_a " << La;
    // Below the lowest row's limit, including black and NaN: row 1
    EXPECT_NEAR(detectionThreshold(0.0f), 1.380384e-3, 1e-8);
    EXPECT_NEAR(detectionThreshold(std::numeric_limits<float>::quiet_NaN()), 1.380384e-3, 1e-8);
    // The rod and cone fits are joined at their crossover, 10^-0.0184 cd/m² (§4.5)
    const float crossover = std::pow(10.0f, -0.0184f);
    EXPECT_NEAR(detectionThreshold(crossover * 0.9999f) / detectionThreshold(crossover * 1.0001f),
                1.0, 1e-3);
}

TEST(HistogramAdjustmentTest, VisualAcuityMatchesTheValuesThePaperQuotes) {
    // §5.3: 25 cd/m² "corresponding to a visual acuity of about 45 cycles/degree", 0.05 cd/m²
    // "about 9 cycles/degree"; daylight "about 50"
    EXPECT_NEAR(visualAcuity(25.0f), 45.0, 1.0);
    EXPECT_NEAR(visualAcuity(0.05f), 9.0, 0.5);
    EXPECT_NEAR(visualAcuity(1e4f), 50.0, 1.5);
    // Eq. 15 by hand: 17.25 atan(1.4 log10(1) + 0.35) + 25.72 = 17.25 (0.336675) + 25.72
    EXPECT_NEAR(visualAcuity(1.0f), 31.52764, 1e-3);
    // Floored at the threshold of vision: 17.25 atan(1.4 (-4) + 0.35) + 25.72 = 1.87058
    EXPECT_NEAR(visualAcuity(1e-4f), 1.87058, 1e-3);
    EXPECT_EQ(visualAcuity(0.0f), visualAcuity(1e-4f));
}

TEST(HistogramAdjustmentTest, MappingIsMonotonicInLuminance) {
    const std::vector<float> samples = bimodalScene();
    for (bool human : {true, false}) {
        HistogramAdjustmentSettings settings;
        settings.humanContrast = human;
        const HistogramToneCurve curve(samples, settings);
        EXPECT_FALSE(curve.isLinear()) << "human " << human;
        float previous = 0.0f;
        for (int i = 0; i <= 4000; ++i) {
            const float Ld = curve.displayLuminance(std::pow(10.0f, -6.0f + 12.0f * i / 4000.0f));
            EXPECT_GE(Ld, previous) << "human " << human << " step " << i;
            EXPECT_GE(Ld, settings.displayMinimum);
            EXPECT_LE(Ld, settings.displayMaximum);
            previous = Ld;
        }
        // The histogram curve spans the display: the dimmest sample at its black, the brightest
        // at its white (Eq. 4 with P = 0 and 1)
        EXPECT_FLOAT_EQ(curve.displayLuminance(float(kSceneMinimum)), settings.displayMinimum);
        EXPECT_FLOAT_EQ(curve.displayLuminance(float(kSceneMaximum)), settings.displayMaximum);

        // And through an image: a grey ramp over 6 decades, brighter to the right
        const Image ramp = makeImage(200, 20, [](int x, int) {
            const float L = std::pow(10.0f, -2.0f + 6.0f * x / 199.0f);
            return Rgb{L, L, L};
        });
        const Image display = histogramAdjust(ramp, settings);
        for (int x = 1; x < 200; ++x)
            EXPECT_GE(luminance(display, x, 10), luminance(display, x - 1, 10)) << "x " << x;
        EXPECT_EQ(luminance(display, 0, 10), 0.0);
        EXPECT_NEAR(luminance(display, 199, 10), 1.0, 1e-6);
    }
}

TEST(HistogramAdjustmentTest, SceneWithinTheDisplaysRangeMapsLinearly) {
    // Four grey quadrants spanning 2 to 40 cd/m², a range of 20 against the display's 100: §4.4
    // maps it linearly, so the shown luminances keep the scene's ratios. 40 pixels across at the
    // default field of view give 40 foveal samples, one a pixel, so the samples are these values.
    const std::array<float, 4> levels = {2.0f, 5.0f, 10.0f, 40.0f};
    const Image scene = makeImage(40, 40, [&](int x, int y) {
        const float L = levels[size_t(2 * (y / 20) + x / 20)];
        return Rgb{L, L, L};
    });
    for (bool human : {true, false}) {
        HistogramAdjustmentSettings settings;
        settings.humanContrast = human;
        const Image display = histogramAdjust(scene, settings);
        const double m = shown(luminance(display, 0, 0), settings) / levels[0];
        for (int q = 0; q < 4; ++q) {
            const int x = 20 * (q % 2) + 5, y = 20 * (q / 2) + 5;
            EXPECT_NEAR(shown(luminance(display, x, y), settings) / levels[size_t(q)], m, 1e-4 * m)
                << "human " << human << " quadrant " << q;
        }
    }
}

TEST(HistogramAdjustmentTest, UniformImageMapsByTheLinearOperator) {
    // No range at all: the linear operator, which maps the log-average to the display's middle
    // sqrt(1 x 100) = 10 cd/m² (v = 9/99), or with the human model its threshold to 10 cd/m²'s:
    // Ld = L ΔL_t(10) / ΔL_t(L) with Table 1's values worked by hand in the test above.
    struct Case {
        float L;
        double linear, human;
    };
    const std::array<Case, 3> cases = {{
        {1e-3f, 9.0 / 99.0, 0.0},  // Ld = 0.583, under the display's black: not seen
        {1.0f, 9.0 / 99.0, (1.0 * 1.071902 / 0.3913015 - 1.0) / 99.0},
        {1000.0f, 9.0 / 99.0, (1000.0 * 1.071902 / 55.59043 - 1.0) / 99.0},
    }};
    for (const Case& c : cases) {
        const Image scene = makeImage(30, 20, [&](int, int) { return Rgb{c.L, c.L, c.L}; });
        for (bool human : {true, false}) {
            HistogramAdjustmentSettings settings;
            settings.humanContrast = human;
            const Image display = histogramAdjust(scene, settings);
            for (int y = 0; y < 20; ++y)
                for (int x = 0; x < 30; ++x)
                    ASSERT_NEAR(luminance(display, x, y), human ? c.human : c.linear, 1e-5)
                        << "L " << c.L << " human " << human;
        }
    }
}

// Naive histogram equalization of the samples (Eq. 4, no ceiling), worked out independently:
// the slope dLd/dLw at each bin centre, the left side of Eq. 5b, with the Ld there.
std::vector<std::array<double, 2>> naiveEqualization(const std::vector<float>& samples,
                                                     const HistogramAdjustmentSettings& s) {
    const int n = HistogramToneCurve::kBins;
    const double bmin = std::log(kSceneMinimum), bmax = std::log(kSceneMaximum);
    const double db = (bmax - bmin) / n, range = std::log(s.displayMaximum / s.displayMinimum);
    std::vector<double> f(size_t(n), 0.0);
    for (float L : samples)
        f[size_t(std::min(int((std::log(L) - bmin) / db), n - 1))] += 1.0;
    const double T = double(samples.size());
    std::vector<std::array<double, 2>> result;
    double below = 0.0;
    for (int i = 0; i < n; ++i) {
        const double P = (below + 0.5 * f[size_t(i)]) / T;
        const double Lw = std::exp(bmin + (i + 0.5) * db);
        const double Ld = s.displayMinimum * std::exp(range * P);
        result.push_back({Ld / Lw * range * f[size_t(i)] / (T * db), Ld});
        below += f[size_t(i)];
    }
    return result;
}

TEST(HistogramAdjustmentTest, HumanContrastCeilingHoldsAtBinResolution) {
    // The paper's central claim (Eq. 7a): dLd/dLw <= ΔL_t(Ld) / ΔL_t(Lw) everywhere, so no
    // displayed contrast is more visible than the same contrast in the scene.
    const std::vector<float> samples = bimodalScene();
    const HistogramAdjustmentSettings settings;
    const HistogramToneCurve curve(samples, settings);
    ASSERT_FALSE(curve.isLinear());
    double worst = 0.0;
    forEachBin(curve, [&](int i, double Lw, double Ld, double slope) {
        const double allowed = detectionThreshold(float(Ld)) / detectionThreshold(float(Lw));
        EXPECT_LE(slope, allowed * humanCeilingSlack(curve, settings))
            << "bin " << i << " Lw " << Lw;
        worst = std::max(worst, slope / allowed);
    });
    // Naive equalization breaks the same bound at least twice over: the scene needs the ceiling
    double naiveWorst = 0.0;
    const auto naive = naiveEqualization(samples, settings);
    forEachBin(curve, [&](int i, double Lw, double, double) {
        const auto [slope, Ld] = naive[size_t(i)];
        naiveWorst = std::max(
            naiveWorst, slope / (detectionThreshold(float(Ld)) / detectionThreshold(float(Lw))));
    });
    EXPECT_GT(naiveWorst, 2.0);
    std::printf("slope / (dL_t(Ld) / dL_t(Lw)): at most %.4f (allowed %.4f); naive %.2f\n", worst,
                humanCeilingSlack(curve, settings), naiveWorst);
}

TEST(HistogramAdjustmentTest, LinearCeilingNeverExaggeratesContrast) {
    // Eq. 5a: dLd/dLw <= Ld/Lw, the contrast of a linear operator
    const std::vector<float> samples = bimodalScene();
    HistogramAdjustmentSettings settings;
    settings.humanContrast = false;
    const HistogramToneCurve curve(samples, settings);
    ASSERT_FALSE(curve.isLinear());
    double worst = 0.0;
    forEachBin(curve, [&](int i, double Lw, double Ld, double slope) {
        EXPECT_LE(slope, Ld / Lw * linearCeilingSlack(curve)) << "bin " << i << " Lw " << Lw;
        worst = std::max(worst, slope / (Ld / Lw));
    });
    double naiveWorst = 0.0;
    const auto naive = naiveEqualization(samples, settings);
    forEachBin(curve, [&](int i, double Lw, double, double) {
        naiveWorst = std::max(naiveWorst, naive[size_t(i)][0] / (naive[size_t(i)][1] / Lw));
    });
    EXPECT_GT(naiveWorst, 2.0);
    std::printf("slope / (Ld / Lw): at most %.4f (allowed %.4f); naive %.2f\n", worst,
                linearCeilingSlack(curve), naiveWorst);
}

TEST(HistogramAdjustmentTest, OutputIsFiniteAndInTheUnitRange) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const float big = std::numeric_limits<float>::max();
    const std::array<Rgb, 10> odd = {{{nan, nan, nan},
                                      {inf, inf, inf},
                                      {-inf, 1.0f, 1.0f},
                                      {-1.0f, -1.0f, -1.0f},
                                      {0.0f, 0.0f, 0.0f},
                                      {big, big, big},
                                      {1e30f, 0.0f, 0.0f},
                                      {1.0f, nan, 3.0f},
                                      {1e-9f, 1e-9f, 1e-9f},
                                      {50.0f, 20.0f, 5.0f}}};
    const Image scene = makeImage(40, 20, [&](int x, int y) { return odd[size_t(x + y) % 10]; });
    for (bool human : {true, false})
        for (bool acuity : {true, false}) {
            HistogramAdjustmentSettings settings;
            settings.humanContrast = human;
            settings.humanAcuity = acuity;
            const Image display = histogramAdjust(scene, settings);
            ASSERT_EQ(display.width(), 40);
            ASSERT_EQ(display.height(), 20);
            for (float v : display.pixels()) {
                ASSERT_TRUE(std::isfinite(v));
                ASSERT_GE(v, 0.0f);
                ASSERT_LE(v, 1.0f);
            }
            if (!acuity) {  // unblurred, a NaN pixel is black
                EXPECT_EQ(luminance(display, 0, 0), 0.0);
            }
        }

    // All black stays black; an empty image stays empty
    const Image black = histogramAdjust(makeImage(16, 8, [](int, int) { return Rgb{}; }));
    for (float v : black.pixels())
        EXPECT_EQ(v, 0.0f);
    for (const auto& [w, h] : {std::array<int, 2>{0, 0}, std::array<int, 2>{5, 0}}) {
        const Image empty = histogramAdjust(Image(w, h, {"R", "G", "B"}));
        EXPECT_EQ(empty.width(), w);
        EXPECT_EQ(empty.height(), h);
        EXPECT_EQ(empty.channelNames(), (std::vector<std::string>{"R", "G", "B"}));
    }
}

TEST(HistogramAdjustmentTest, HueIsKeptWhereNoChannelClips) {
    // 16 coloured blocks over 6 decades: every unclipped pixel keeps its channel ratios
    const std::array<Rgb, 4> hues = {
        {{1.0f, 0.5f, 0.2f}, {0.1f, 0.8f, 0.3f}, {0.3f, 0.3f, 1.0f}, {0.9f, 0.9f, 0.9f}}};
    const auto colour = [&](int x, int y) {
        const int block = 4 * (y / 10) + x / 10;
        const float L = std::pow(10.0f, -2.0f + 6.0f * block / 15.0f);
        const Rgb& hue = hues[size_t(block) % 4];
        return Rgb{L * hue[0], L * hue[1], L * hue[2]};
    };
    const Image scene = makeImage(40, 40, colour);
    const Image display = histogramAdjust(scene);
    int checked = 0;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
            const Rgb in = colour(x, y);
            const float* out = &display.pixels()[size_t(y * 40 + x) * 3];
            if (out[1] <= 0.0f || std::max({out[0], out[1], out[2]}) >= 1.0f)
                continue;
            EXPECT_NEAR(out[0] / out[1], in[0] / in[1], 1e-4 * in[0] / in[1]) << x << "," << y;
            EXPECT_NEAR(out[2] / out[1], in[2] / in[1], 1e-4 * in[2] / in[1]) << x << "," << y;
            ++checked;
        }
    EXPECT_GT(checked, 1000);
}

// Michelson contrast (max - min) / (max + min) of the displayed luminance over columns [x0, x1)
double contrast(const Image& image, int x0, int x1) {
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (int y = 8; y < image.height() - 8; ++y)
        for (int x = x0; x < x1; ++x) {
            lo = std::min(lo, luminance(image, x, y));
            hi = std::max(hi, luminance(image, x, y));
        }
    return (hi - lo) / (hi + lo);
}

// A checkerboard of 1-pixel squares, white L and black 0.
Image checkerboard(int width, int height, const std::function<float(int)>& white) {
    return makeImage(width, height, [&](int x, int y) {
        const float L = (x + y) % 2 ? white(x) : 0.0f;
        return Rgb{L, L, L};
    });
}

TEST(HistogramAdjustmentTest, AcuityLossBlursFineDetailInTheDarkOnly) {
    // 64 pixels over 1°, as a 2,300-pixel-wide render of a 36° view: 64 pixels a degree, so a
    // 1-pixel checkerboard is 32 cycles/degree. At the mean 5e-4 cd/m² the eye resolves 2.6
    // (Eq. 15): the pattern must vanish; at 50 cd/m², 47: it must stay. The linear ceiling keeps
    // the scotopic pattern above the display's black, so the blur alone decides.
    HistogramAdjustmentSettings settings;
    settings.humanContrast = false;
    settings.horizontalFieldOfViewDegrees = 1.0f;
    for (bool acuity : {true, false}) {
        settings.humanAcuity = acuity;
        const Image dark =
            histogramAdjust(checkerboard(64, 64, [](int) { return 1e-3f; }), settings);
        const Image bright =
            histogramAdjust(checkerboard(64, 64, [](int) { return 100.0f; }), settings);
        if (acuity)
            EXPECT_LT(contrast(dark, 8, 56), 1e-3);
        else
            EXPECT_GT(contrast(dark, 8, 56), 0.999);
        EXPECT_GT(contrast(bright, 8, 56), 0.999) << "acuity " << acuity;
    }

    // In one image the blur follows the local adaptation (two foveal samples over 2°): the dark
    // half blurs, the bright half stays sharp. A display black of 1e-4 cd/m² leaves the scene's
    // range within the display's, so both halves are shown linearly.
    settings.humanAcuity = true;
    settings.horizontalFieldOfViewDegrees = 2.0f;
    settings.displayMinimum = 1e-4f;
    const Image halves = histogramAdjust(
        checkerboard(128, 64, [](int x) { return x < 64 ? 1e-3f : 100.0f; }), settings);
    EXPECT_LT(contrast(halves, 8, 24), 1e-3);
    EXPECT_GT(contrast(halves, 104, 120), 0.999);
}

TEST(HistogramAdjustmentTest, RejectsMissingChannelsAndBadSettings) {
    EXPECT_THROW(histogramAdjust(Image(4, 4, {"Y"})), std::invalid_argument);
    HistogramAdjustmentSettings settings;
    settings.horizontalFieldOfViewDegrees = 0.0f;
    EXPECT_THROW(histogramAdjust(Image(4, 4, {"R", "G", "B"}), settings), std::invalid_argument);
    settings = {};
    settings.displayMinimum = 200.0f;
    EXPECT_THROW(HistogramToneCurve({}, settings), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
