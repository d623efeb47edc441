// Image-difference metrics between a test image and a reference: RMSE, relative MSE, mean
// absolute and mean relative error, PSNR and SSIM, per channel, on Rec. 709 luminance and over
// all channels pooled; optionally over the regions of a mask and on K x K block means. Used by
// `penumbra diff` (docs/cli.md) and meant as the basis of the test suite's image comparisons.
// No file formats here: images come from core/image_io.h.
//
// Definitions, for a test value x and a reference value y of one channel at one pixel:
//   RMSE    sqrt(mean (x - y)^2)
//   relMSE  mean (x - y)^2 / (y^2 + eps): the relative MSE of Rousselle, Knaus and Zwicker,
//           "Adaptive Sampling and Reconstruction using Greedy Error Minimization" (TOG 30(6),
//           2011), as used for the comparisons of Bitterli et al., "Nonlinearly Weighted
//           First-order Regression for Denoising Monte Carlo Renderings" (CGF 35(4), 2016).
//           eps = 1e-2 by default: it keeps black reference pixels from dominating (the term is
//           at most 100 (x - y)^2 there) and weighs values above 0.1, the range of a lit scene
//           in cd/m^2 or of a display image, by their relative error.
//   MAE     mean |x - y|
//   MRE     mean |x - y| / sqrt(y^2 + eps): the square root of relMSE's per-pixel term, so both
//           share one eps and MRE^2 <= relMSE (Jensen).
//   PSNR    10 log10(peak^2 / MSE) dB, peak = the reference's largest value over the compared
//           channels unless given; +infinity for identical images.
//   SSIM    Wang, Bovik, Sheikh and Simoncelli, "Image Quality Assessment: From Error
//           Visibility to Structural Similarity" (IEEE TIP 13(4), 2004), eq. 13 with the
//           Gaussian window of eq. 14-16: 11 x 11, sigma 1.5, K1 = 0.01, K2 = 0.03, dynamic
//           range L = 1. Display values (8-bit formats, in [0, 1]) are used as they are; HDR
//           values are first mapped by v / (1 + v) (Reinhard et al., "Photographic Tone
//           Reproduction for Digital Images", SIGGRAPH 2002, eq. 3), which puts every radiance in
//           [0, 1) without clipping highlights, so L = 1 holds for both. Where the window leaves
//           the image or covers an excluded pixel, its weights are renormalised over the rest
//           (Wang's reference code instead drops a 5-pixel border).
// Every metric except PSNR and SSIM is the mean of a per-pixel term; SSIM the mean of its
// per-pixel map. Row "all" pools the channels: the mean over channels of each per-pixel term
// (and of the SSIM maps), PSNR from the pooled MSE.
#pragma once

#include "core/image.h"

#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

enum class Metric { Rmse, RelMse, Mae, Mre, Psnr, Ssim };
inline constexpr std::array<Metric, 6> kAllMetrics = {Metric::Rmse, Metric::RelMse, Metric::Mae,
                                                      Metric::Mre,  Metric::Psnr,   Metric::Ssim};

// "rmse", "relmse", "mae", "mre", "psnr", "ssim".
std::string_view metricName(Metric metric);
// The metric called `name` (as metricName gives it), or nothing.
std::optional<Metric> findMetric(std::string_view name);
// "rmse, relmse, mae, mre, psnr, ssim", for messages.
std::string metricNameList();
// PSNR and SSIM grow as the images get closer; the others shrink.
bool higherIsBetter(Metric metric);

// One value per metric; NaN where not computed or undefined (no pixels).
struct MetricValues {
    std::array<double, kAllMetrics.size()> values;
    MetricValues() { values.fill(std::numeric_limits<double>::quiet_NaN()); }
    double& operator[](Metric m) { return values[size_t(m)]; }
    double operator[](Metric m) const { return values[size_t(m)]; }
};

enum class SsimInput {
    Display,   // values as they are, expected in [0, 1] (8-bit formats)
    Reinhard,  // v / (1 + v) first, for scene-linear HDR values
};

struct MetricOptions {
    // Channels to compare, by name; empty: R, G, B when the reference has them, else all of the
    // reference's channels. Each must exist in both images.
    std::vector<std::string> channels;
    double relMseEpsilon = 1e-2;  // eps of relMSE and MRE, in the images' units squared
    int downsample = 1;           // compare K x K block means (1: the pixels themselves)
    double peak = 0.0;            // PSNR peak; 0: the reference's largest compared value
    bool computeSsim = true;      // SSIM costs about as much as all other metrics together
    SsimInput ssimInput = SsimInput::Reinhard;
    // Names used in error messages (file names at the command line).
    std::string testName = "test", referenceName = "reference", maskName = "mask";
};

// The metrics over one region of the mask (or the whole image without a mask).
struct RegionMetrics {
    float maskValue = 0.0f;          // the mask's value (first channel) in this region
    size_t pixels = 0;               // compared pixels in the region (after downsampling)
    std::vector<MetricValues> rows;  // as MetricReport::rowNames
};

struct MetricReport {
    // The compared channels, then "luminance" (Rec. 709: 0.2126 R + 0.7152 G + 0.0722 B, of
    // the values as stored) when R, G and B are compared, then "all".
    std::vector<std::string> rowNames;
    // Per row: the mean over regions of each region's metric (for RMSE and PSNR, of its MSE),
    // so that every region counts equally; without a mask, the whole image's metrics.
    std::vector<MetricValues> rows;
    std::vector<RegionMetrics> regions;  // by increasing mask value; one without a mask
    bool masked = false;

    // Pixels of the full-resolution inputs with a NaN or infinite value in a compared channel.
    // They are left out of every metric; a caller should treat any as an error in itself.
    size_t testNonFinite = 0, referenceNonFinite = 0;

    int width = 0, height = 0;  // the compared resolution (after downsampling)
    size_t comparedPixels = 0;  // pixels (blocks) that entered the metrics
    size_t mixedBlocks = 0;     // blocks left out because they straddle mask regions
    double peak = 0.0;          // the PSNR peak used

    // Index of the row called `name`, or -1.
    int rowIndex(std::string_view name) const;
};

// Compares `test` with `reference` (same size; `mask`, if given, too: its first channel's
// distinct values are the regions). A block or pixel with a non-finite compared value in either
// image is left out; with a mask and downsample > 1, so is a block whose mask values differ.
// Throws InputError (core/errors.h) naming the images for different sizes, a missing channel
// or downsample < 1. If `errorMap` is not null it receives, at the compared resolution, one
// channel "relmse" with the per-pixel relMSE term of row "all" (NaN where left out).
MetricReport computeMetrics(const Image& test, const Image& reference, const Image* mask,
                            const MetricOptions& options, Image* errorMap = nullptr);

// K x K block means: ceil(width / k) x ceil(height / k) pixels, same channels; blocks at the
// right and bottom edges average the pixels they cover. A non-finite value makes its block's
// channel non-finite. Throws std::invalid_argument for k < 1.
Image downsampleBlocks(const Image& image, int k);

// Pixels with a NaN or infinite value in any of `channels` (indices into image's channels).
size_t countNonFinitePixels(const Image& image, const std::vector<int>& channels);

}  // namespace penumbra
