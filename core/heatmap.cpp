#include "core/heatmap.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra {
namespace {

namespace IBA = OIIO::ImageBufAlgo;

constexpr int kFontSize = 13;
constexpr int kLabelGap = 8;    // least space between two labels, in pixels
constexpr int kLabelInset = 3;  // least space between a label and the picture's side
constexpr float kTextColor[3] = {1.0f, 1.0f, 1.0f};
constexpr float kNonFiniteColor[3] = {1.0f, 0.0f, 1.0f};

// The first font OpenImageIO can load: Debian's OpenImageIO finds no default font of its own
// (its DroidSans is not packaged), so DejaVu Sans is asked for by name first. nullptr if none.
const char* findFont() {
    for (const char* font : {"DejaVuSans", ""}) {
        if (IBA::text_size("0.5", kFontSize, font).defined())
            return font;
    }
    OIIO::geterror();  // clear the failed look-ups' messages
    return nullptr;
}

void check(bool ok, const OIIO::ImageBuf& buffer, const char* what) {
    if (!ok)
        throw std::runtime_error(std::string("false colour: ") + what + ": " + buffer.geterror());
}

void validate(const Image& values, const FalseColourSettings& settings) {
    if (values.channels() != 1)
        throw std::invalid_argument("renderFalseColour: the image must have one channel");
    if (!std::isfinite(settings.maximum) || settings.maximum < 0.0)
        throw std::invalid_argument("renderFalseColour: maximum must be finite and >= 0");
    // Float pixels span about 83 decades; 30 is far beyond any photometric range and keeps
    // maximum / 10^decades a normal double.
    if (settings.decades < 1 || settings.decades > 30)
        throw std::invalid_argument("renderFalseColour: decades must be 1 to 30");
    if (settings.divisions < 1 || settings.divisions > 100)
        throw std::invalid_argument("renderFalseColour: divisions must be 1 to 100");
}

// The smallest step s = m x 10^k >= x > 0 with m one of the "nice" numbers of Talbot, Lin and
// Hanrahan ("An Extension of Wilkinson's Algorithm for Positioning Tick Labels on Axes", IEEE
// TVCG 16(6), 2010: Q = 1, 5, 2, 2.5, 4, 3), rounding up as Heckbert's loose labels do ("Nice
// Numbers for Graph Labels", Graphics Gems, 1990): every multiple of s is a round number.
double niceStep(double x) {
    const double power = std::pow(10.0, std::floor(std::log10(x)));
    for (const double m : {1.0, 2.0, 2.5, 3.0, 4.0, 5.0}) {
        if (x <= m * power)
            return m * power;
    }
    return 10.0 * power;
}

// The top of the scale (settings.maximum, or the automatic one, which the header describes);
// counts the non-finite values into legend.nonFinite.
double scaleTop(const Image& values, const FalseColourSettings& settings,
                FalseColourLegend& legend) {
    double largest = 0.0;
    for (const float v : values.pixels()) {
        if (std::isfinite(v))
            largest = std::max(largest, double(v));
        else
            ++legend.nonFinite;
    }
    if (settings.maximum > 0.0)
        return settings.maximum;
    if (settings.scale == FalseColourScale::Log || largest == 0.0)
        return largest;
    // The 99th percentile by nearest rank: the value with 99 % of the finite values at or below.
    std::vector<float> finite;
    std::copy_if(values.pixels().begin(), values.pixels().end(), std::back_inserter(finite),
                 [](float v) { return std::isfinite(v); });
    const size_t rank = (99 * finite.size() + 99) / 100 - 1;  // ceil(0.99 n) - 1, exactly
    std::nth_element(finite.begin(), finite.begin() + std::ptrdiff_t(rank), finite.end());
    const double top = finite[rank] > 0.0f ? double(finite[rank]) : largest;
    return settings.divisions * niceStep(top / settings.divisions);
}

// Position of `value` along the colour bar, in [0, 1]: 0 at or below legend.low, 1 at or above
// legend.high, linear in the value or in its logarithm between.
double scalePosition(double value, const FalseColourLegend& legend,
                     const FalseColourSettings& settings) {
    if (!(legend.high > 0.0) || !(value > legend.low))
        return 0.0;
    if (value >= legend.high)
        return 1.0;
    if (settings.scale == FalseColourScale::Log)
        return std::log10(value / legend.low) / settings.decades;
    return (value - legend.low) / (legend.high - legend.low);
}

// The colours of `positions` (width x height, top row first, each in [0, 1]) in viridis: the
// map and the bar go through this one function, so a value's pixel matches the bar's.
OIIO::ImageBuf viridis(const std::vector<float>& positions, int width, int height) {
    OIIO::ImageBuf scale(OIIO::ImageSpec(width, height, 1, OIIO::TypeDesc::FLOAT));
    check(scale.set_pixels(scale.roi(), OIIO::TypeDesc::FLOAT, positions.data()), scale,
          "set_pixels");
    OIIO::ImageBuf colours = IBA::color_map(scale, 0, "viridis");
    check(!colours.has_error(), colours, "color_map");
    return colours;
}

// Width in pixels from a left-aligned text's anchor to its right edge; 0 without a font.
int textWidth(const std::string& text, const char* font) {
    if (!font)
        return 0;
    const OIIO::ROI box = IBA::text_size(text, kFontSize, font);
    return box.defined() ? std::max(box.xend, 0) : 0;
}

// How far a label `width` pixels wide reaches left and right of its anchor (its tick): centred
// under it, but moved inward at the bar's ends so that it stays kLabelInset pixels inside the
// picture (the first anchor has kFalseColourMargin pixels to its left, the last as many to its
// right).
struct LabelSpan {
    int left, right;
};
LabelSpan labelSpan(int i, int divisions, int width) {
    int left = width / 2;
    if (i == 0)
        left = std::min(left, kFalseColourMargin - kLabelInset);
    if (i == divisions)
        left = std::max(left, width - (kFalseColourMargin + 1 - kLabelInset));
    return {left, width - left};
}

// The narrowest picture the legend's text fits: the title, and the labels kLabelGap apart when
// their anchors are evenly spaced along the bar (without a font, the ticks that far apart).
int legendWidth(const std::string& title, const std::vector<std::string>& labels,
                const char* font) {
    const int divisions = int(labels.size()) - 1;
    int pitch = 0;  // least distance between two neighbouring anchors
    for (int i = 0; i < divisions; ++i) {
        const LabelSpan a = labelSpan(i, divisions, textWidth(labels[size_t(i)], font));
        const LabelSpan b = labelSpan(i + 1, divisions, textWidth(labels[size_t(i) + 1], font));
        pitch = std::max(pitch, a.right + b.left + kLabelGap);
    }
    const int bar = divisions * pitch + 1;
    return 2 * kFalseColourMargin + std::max(bar, textWidth(title, font));
}

}  // namespace

