#include "core/film.h"

#include "core/errors.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <stdexcept>

namespace penumbra {
namespace {

constexpr float kGaussianRadius = 1.5f;
constexpr float kGaussianSigma = 0.5f;
constexpr float kBlackmanHarrisRadius = 2.0f;

float gaussian(float x, float sigma) {
    return std::exp(-x * x / (2.0f * sigma * sigma)) / (std::sqrt(2.0f * kPi) * sigma);
}

}  // namespace

FilterType parseFilter(std::string_view name) {
    for (FilterType type : {FilterType::Box, FilterType::Gaussian, FilterType::BlackmanHarris}) {
        if (name == filterName(type)) {
            return type;
        }
    }
    throw UsageError("--filter: unknown filter \"" + std::string(name) +
                     "\" (valid: box, gaussian, blackman-harris)");
}

std::string_view filterName(FilterType type) {
    switch (type) {
        case FilterType::Box:
            return "box";
        case FilterType::Gaussian:
            return "gaussian";
        case FilterType::BlackmanHarris:
            return "blackman-harris";
    }
    return "box";
}

PixelFilter::PixelFilter(FilterType type) : type_(type) {
    switch (type) {
        case FilterType::Box:
            radius_ = 0.5f;
            break;
        case FilterType::Gaussian:
            radius_ = kGaussianRadius;
            break;
        case FilterType::BlackmanHarris:
            radius_ = kBlackmanHarrisRadius;
            break;
    }
    // Tabulate f1 at bin midpoints over [-radius, radius] and integrate it into a CDF; the
    // sampled density is this piecewise-constant approximation of f1.
    const int bins = int(std::lround(2.0f * radius_ * float(kBinsPerPixel)));
    const double binWidth = 2.0 * double(radius_) / bins;
    std::vector<double> integral(size_t(bins) + 1, 0.0);
    for (size_t i = 0; i < size_t(bins); ++i) {
        integral[i + 1] = integral[i] + profile(float(-double(radius_) + (i + 0.5) * binWidth));
    }
    cdf_.resize(integral.size());
    for (size_t i = 0; i < cdf_.size(); ++i) {
        cdf_[i] = float(integral[i] / integral.back());
    }
}

float PixelFilter::profile(float x) const {
    x = std::abs(x);
    if (x > radius_) {
        return 0.0f;
    }
    switch (type_) {
        case FilterType::Box:
            return 1.0f;
        case FilterType::Gaussian:
            // Gaussian shifted down to reach zero at the radius (pbrt-v4 Sec. 8.8,
            // GaussianFilter::Evaluate).
            return std::max(
                0.0f, gaussian(x, kGaussianSigma) - gaussian(kGaussianRadius, kGaussianSigma));
        case FilterType::BlackmanHarris: {
            // Minimum 4-term Blackman-Harris window, -92 dB side lobes (Harris 1978, "On the
            // Use of Windows for Harmonic Analysis with the Discrete Fourier Transform",
            // Proc. IEEE 66(1)), w(t) = a0 - a1 cos 2 pi t + a2 cos 4 pi t - a3 cos 6 pi t with
            // t in [0, 1] across the support; its ends are 6e-5, not exactly 0.
            const float t = (x + radius_) / (2.0f * radius_);
            constexpr float a0 = 0.35875f, a1 = 0.48829f, a2 = 0.14128f, a3 = 0.01168f;
            return a0 - a1 * std::cos(2.0f * kPi * t) + a2 * std::cos(4.0f * kPi * t) -
                   a3 * std::cos(6.0f * kPi * t);
        }
    }
    return 0.0f;
}

float PixelFilter::evaluate(Vec2 offset) const {
    return profile(offset.x) * profile(offset.y);
}

float PixelFilter::sample1D(float u) const {
    // The bin whose CDF interval holds u (upper_bound skips empty bins), then the linear
    // inverse of the CDF within it.
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    const size_t bin =
        size_t(std::clamp<ptrdiff_t>(it - cdf_.begin() - 1, 0, ptrdiff_t(cdf_.size()) - 2));
    const float width = cdf_[bin + 1] - cdf_[bin];
    const float t = width > 0.0f ? std::clamp((u - cdf_[bin]) / width, 0.0f, 1.0f) : 0.5f;
    const float binWidth = 2.0f * radius_ / float(cdf_.size() - 1);
    return -radius_ + (float(bin) + t) * binWidth;
}

Vec2 PixelFilter::sampleOffset(Vec2 u) const {
    // The box filter's inverse CDF is the identity: skip the table search.
    if (type_ == FilterType::Box)
        return u - Vec2(0.5f);
    return {sample1D(u.x), sample1D(u.y)};
}

Film::Film(int width, int height, std::vector<AovSpec> aovs)
    : width_(width), height_(height), aovs_(std::move(aovs)) {
    if (width <= 0 || height <= 0) {
        throw std::invalid_argument("Film: empty image");
    }
    for (const AovSpec& aov : aovs_) {
        if (aov.channels.empty() || aov.channels.size() > 3) {
            throw std::invalid_argument("Film: AOV \"" + aov.name + "\" needs 1 to 3 channels");
        }
    }
    const size_t n = size_t(width) * size_t(height);
    pixels_.resize(n);
    aovSums_.assign(aovs_.size(), std::vector<AovSum>(n));
}

size_t Film::index(IVec2 pixel) const {
    assert(pixel.x >= 0 && pixel.x < width_ && pixel.y >= 0 && pixel.y < height_);
    return size_t(pixel.y) * size_t(width_) + size_t(pixel.x);
}

void Film::addSample(IVec2 pixel, const Color& L, float weight) {
    PixelSum& sum = pixels_[index(pixel)];
    const bool finite = isFinite(L) && std::isfinite(weight);
    assert(finite && "non-finite radiance sample reached the film");
    if (!finite) {
        sum.dropped++;
        return;
    }
    for (int c = 0; c < 3; ++c) {
        sum.rgb[c] += double(weight) * double(L[c]);
    }
    sum.weight += weight;
    const double y = luminance(L);
    sum.luminance += y;
    sum.luminanceSquared += y * y;
    sum.count++;
}

float Film::relativeStandardError(IVec2 pixel) const {
    const PixelSum& sum = pixels_[index(pixel)];
    if (sum.count < 2)
        return std::numeric_limits<float>::infinity();
    const double n = sum.count;
    const double mean = sum.luminance / n;
    const double variance =
        std::max(0.0, (sum.luminanceSquared - mean * sum.luminance) / (n - 1.0));
    return float(std::sqrt(variance / n) / std::max(mean, kNoiseFloor));
}

Image Film::resolveSampleCounts() const {
    Image image(width_, height_, {"N"});
    for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x)
            image.at(x, y, 0) = float(pixels_[index({x, y})].count);
    }
    return image;
}

