// False-colour pictures of a one-channel image with a labelled legend: rendered luminance
// (cd/m²) or illuminance (lux) read as Radiance's falsecolor shows them (Ward, "The RADIANCE
// Lighting Simulation and Rendering System", SIGGRAPH 1994; falsecolor's -s, -log and -n), and
// the per-pixel error of `penumbra diff --heatmap`. Drawn with OpenImageIO's ImageBufAlgo
// (color_map, fill, paste, render_text); write the result with writeImage (core/image_io.h),
// which goes through a temporary file and a rename.
#pragma once

#include "core/image.h"

#include <cstddef>
#include <string>
#include <vector>

namespace penumbra {

// Layout of the legend strip below the map, in pixels (docs/cli.md shows it). The legend sits
// below rather than beside the map because most views are landscape: a fixed-height strip
// barely changes their shape, and the labels read along the bar like a ruler. A tall, narrow
// map is widened with background to fit the labels instead.
inline constexpr int kFalseColourMinWidth = 320;     // the picture is at least this wide
inline constexpr int kFalseColourLegendHeight = 64;  // strip added below the map
inline constexpr int kFalseColourMargin = 10;        // left and right of the colour bar
inline constexpr int kFalseColourBarTop = 22;        // colour bar, from the top of the strip
inline constexpr int kFalseColourBarHeight = 14;
inline constexpr int kFalseColourTickHeight = 3;  // division marks, below the bar
// Linear grey behind the legend and beside narrow maps; also what a map may show where it has
// no value (the cells of a workplane's bounding rectangle outside the workplane).
inline constexpr float kFalseColourBackground = 0.01f;

enum class FalseColourScale { Linear, Log };

// How values become colours. Values are in whatever unit the image holds (cd/m², lux, a
// relative error); the title should name it.
struct FalseColourSettings {
    FalseColourScale scale = FalseColourScale::Log;
    // Top of the scale (> 0, finite), or 0 for automatic:
    // - log: the largest finite value;
    // - linear: divisions x the smallest step in {1, 2, 2.5, 3, 4, 5} x 10^k that makes the
    //   scale reach the 99th percentile of the finite values (the largest value if that
    //   percentile is 0), so that every label is a round number and a few glare pixels (a
    //   luminaire or a sun patch in view) do not squash the rest of the picture into the first
    //   colours; the pixels above show as the last colour.
    double maximum = 0.0;
    int decades = 4;  // log: the scale spans maximum / 10^decades .. maximum; 1 to 30
    // Labelled steps along the bar, 1 to 100 (more labels than that cannot be read along one
    // bar, and each widens the picture).
    int divisions = 8;
    std::string title;  // drawn above the bar, e.g. "luminance, cd/m²" or "illuminance, lux"
};

// What the colours mean and where the legend is.
struct FalseColourLegend {
    // The scale's ends, in the values' unit: a value at or below `low` (zero and negative values
    // included) is the colour map's first colour, one at or above `high` its last. Linear: low
    // = 0. Log: low = high / 10^decades. Both 0 when no value is finite and > 0.
    double low = 0.0, high = 0.0;
    size_t nonFinite = 0;   // pixels drawn magenta (linear (1, 0, 1)): NaN or infinite value
    bool labelled = false;  // false when no font was found: the title and labels are not drawn
    // The values at the division boundaries, low first, high last (divisions + 1 of them),
    // whether drawn or not: label i is at fraction i / divisions of the bar, under its tick.
    std::vector<double> labels;
    // The colour bar: columns barLeft .. barLeft + barWidth - 1, rows barTop .. barTop +
    // kFalseColourBarHeight - 1 of the picture; column barLeft + i shows the colour of the
    // fraction i / (barWidth - 1) of the scale.
    int barLeft = 0, barTop = 0, barWidth = 0;
};

// The legend of the error heat map: the same fields.
using HeatmapLegend = FalseColourLegend;

// A legend value as the labels show it: 3 significant digits, in plain notation from 0.001 to
// below 10^6 ("0.00316", "31.6", "1000", "31600"), in short scientific notation beyond ("1e-4",
// "2.5e7").
std::string formatLegendValue(double value);

// Maps `values` (one channel) with the viridis colour map of van der Walt and Smith (matplotlib
// 1.5, 2015; OpenImageIO's "viridis" table, perceptually uniform, increasing in lightness and
// readable in grey and by colour-blind viewers) on `settings`' scale, and adds below it a
// legend: the title, the colour bar with a tick at each division boundary and the value there.
// Returns linear RGB of width max(values' width, kFalseColourMinWidth, what the title and
// labels need) and height values' height + kFalseColourLegendHeight, the map at the top left.
// Text uses the DejaVu Sans font (Debian's fonts-dejavu-core) or OpenImageIO's default; without
// either the legend has no text and `legend.labelled` is false. Throws std::invalid_argument
// for an image of more than one channel or settings out of their ranges.
Image renderFalseColour(const Image& values, const FalseColourSettings& settings,
                        FalseColourLegend& legend);

// The error heat map of `penumbra diff --heatmap`: `error` (one channel, values >= 0) on a log
// scale of four decades below its largest finite value, labelled at the ends and the middle
// (the geometric mean of the ends), under `title`.
Image renderHeatmap(const Image& error, const std::string& title, HeatmapLegend& legend);

}  // namespace penumbra