std::string formatLegendValue(double value) {
    if (value == 0.0)
        return "0";  // also -0
    if (!std::isfinite(value))
        return std::isnan(value) ? "nan" : (value > 0.0 ? "inf" : "-inf");
    // printf's %.2e rounds to 3 significant digits; its exponent then picks the notation (after
    // the rounding, so that 999.96 reads 1000 and 0.00099996 reads 0.001).
    char scientific[32], plain[48];
    std::snprintf(scientific, sizeof scientific, "%.2e", value);
    const char* e = std::strchr(scientific, 'e');
    const std::string mantissa(scientific, size_t(e - scientific));
    const int exponent = std::atoi(e + 1);
    // Drops the zeros that end a decimal fraction, and then a bare point: "2.50" is "2.5".
    const auto trim = [](std::string digits) {
        if (digits.find('.') != std::string::npos) {
            digits.erase(digits.find_last_not_of('0') + 1);
            if (digits.back() == '.')
                digits.pop_back();
        }
        return digits;
    };
    if (exponent >= -3 && exponent < 6) {
        // 2 - exponent decimals show the 3 digits: 31.6, 0.00316; none above 100: 31600.
        std::snprintf(plain, sizeof plain, "%.*f", std::max(0, 2 - exponent),
                      std::atof(scientific));
        return trim(plain);
    }
    return trim(mantissa) + "e" + std::to_string(exponent);
}