void Film::addAov(IVec2 pixel, int aov, const Vec3& value) {
    assert(aov >= 0 && size_t(aov) < aovs_.size());
    const size_t i = index(pixel);
    const bool finite = isFinite(value);
    assert(finite && "non-finite AOV value reached the film");
    if (!finite) {
        pixels_[i].dropped++;
        return;
    }
    AovSum& sum = aovSums_[size_t(aov)][i];
    for (int c = 0; c < 3; ++c) {
        sum.value[c] += double(value[c]);
    }
    sum.count++;
}

uint64_t Film::droppedSamples() const {
    uint64_t dropped = 0;
    for (const PixelSum& p : pixels_) {
        dropped += p.dropped;
    }
    return dropped;
}

Image Film::resolve() const {
    Image image(width_, height_, {"R", "G", "B"});
    for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
            const PixelSum& sum = pixels_[index({x, y})];
            if (sum.weight == 0.0) {
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                image.at(x, y, c) = float(sum.rgb[c] / sum.weight);
            }
        }
    }
    return image;
}

Image Film::resolveAov(int aov) const {
    assert(aov >= 0 && size_t(aov) < aovs_.size());
    const AovSpec& spec = aovs_[size_t(aov)];
    Image image(width_, height_, spec.channels);
    for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
            const AovSum& sum = aovSums_[size_t(aov)][index({x, y})];
            if (sum.count == 0) {
                continue;
            }
            for (int c = 0; c < image.channels(); ++c) {
                image.at(x, y, c) = float(sum.value[c] / sum.count);
            }
        }
    }
    return image;
}

}  // namespace penumbra
