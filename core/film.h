// The film: per-pixel sums of radiance samples and AOVs, and the pixel reconstruction filters.
//
// Reconstruction uses filter importance sampling (pbrt-v4, Pharr, Jakob and Humphreys 2023,
// Sec. 8.8, "FilterSampler"; Ernst et al. 2006, "Filter Importance Sampling"): the camera
// places each sample of pixel p at p + (0.5, 0.5) + filter.sampleOffset(u), with the offset
// distributed as the filter, and the sample is added to pixel p alone with weight f/pdf, which
// is 1 for the positive filters here. No sample is ever splatted into a neighbour, so tiles
// never write to each other's pixels, and as each pixel's samples are added by one thread in a
// fixed order the image is identical whatever the thread count.
#pragma once

#include "core/image.h"
#include "core/math.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

enum class FilterType { Box, Gaussian, BlackmanHarris };

// "box", "gaussian" or "blackman-harris"; anything else throws UsageError listing these.
FilterType parseFilter(std::string_view name);
std::string_view filterName(FilterType type);

// A separable pixel reconstruction filter f(x, y) = f1(x) f1(y), |x|, |y| <= radius (pixels):
//   box:             f1 = 1, radius 0.5 (each sample counts in the pixel it falls in);
//   gaussian:        radius 1.5, sigma 0.5, minus its value at the radius so it reaches 0
//                    there (pbrt-v4's GaussianFilter);
//   blackman-harris: radius 2, the minimum 4-term Blackman-Harris window (Harris 1978).
class PixelFilter {
  public:
    explicit PixelFilter(FilterType type = FilterType::Box);

    FilterType type() const { return type_; }
    // Half-width of the support, in pixels.
    float radius() const { return radius_; }
    // Unnormalised filter value at an offset (pixels) from the pixel centre.
    float evaluate(Vec2 offset) const;
    // Offset (pixels, relative to the pixel centre, each coordinate in [-radius, radius])
    // distributed proportionally to the filter, from a uniform 2D sample. Each axis inverts a
    // tabulated CDF with kBinsPerPixel piecewise-constant bins per pixel of width (1024 bins for
    // blackman-harris), so the filter actually applied is f at that resolution; sample weights
    // are exactly 1.
    Vec2 sampleOffset(Vec2 u) const;

    static constexpr int kBinsPerPixel = 256;

  private:
    float profile(float x) const;  // f1
    float sample1D(float u) const;

    FilterType type_;
    float radius_;
    std::vector<float> cdf_;  // bins + 1 entries over [-radius, radius], cdf_.back() == 1
};

// An AOV layer: its name ("albedo") and the names of its 1 to 3 channels ({"R", "G", "B"},
// {"X", "Y", "Z"}, {"Z"}); a file names them "<name>.<channel>".
struct AovSpec {
    std::string name;
    std::vector<std::string> channels{"R", "G", "B"};
};

class Film {
  public:
    Film(int width, int height, std::vector<AovSpec> aovs = {});

    int width() const { return width_; }
    int height() const { return height_; }
    const std::vector<AovSpec>& aovs() const { return aovs_; }

    // Adds a radiance sample L (cd/m², linear sRGB) with weight f/pdf to `pixel` (x right,
    // y down, (0, 0) top-left). A sample with a non-finite L or weight asserts in debug builds
    // and is dropped (and counted) in release builds: the tracer should never produce one.
    // Not synchronised: each pixel must be written by one thread at a time.
    void addSample(IVec2 pixel, const Color& L, float weight);
    // Adds one value of AOV layer `aov` (index into aovs()); only the first
    // aovs()[aov].channels.size() components are used. Non-finite values as in addSample.
    void addAov(IVec2 pixel, int aov, const Vec3& value);

    // Samples added to (and not dropped from) `pixel`.
    uint32_t sampleCount(IVec2 pixel) const { return pixels_[index(pixel)].count; }
    // The pixel's error estimate for adaptive sampling: the standard error of its mean luminance,
    // sqrt(s² / n) with s² the unbiased sample variance of the n samples' luminance, relative to
    // max(mean luminance, kNoiseFloor). Infinite below two samples.
    float relativeStandardError(IVec2 pixel) const;
    // Luminance (cd/m²) below which the error counts as relative to this floor instead: as the
    // epsilon of relative MSE (core/image_metrics.h), it keeps black pixels from needing ever more
    // samples for a vanishing error.
    static constexpr double kNoiseFloor = 1e-2;
    // Samples per pixel, one channel "N".
    Image resolveSampleCounts() const;
    // Radiance samples and AOV values dropped for being non-finite, over the whole film.
    uint64_t droppedSamples() const;

    // Weighted mean radiance per pixel (sum w L / sum w), channels R, G, B; 0 where no sample
    // (or only zero weights) arrived.
    Image resolve() const;
    // Mean of the values added to each pixel, channels named as in the AovSpec.
    Image resolveAov(int aov) const;

  private:
    struct PixelSum {
        double rgb[3] = {0.0, 0.0, 0.0};
        double weight = 0.0;
        double luminance = 0.0, luminanceSquared = 0.0;  // moments for the error estimate
        uint32_t count = 0;
        uint32_t dropped = 0;  // per pixel, so counting needs no synchronisation either
    };
    struct AovSum {
        double value[3] = {0.0, 0.0, 0.0};
        uint32_t count = 0;
    };

    size_t index(IVec2 pixel) const;

    int width_, height_;
    std::vector<AovSpec> aovs_;
    std::vector<PixelSum> pixels_;
    std::vector<std::vector<AovSum>> aovSums_;  // [aov][pixel]
};

}  // namespace penumbra
