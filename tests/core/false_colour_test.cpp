// False-colour pictures (core/heatmap.h): colours against matplotlib's published viridis table,
// the scales' placement of a value against their closed forms, the legend's labels, the
// automatic maximum, clamping, non-finite pixels, the picture's size and the labels' spacing.
#include "core/heatmap.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {
namespace {

using Rgb = std::array<double, 3>;

Image makeValues(int width, int height, const std::function<float(int, int)>& value) {
    Image image(width, height, {"Y"});
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x)
            image.at(x, y, 0) = value(x, y);
    }
    return image;
}

Rgb pixel(const Image& picture, int x, int y) {
    return {picture.at(x, y, 0), picture.at(x, y, 1), picture.at(x, y, 2)};
}

double distance(const Rgb& a, const Rgb& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
}

// Relative luminance of linear sRGB (ITU-R BT.709 primaries).
double luminance(const Rgb& c) {
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
}

// The sRGB transfer function (IEC 61966-2-1), linear to encoded.
double encodeSrgb(double linear) {
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// The bar's row through its middle, and column at `fraction` of the scale.
int barRow(const FalseColourLegend& legend) {
    return legend.barTop + kFalseColourBarHeight / 2;
}
int barColumn(const FalseColourLegend& legend, double fraction) {
    return legend.barLeft + int(std::lround(fraction * (legend.barWidth - 1)));
}

// The fraction of the scale whose bar colour is nearest `colour`.
double nearestFraction(const Image& picture, const FalseColourLegend& legend, const Rgb& colour) {
    int best = 0;
    for (int i = 1; i < legend.barWidth; ++i) {
        if (distance(pixel(picture, legend.barLeft + i, barRow(legend)), colour) <
            distance(pixel(picture, legend.barLeft + best, barRow(legend)), colour))
            best = i;
    }
    return double(best) / (legend.barWidth - 1);
}

FalseColourSettings settings(FalseColourScale scale, double maximum, int decades, int divisions) {
    FalseColourSettings s;
    s.scale = scale;
    s.maximum = maximum;
    s.decades = decades;
    s.divisions = divisions;
    s.title = "illuminance, lux";
    return s;
}

TEST(FalseColour, LinearRampFollowsViridis) {
    // Values 0 .. 100 across, on a linear scale to 100: pixel x sits at fraction x / 100.
    const Image values = makeValues(101, 4, [](int x, int) { return float(x); });
    FalseColourLegend legend;
    const Image picture =
        renderFalseColour(values, settings(FalseColourScale::Linear, 100.0, 4, 4), legend);
    // Viridis increases in lightness (van der Walt and Smith), so luminance rises along the ramp.
    for (int x = 1; x <= 100; ++x)
        EXPECT_GT(luminance(pixel(picture, x, 2)), luminance(pixel(picture, x - 1, 2))) << x;
    // matplotlib's `_viridis_data` (sRGB-encoded, 256 entries, entry i at fraction i / 255),
    // interpolated at 0, 0.25, 0.5, 0.75 and 1. OpenImageIO's table keeps 17 of the entries,
    // linearised, and interpolates between them in linear RGB: hence the tolerance of 0.01
    // (2.5 of 255 sRGB levels) on the encoded colour.
    struct Entry {
        int index;
        Rgb srgb;
    };
    const Entry table[] = {
        {0, {0.267004, 0.004874, 0.329415}},   {63, {0.231674, 0.318106, 0.544834}},
        {64, {0.229739, 0.322361, 0.545706}},  {127, {0.128729, 0.563265, 0.551229}},
        {128, {0.127568, 0.566949, 0.550556}}, {191, {0.360741, 0.785964, 0.387814}},
        {192, {0.369214, 0.788888, 0.382914}}, {255, {0.993248, 0.906157, 0.143936}}};
    for (const int x : {0, 25, 50, 75, 100}) {
        const double index = x / 100.0 * 255.0;
        const Entry* below = &table[0];
        for (const Entry& e : table) {
            if (e.index <= index)
                below = &e;
        }
        const Entry* above = below == &table[std::size(table) - 1] ? below : below + 1;
        const double t =
            above == below ? 0.0 : (index - below->index) / (above->index - below->index);
        for (int c = 0; c < 3; ++c) {
            const double expected =
                below->srgb[size_t(c)] + t * (above->srgb[size_t(c)] - below->srgb[size_t(c)]);
            EXPECT_NEAR(encodeSrgb(picture.at(x, 0, c)), expected, 0.01) << x << " " << c;
        }
    }
    // The bar runs through the same colours: its ends are the map's ends.
    EXPECT_LT(
        distance(pixel(picture, barColumn(legend, 0.0), barRow(legend)), pixel(picture, 0, 0)),
        1e-6);
    EXPECT_LT(
        distance(pixel(picture, barColumn(legend, 1.0), barRow(legend)), pixel(picture, 100, 0)),
        1e-6);
}

TEST(FalseColour, LogAndLinearPlaceAValueAtItsFraction) {
    // 10 with maximum 1000: log10(10 / 0.1) / 4 = 0.5 of a four-decade log scale, 10 / 1000 =
    // 0.01 of a linear one.
    const Image values = makeValues(8, 6, [](int, int) { return 10.0f; });
    for (const auto& [scale, fraction] :
         {std::pair{FalseColourScale::Log, 0.5}, std::pair{FalseColourScale::Linear, 0.01}}) {
        FalseColourLegend legend;
        const Image picture = renderFalseColour(values, settings(scale, 1000.0, 4, 8), legend);
        const Rgb colour = pixel(picture, 3, 3);
        EXPECT_LT(distance(colour, pixel(picture, barColumn(legend, fraction), barRow(legend))),
                  4e-3)
            << fraction;
        EXPECT_NEAR(nearestFraction(picture, legend, colour), fraction, 0.01);
    }
}

TEST(FalseColour, LabelsAreTheValuesAtTheDivisionBoundaries) {
    const Image values = makeValues(4, 4, [](int, int) { return 1.0f; });
    FalseColourLegend legend;
    renderFalseColour(values, settings(FalseColourScale::Log, 1000.0, 3, 3), legend);
    ASSERT_EQ(legend.labels.size(), 4u);
    const double decades[] = {1.0, 10.0, 100.0, 1000.0};
    for (size_t i = 0; i < 4; ++i)
        EXPECT_DOUBLE_EQ(legend.labels[i], decades[i]) << i;
    EXPECT_DOUBLE_EQ(legend.low, 1.0);
    EXPECT_DOUBLE_EQ(legend.high, 1000.0);

    renderFalseColour(values, settings(FalseColourScale::Linear, 1000.0, 3, 4), legend);
    EXPECT_EQ(legend.labels, (std::vector<double>{0.0, 250.0, 500.0, 750.0, 1000.0}));
    EXPECT_EQ(legend.low, 0.0);

    // The defaults: four decades in eight steps of a half decade, as the legend prints them.
    FalseColourSettings defaults;
    defaults.maximum = 1000.0;
    renderFalseColour(values, defaults, legend);
    std::vector<std::string> texts;
    for (const double label : legend.labels)
        texts.push_back(formatLegendValue(label));
    EXPECT_EQ(texts, (std::vector<std::string>{"0.1", "0.316", "1", "3.16", "10", "31.6", "100",
                                               "316", "1000"}));
}

TEST(FalseColour, FormatsValuesWithThreeSignificantDigits) {
    EXPECT_EQ(formatLegendValue(0.0), "0");
    EXPECT_EQ(formatLegendValue(1000.0), "1000");
    EXPECT_EQ(formatLegendValue(31622.8), "31600");
    EXPECT_EQ(formatLegendValue(999.6), "1000");
    EXPECT_EQ(formatLegendValue(100.0), "100");
    EXPECT_EQ(formatLegendValue(12.34), "12.3");
    EXPECT_EQ(formatLegendValue(2.5), "2.5");
    EXPECT_EQ(formatLegendValue(-3.14159), "-3.14");
    EXPECT_EQ(formatLegendValue(0.00316228), "0.00316");
    EXPECT_EQ(formatLegendValue(0.00099996), "0.001");
    EXPECT_EQ(formatLegendValue(1e-4), "1e-4");
    EXPECT_EQ(formatLegendValue(2.5e-5), "2.5e-5");
    EXPECT_EQ(formatLegendValue(1e6), "1e6");
    EXPECT_EQ(formatLegendValue(1.5e7), "1.5e7");
}

TEST(FalseColour, AutomaticMaximum) {
    FalseColourLegend legend;
    // Log: the largest finite value.
    const Image peak =
        makeValues(10, 10, [](int x, int y) { return x == 3 && y == 7 ? 734.2f : 5.0f; });
    renderFalseColour(peak, settings(FalseColourScale::Log, 0.0, 4, 8), legend);
    EXPECT_EQ(legend.high, double(734.2f));
    EXPECT_DOUBLE_EQ(legend.low, double(734.2f) * 1e-4);

    // Linear: 1 % glare at 1e5 over a room at 400 lux. The 99th percentile is 400, the step
    // 400 / 8 = 50, a nice number: the scale ends at 400 and the glare is the last colour.
    const Image glare =
        makeValues(20, 10, [](int x, int y) { return y == 0 && x < 2 ? 1e5f : 400.0f; });
    const Image picture =
        renderFalseColour(glare, settings(FalseColourScale::Linear, 0.0, 4, 8), legend);
    EXPECT_DOUBLE_EQ(legend.high, 400.0);
    EXPECT_EQ(legend.labels, (std::vector<double>{0, 50, 100, 150, 200, 250, 300, 350, 400}));
    EXPECT_LT(
        distance(pixel(picture, 0, 0), pixel(picture, barColumn(legend, 1.0), barRow(legend))),
        1e-6);
    EXPECT_LT(
        distance(pixel(picture, 5, 5), pixel(picture, barColumn(legend, 1.0), barRow(legend))),
        1e-6);

    // Steps of 2.5 and 3 x 10^k as well as 1, 2 and 5: 1800 / 8 = 225 rounds up to 250, and
    // 2150 / 8 = 268.75 to 300 (not to 500, which would leave nearly half the colours unused).
    renderFalseColour(makeValues(4, 4, [](int, int) { return 1800.0f; }),
                      settings(FalseColourScale::Linear, 0.0, 4, 8), legend);
    EXPECT_DOUBLE_EQ(legend.high, 2000.0);
    renderFalseColour(makeValues(4, 4, [](int, int) { return 2150.0f; }),
                      settings(FalseColourScale::Linear, 0.0, 4, 8), legend);
    EXPECT_DOUBLE_EQ(legend.high, 2400.0);
    // A 99th percentile of 0 (a few lit pixels in the dark) falls back to the largest value:
    // 7 / 8 rounds up to 1, the scale ends at 8.
    renderFalseColour(
        makeValues(100, 10, [](int x, int y) { return x == 0 && y < 5 ? 7.0f : 0.0f; }),
        settings(FalseColourScale::Linear, 0.0, 4, 8), legend);
    EXPECT_DOUBLE_EQ(legend.high, 8.0);
    // Nothing above zero: an empty scale, every pixel the first colour.
    const Image dark = renderFalseColour(makeValues(4, 4, [](int, int) { return 0.0f; }),
                                         settings(FalseColourScale::Log, 0.0, 4, 2), legend);
    EXPECT_EQ(legend.high, 0.0);
    EXPECT_EQ(legend.low, 0.0);
    EXPECT_EQ(legend.labels, (std::vector<double>{0, 0, 0}));
    EXPECT_LT(distance(pixel(dark, 2, 2), pixel(dark, barColumn(legend, 0.0), barRow(legend))),
              1e-6);
}

TEST(FalseColour, ClampsBelowAndAboveTheScale) {
    // Log to 100 over two decades (1 .. 100); linear 0 .. 100.
    const float row[] = {0.0f, -3.0f, 0.5f, 1.0f, 100.0f, 1e4f};
    const Image values = makeValues(6, 1, [&](int x, int) { return row[x]; });
    for (const FalseColourScale scale : {FalseColourScale::Log, FalseColourScale::Linear}) {
        FalseColourLegend legend;
        const Image picture = renderFalseColour(values, settings(scale, 100.0, 2, 2), legend);
        const Rgb first = pixel(picture, barColumn(legend, 0.0), barRow(legend));
        const Rgb last = pixel(picture, barColumn(legend, 1.0), barRow(legend));
        // Log: 0, -3, 0.5 and its bottom 1 are the first colour; linear: 0 and -3.
        const int belowOrAtBottom = scale == FalseColourScale::Log ? 4 : 2;
        for (int x = 0; x < belowOrAtBottom; ++x)
            EXPECT_LT(distance(pixel(picture, x, 0), first), 1e-6) << x;
        for (int x = 4; x < 6; ++x)
            EXPECT_LT(distance(pixel(picture, x, 0), last), 1e-6) << x;
    }
}

TEST(FalseColour, NonFinitePixelsAreMagentaAndLeftOutOfTheScale) {
    Image values = makeValues(5, 5, [](int x, int y) { return float(1 + x + y); });
    values.at(0, 0, 0) = std::numeric_limits<float>::quiet_NaN();
    values.at(1, 0, 0) = std::numeric_limits<float>::infinity();
    values.at(2, 0, 0) = -std::numeric_limits<float>::infinity();
    for (const FalseColourScale scale : {FalseColourScale::Log, FalseColourScale::Linear}) {
        FalseColourLegend legend;
        const Image picture = renderFalseColour(values, settings(scale, 0.0, 4, 4), legend);
        EXPECT_EQ(legend.nonFinite, 3u);
        for (int x = 0; x < 3; ++x)
            EXPECT_EQ(pixel(picture, x, 0), (Rgb{1.0, 0.0, 1.0})) << x;
        EXPECT_NE(pixel(picture, 3, 0), (Rgb{1.0, 0.0, 1.0}));
        if (scale == FalseColourScale::Log)
            EXPECT_EQ(legend.high, 9.0);  // the largest finite value
        else
            EXPECT_EQ(legend.high, 10.0);  // its 99th percentile, 9, in 4 steps of 2.5
    }
}

TEST(FalseColour, PictureSize) {
    FalseColourLegend legend;
    // A small map: the minimum width, the legend strip below.
    Image picture = renderFalseColour(makeValues(40, 30, [](int x, int) { return float(x + 1); }),
                                      settings(FalseColourScale::Log, 0.0, 4, 2), legend);
    EXPECT_EQ(picture.width(), kFalseColourMinWidth);
    EXPECT_EQ(picture.height(), 30 + kFalseColourLegendHeight);
    EXPECT_EQ(legend.barLeft, kFalseColourMargin);
    EXPECT_EQ(legend.barTop, 30 + kFalseColourBarTop);
    EXPECT_EQ(legend.barWidth, kFalseColourMinWidth - 2 * kFalseColourMargin);
    // A wide one: its own width, the bar across it.
    picture = renderFalseColour(makeValues(500, 20, [](int x, int) { return float(x + 1); }),
                                settings(FalseColourScale::Linear, 0.0, 4, 4), legend);
    EXPECT_EQ(picture.width(), 500);
    EXPECT_EQ(picture.height(), 20 + kFalseColourLegendHeight);
    EXPECT_EQ(legend.barWidth, 500 - 2 * kFalseColourMargin);
}

TEST(FalseColour, LabelsAreDrawnApartUnderTheirTicks) {
    // 16 divisions do not fit 320 pixels: the picture widens so that labels do not overlap.
    const Image values = makeValues(40, 10, [](int x, int) { return float(x + 1); });
    FalseColourLegend legend;
    const Image picture =
        renderFalseColour(values, settings(FalseColourScale::Log, 0.0, 4, 16), legend);
    const int tickTop = legend.barTop + kFalseColourBarHeight;
    const auto anchor = [&](int i) { return barColumn(legend, double(i) / 16); };
    // A tick below the bar at each division boundary, in the text colour.
    for (int i = 0; i <= 16; ++i)
        EXPECT_EQ(pixel(picture, anchor(i), tickTop + 1), (Rgb{1.0, 1.0, 1.0})) << i;
    if (!legend.labelled)
        GTEST_SKIP() << "no font: the labels are not drawn";
    EXPECT_GT(picture.width(), kFalseColourMinWidth);
    const auto ink = [&](int x) {
        for (int y = tickTop + kFalseColourTickHeight; y < picture.height(); ++y) {
            if (picture.at(x, y, 1) > 0.2f)
                return true;
        }
        return false;
    };
    for (int i = 0; i <= 16; ++i) {
        // Each label has ink within a few pixels of its anchor (the end labels start or end
        // there, the others are centred on it)...
        bool near = false;
        for (int x = std::max(0, anchor(i) - 4); x <= std::min(picture.width() - 1, anchor(i) + 4);
             ++x)
            near = near || ink(x);
        EXPECT_TRUE(near) << i;
        if (i == 16)
            break;
        // ...and between two neighbours runs a blank gap wider than the space between glyphs.
        int run = 0, longest = 0;
        for (int x = anchor(i); x < anchor(i + 1); ++x) {
            run = ink(x) ? 0 : run + 1;
            longest = std::max(longest, run);
        }
        EXPECT_GE(longest, 5) << "between labels " << i << " and " << i + 1;
    }
}

TEST(FalseColour, HeatmapIsTheFourDecadeLogScaleLabelledAtTheEndsAndMiddle) {
    const Image error = makeValues(40, 30, [](int x, int y) { return 1e-3f * float(1 + x * y); });
    HeatmapLegend heatmap;
    const Image wrapped = renderHeatmap(error, "relMSE", heatmap);
    FalseColourSettings s = settings(FalseColourScale::Log, 0.0, 4, 2);
    s.title = "relMSE";
    FalseColourLegend legend;
    const Image direct = renderFalseColour(error, s, legend);
    EXPECT_EQ(heatmap.high, double(1e-3f * float(1 + 39 * 29)));
    ASSERT_EQ(heatmap.labels.size(), 3u);
    EXPECT_DOUBLE_EQ(heatmap.labels[0], heatmap.high * 1e-4);
    EXPECT_DOUBLE_EQ(heatmap.labels[1], heatmap.high * 1e-2);  // the geometric mean of the ends
    EXPECT_DOUBLE_EQ(heatmap.labels[2], heatmap.high);
    ASSERT_EQ(wrapped.width(), direct.width());
    ASSERT_EQ(wrapped.height(), direct.height());
    EXPECT_TRUE(
        std::equal(wrapped.pixels().begin(), wrapped.pixels().end(), direct.pixels().begin()));
}

TEST(FalseColour, RefusesWhatItCannotShow) {
    const Image values = makeValues(2, 2, [](int, int) { return 1.0f; });
    FalseColourLegend legend;
    EXPECT_THROW(renderFalseColour(Image(2, 2, {"R", "G"}), {}, legend), std::invalid_argument);
    for (const FalseColourSettings& bad :
         {settings(FalseColourScale::Log, -1.0, 4, 8),
          settings(FalseColourScale::Log, std::numeric_limits<double>::quiet_NaN(), 4, 8),
          settings(FalseColourScale::Log, std::numeric_limits<double>::infinity(), 4, 8),
          settings(FalseColourScale::Log, 0.0, 0, 8), settings(FalseColourScale::Log, 0.0, 31, 8),
          settings(FalseColourScale::Linear, 0.0, 4, 0),
          settings(FalseColourScale::Linear, 0.0, 4, 101)})
        EXPECT_THROW(renderFalseColour(values, bad, legend), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
