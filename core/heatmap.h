// A false-colour picture of a per-pixel error with its legend, for `penumbra diff --heatmap`.
// Drawn with OpenImageIO's ImageBufAlgo (color_map, fill, paste, render_text); write the result
// with writeImage (core/image_io.h), which goes through a temporary file and a rename.
#pragma once

#include "core/image.h"

#include <string>

namespace penumbra {

// Layout of the legend strip below the map, in pixels (docs/cli.md shows it).
inline constexpr int kHeatmapMinWidth = 320;     // the picture is at least this wide
inline constexpr int kHeatmapLegendHeight = 64;  // strip added below the map
inline constexpr int kHeatmapMargin = 10;        // left and right of the colour bar
inline constexpr int kHeatmapBarTop = 22;        // colour bar, from the top of the strip
inline constexpr int kHeatmapBarHeight = 14;

// What the colours mean.
struct HeatmapLegend {
    // Log scale: low (and below, zero included) is the colour map's first colour, high its last.
    // high = the largest finite error, low = high x 1e-4; both 0 when every error is 0.
    double low = 0.0, high = 0.0;
    size_t nonFinite = 0;   // pixels drawn magenta (linear (1, 0, 1)): NaN or infinite error
    bool labelled = false;  // false when no font was found: the values are not drawn
};

// Maps `error` (one channel, values >= 0) with the viridis colour map of van der Walt and Smith
// (matplotlib 1.5, 2015; OpenImageIO's "viridis" table, perceptually uniform and readable in
// grey and by colour-blind viewers) on a log10 scale, and adds below it a legend: `title`, a
// colour bar and the values at its ends and middle (the middle is the geometric mean). Returns
// linear RGB, (max(width, kHeatmapMinWidth)) x (height + kHeatmapLegendHeight), the map at the
// top left. Labels use the DejaVu Sans font (Debian's fonts-dejavu-core) or OpenImageIO's
// default; without either the legend has no text and `legend.labelled` is false.
Image renderHeatmap(const Image& error, const std::string& title, HeatmapLegend& legend);

}  // namespace penumbra
