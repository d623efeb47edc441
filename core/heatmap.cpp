#include "core/heatmap.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace penumbra {
namespace {

namespace IBA = OIIO::ImageBufAlgo;

constexpr double kDecades = 4.0;  // the log scale spans high x 1e-4 .. high
constexpr int kFontSize = 13;
constexpr float kBackground = 0.01f;  // linear grey behind the legend and beside narrow maps
constexpr float kTextColor[3] = {1.0f, 1.0f, 1.0f};
constexpr float kNonFiniteColor[3] = {1.0f, 0.0f, 1.0f};

// The first font OpenImageIO can load: Debian's OpenImageIO finds no default font of its own
// (its DroidSans is not packaged), so DejaVu Sans is asked for by name first. "" if none.
const char* findFont() {
    for (const char* font : {"DejaVuSans", ""}) {
        if (IBA::text_size("0.5", kFontSize, font).defined())
            return font;
    }
    OIIO::geterror();  // clear the failed look-ups' messages
    return nullptr;
}

std::string formatValue(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

// Position on the colour scale, in [0, 1].
float scalePosition(double value, const HeatmapLegend& legend) {
    if (!(legend.high > 0.0) || !(value > legend.low))
        return 0.0f;
    const double t = std::log10(value / legend.low) / kDecades;
    return float(std::min(t, 1.0));
}

void check(bool ok, const OIIO::ImageBuf& buffer, const char* what) {
    if (!ok)
        throw std::runtime_error(std::string("heat map: ") + what + ": " + buffer.geterror());
}

}  // namespace

Image renderHeatmap(const Image& error, const std::string& title, HeatmapLegend& legend) {
    if (error.channels() != 1)
        throw std::invalid_argument("renderHeatmap: the error image must have one channel");
    const int width = error.width(), height = error.height();

    // The scale: four decades below the largest finite error.
    legend = HeatmapLegend{};
    for (const float e : error.pixels()) {
        if (std::isfinite(e))
            legend.high = std::max(legend.high, double(e));
        else
            ++legend.nonFinite;
    }
    legend.low = legend.high * std::pow(10.0, -kDecades);

    // Canvas: background, then the map at the top left.
    const int canvasWidth = std::max(width, kHeatmapMinWidth);
    const int canvasHeight = height + kHeatmapLegendHeight;
    OIIO::ImageBuf canvas(OIIO::ImageSpec(canvasWidth, canvasHeight, 3, OIIO::TypeDesc::FLOAT));
    const float background[3] = {kBackground, kBackground, kBackground};
    check(IBA::fill(canvas, background), canvas, "fill");
    if (width > 0 && height > 0) {
        std::vector<float> positions(error.pixels().size());
        for (size_t i = 0; i < positions.size(); ++i)
            positions[i] = scalePosition(error.pixels()[i], legend);
        OIIO::ImageBuf scale(OIIO::ImageSpec(width, height, 1, OIIO::TypeDesc::FLOAT));
        check(scale.set_pixels(scale.roi(), OIIO::TypeDesc::FLOAT, positions.data()), scale,
              "set_pixels");
        const OIIO::ImageBuf colours = IBA::color_map(scale, 0, "viridis");
        check(!colours.has_error(), colours, "color_map");
        check(IBA::paste(canvas, 0, 0, 0, 0, colours), canvas, "paste");
    }

    // Colour bar: a left-to-right ramp 0..1 through the same map.
    const int barWidth = canvasWidth - 2 * kHeatmapMargin;
    const int barTop = height + kHeatmapBarTop;
    const float zero[1] = {0.0f}, one[1] = {1.0f};
    const OIIO::ImageBuf ramp =
        IBA::fill(zero, one, zero, one, OIIO::ROI(0, barWidth, 0, kHeatmapBarHeight, 0, 1, 0, 1));
    const OIIO::ImageBuf bar = IBA::color_map(ramp, 0, "viridis");
    check(!bar.has_error(), bar, "color_map");
    check(IBA::paste(canvas, kHeatmapMargin, barTop, 0, 0, bar), canvas, "paste");

    // Text: the title above the bar, the values at its ends and middle below it.
    if (const char* font = findFont()) {
        const int titleBaseline = height + kHeatmapBarTop - 6;
        const int labelBaseline = barTop + kHeatmapBarHeight + 16;
        const double mid = std::sqrt(legend.low * legend.high);
        struct Label {
            int x;
            std::string text;
            IBA::TextAlignX align;
        };
        const Label labels[] = {
            {kHeatmapMargin, title, IBA::TextAlignX::Left},
            {kHeatmapMargin, formatValue(legend.low), IBA::TextAlignX::Left},
            {canvasWidth / 2, formatValue(mid), IBA::TextAlignX::Center},
            {canvasWidth - kHeatmapMargin, formatValue(legend.high), IBA::TextAlignX::Right},
        };
        for (const Label& label : labels) {
            const int baseline = &label == &labels[0] ? titleBaseline : labelBaseline;
            check(IBA::render_text(canvas, label.x, baseline, label.text, kFontSize, font,
                                   kTextColor, label.align),
                  canvas, "render_text");
        }
        legend.labelled = true;
    }

    Image result(canvasWidth, canvasHeight, {"R", "G", "B"});
    check(canvas.get_pixels(canvas.roi(), OIIO::TypeDesc::FLOAT, result.pixels().data()), canvas,
          "get_pixels");
    // Pixels without an error value, in a colour the map does not contain.
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            if (!std::isfinite(error.at(x, y, 0))) {
                for (int c = 0; c < 3; ++c)
                    result.at(x, y, c) = kNonFiniteColor[c];
            }
        }
    }
    return result;
}

}  // namespace penumbra