Image renderFalseColour(const Image& values, const FalseColourSettings& settings,
                        FalseColourLegend& legend) {
    validate(values, settings);
    const int width = values.width(), height = values.height();
    const int divisions = settings.divisions;

    // The scale, and the value at each division boundary: label i at fraction i / divisions.
    legend = FalseColourLegend{};
    legend.high = scaleTop(values, settings, legend);
    const bool log = settings.scale == FalseColourScale::Log;
    legend.low = log ? legend.high / std::pow(10.0, settings.decades) : 0.0;
    std::vector<std::string> labelTexts;
    for (int i = 0; i <= divisions; ++i) {
        // Dividing by an exact power of ten keeps the round labels round (1000 / 10^3 = 1).
        const double label =
            log ? legend.high /
                      std::pow(10.0, double(settings.decades * (divisions - i)) / divisions)
                : legend.high * i / divisions;
        legend.labels.push_back(label);
        labelTexts.push_back(formatLegendValue(label));
    }

    // Canvas: background, wide enough for the map and the legend's text.
    const char* font = findFont();
    const int canvasWidth =
        std::max({width, kFalseColourMinWidth, legendWidth(settings.title, labelTexts, font)});
    const int canvasHeight = height + kFalseColourLegendHeight;
    OIIO::ImageBuf canvas(OIIO::ImageSpec(canvasWidth, canvasHeight, 3, OIIO::TypeDesc::FLOAT));
    const float background[3] = {kFalseColourBackground, kFalseColourBackground,
                                 kFalseColourBackground};
    check(IBA::fill(canvas, background), canvas, "fill");

    // The map at the top left.
    if (width > 0 && height > 0) {
        std::vector<float> positions(values.pixels().size());
        for (size_t i = 0; i < positions.size(); ++i)
            positions[i] = float(scalePosition(values.pixels()[i], legend, settings));
        check(IBA::paste(canvas, 0, 0, 0, 0, viridis(positions, width, height)), canvas, "paste");
    }

    // Colour bar: column i shows the fraction i / (barWidth - 1), so its ends are the map's
    // first and last colours.
    legend.barLeft = kFalseColourMargin;
    legend.barTop = height + kFalseColourBarTop;
    legend.barWidth = canvasWidth - 2 * kFalseColourMargin;
    std::vector<float> ramp(size_t(legend.barWidth) * kFalseColourBarHeight);
    for (size_t i = 0; i < ramp.size(); ++i)
        ramp[i] = float(i % size_t(legend.barWidth)) / float(legend.barWidth - 1);
    check(IBA::paste(canvas, legend.barLeft, legend.barTop, 0, 0,
                     viridis(ramp, legend.barWidth, kFalseColourBarHeight)),
          canvas, "paste");

    // A tick below the bar at each division boundary: the column whose colour its label names.
    const int tickTop = legend.barTop + kFalseColourBarHeight;
    std::vector<int> anchors;
    for (int i = 0; i <= divisions; ++i) {
        anchors.push_back(legend.barLeft +
                          int(std::lround(double(i) * (legend.barWidth - 1) / divisions)));
        check(IBA::fill(canvas, kTextColor,
                        OIIO::ROI(anchors.back(), anchors.back() + 1, tickTop,
                                  tickTop + kFalseColourTickHeight, 0, 1, 0, 3)),
              canvas, "fill");
    }

    // Text: the title above the bar, the labels below the ticks.
    if (font) {
        const int titleBaseline = height + kFalseColourBarTop - 6;
        const int labelBaseline = tickTop + 16;
        check(IBA::render_text(canvas, kFalseColourMargin, titleBaseline, settings.title, kFontSize,
                               font, kTextColor),
              canvas, "render_text");
        for (int i = 0; i <= divisions; ++i) {
            const std::string& text = labelTexts[size_t(i)];
            const int left = labelSpan(i, divisions, textWidth(text, font)).left;
            check(IBA::render_text(canvas, anchors[size_t(i)] - left, labelBaseline, text,
                                   kFontSize, font, kTextColor),
                  canvas, "render_text");
        }
        legend.labelled = true;
    }

    Image result(canvasWidth, canvasHeight, {"R", "G", "B"});
    check(canvas.get_pixels(canvas.roi(), OIIO::TypeDesc::FLOAT, result.pixels().data()), canvas,
          "get_pixels");
    // Pixels without a value, in a colour the map does not contain.
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            if (!std::isfinite(values.at(x, y, 0))) {
                for (int c = 0; c < 3; ++c)
                    result.at(x, y, c) = kNonFiniteColor[c];
            }
        }
    }
    return result;
}

Image renderHeatmap(const Image& error, const std::string& title, HeatmapLegend& legend) {
    FalseColourSettings settings;
    settings.scale = FalseColourScale::Log;
    settings.decades = 4;
    settings.divisions = 2;  // the ends and the geometric mean
    settings.title = title;
    return renderFalseColour(error, settings, legend);
}

}  // namespace penumbra
