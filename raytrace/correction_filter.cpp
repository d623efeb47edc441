#include "raytrace/correction_filter.h"

#include "core/math.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace penumbra {

namespace {

// How alike two pixels' surfaces must be to share their correction. The correction is
// continuous along one smooth surface and jumps across edges: a crease (normals 15 degrees
// apart weigh exp(-(1 - cos 15°) / 0.01) = 0.03), a depth step (relative to the distance and to
// how far apart the pixels are, so a slanted wall still counts as one surface) or a change of
// material (albedo).
constexpr float kNormalScale = 0.01f;   // on 1 - cos(angle)
constexpr float kDepthScale = 0.03f;    // relative depth change per pixel of distance
constexpr float kAlbedoScale = 0.05f;   // on the largest channel difference
constexpr float kMinimumSigma = 0.25f;  // below: a Gaussian of one pixel, nothing to average

Vec3 pixel3(const Image& image, int x, int y) {
    return Vec3(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
}

// A pixel's mean normal made unit again (the mean of its samples' normals is shorter at an edge),
// or zero where nothing was hit.
Vec3 unitNormal(const Image& normal, int x, int y) {
    const Vec3 n = pixel3(normal, x, y);
    const float length = glm::length(n);
    return length > 0.0f ? n / length : Vec3(0.0f);
}

// 1 - cos of the angle between two unit normals; two pixels that hit nothing are alike.
float normalGap(const Vec3& a, const Vec3& b) {
    const bool hitA = a != Vec3(0.0f), hitB = b != Vec3(0.0f);
    if (!hitA || !hitB)
        return hitA == hitB ? 0.0f : 1.0f;
    return 1.0f - glm::dot(a, b);
}

// Pixels within this many pixels (each axis) of the centre are in a filter of width sigma.
int reachOf(float sigma) {
    return static_cast<int>(std::ceil(2.0f * sigma));
}

// How alike two pixels' surfaces are, as a weight in (0, 1], from the guide's features gathered
// per pixel once (the normals made unit) rather than once per neighbour.
class SurfaceLikeness {
  public:
    explicit SurfaceLikeness(const FilterGuide& guide)
        : width_(guide.normal.width()),
          features_(static_cast<size_t>(width_) * guide.normal.height()) {
        for (int y = 0; y < guide.normal.height(); ++y)
            for (int x = 0; x < width_; ++x)
                features_[static_cast<size_t>(y) * width_ + x] = {unitNormal(guide.normal, x, y),
                                                                  guide.depth.at(x, y, 0),
                                                                  pixel3(guide.albedo, x, y)};
    }

    // Pixel (qx, qy) seen from pixel (x, y), `distance` pixels apart.
    float operator()(int x, int y, int qx, int qy, float distance) const {
        const Features& p = at(x, y);
        const Features& q = at(qx, qy);
        const float angleGap = normalGap(p.normal, q.normal);
        const float depthGap = std::abs(q.depth - p.depth) /
                               (kDepthScale * std::max(p.depth, 1e-6f) * std::max(distance, 1.0f));
        const float albedoGap = maxComponent(glm::abs(q.albedo - p.albedo)) / kAlbedoScale;
        return std::exp(-angleGap / kNormalScale - depthGap - sqr(albedoGap));
    }

  private:
    struct Features {
        Vec3 normal;
        float depth;
        Vec3 albedo;
    };
    const Features& at(int x, int y) const {
        return features_[static_cast<size_t>(y) * width_ + x];
    }

    int width_;
    std::vector<Features> features_;
};

// A Gaussian of width sigma tabulated over a square window of half-width `reach` (at least the
// filter's own reach, zero beyond it), with each offset's distance: no exp per neighbour.
class GaussianWindow {
  public:
    GaussianWindow(float sigma, int reach)
        : reach_(reach), weights_(sqr(size_t(2 * reach + 1))), distances_(weights_.size()) {
        const int own = sigma < kMinimumSigma ? -1 : reachOf(sigma);
        for (int dy = -reach; dy <= reach; ++dy) {
            for (int dx = -reach; dx <= reach; ++dx) {
                const size_t i = index(dx, dy);
                const float d2 = float(sqr(dx) + sqr(dy));
                distances_[i] = std::sqrt(d2);
                const bool inside = std::abs(dx) <= own && std::abs(dy) <= own;
                weights_[i] = inside ? std::exp(-0.5f * d2 / sqr(sigma)) : 0.0f;
            }
        }
    }

    int reach() const { return reach_; }
    float weight(int dx, int dy) const { return weights_[index(dx, dy)]; }
    float distance(int dx, int dy) const { return distances_[index(dx, dy)]; }

  private:
    size_t index(int dx, int dy) const {
        return static_cast<size_t>(dy + reach_) * size_t(2 * reach_ + 1) + size_t(dx + reach_);
    }

    int reach_;
    std::vector<float> weights_, distances_;
};

// Calls visit(qx, qy, w) for each pixel of `window` around (x, y) inside the image, w being the
// window's Gaussian times how alike the two surfaces are: the weight of a cross-bilateral filter.
template <typename Visit>
void forEachNeighbour(int x, int y, int width, int height, const GaussianWindow& window,
                      const SurfaceLikeness& likeness, Visit visit) {
    const int reach = window.reach();
    for (int qy = std::max(y - reach, 0); qy <= std::min(y + reach, height - 1); ++qy) {
        for (int qx = std::max(x - reach, 0); qx <= std::min(x + reach, width - 1); ++qx) {
            const int dx = qx - x, dy = qy - y;
            visit(qx, qy, likeness(x, y, qx, qy, window.distance(dx, dy)) * window.weight(dx, dy));
        }
    }
}

// The candidate widths of chooseFilterWidths, narrowest first.
constexpr int kCandidates = 4;
constexpr int kDefaultCandidate = 2;  // sigma itself
using Candidates = std::array<float, kCandidates>;

Candidates candidateWidths(float sigma) {
    return {0.0f, 0.5f * sigma, sigma, std::max(sigma, std::min(2.0f * sigma, kWidestChosenSigma))};
}

// Each candidate's SURE of one pixel's squared error (summed over the channels), NaN where the
// pixel's variance is unknown. windows: each candidate's Gaussian over the widest's window.
Candidates pixelRisks(const NoisyImage& image, const SurfaceLikeness& likeness,
                      const std::array<GaussianWindow, kCandidates>& windows, int x, int y) {
    const Image& mean = image.mean;
    const int channels = mean.channels();
    double variance = 0.0;
    for (int c = 0; c < channels; ++c) {
        const float v = image.varianceOfMean.at(x, y, c);
        if (!(v >= 0.0f))
            return Candidates{NAN, NAN, NAN, NAN};
        variance += v;
    }
    std::array<std::array<double, 3>, kCandidates> sums{};
    std::array<double, kCandidates> weights{};
    const int reach = windows[0].reach();
    for (int qy = std::max(y - reach, 0); qy <= std::min(y + reach, mean.height() - 1); ++qy) {
        for (int qx = std::max(x - reach, 0); qx <= std::min(x + reach, mean.width() - 1); ++qx) {
            const int dx = qx - x, dy = qy - y;
            const float alike = likeness(x, y, qx, qy, windows[0].distance(dx, dy));
            for (size_t k = 0; k < kCandidates; ++k) {
                const double w = double(alike) * windows[k].weight(dx, dy);
                if (w <= 0.0)
                    continue;
                weights[k] += w;
                for (int c = 0; c < channels; ++c)
                    sums[k][size_t(c)] += w * mean.at(qx, qy, c);
            }
        }
    }
    Candidates risks;
    for (size_t k = 0; k < kCandidates; ++k) {
        // A width below the filter's smallest leaves the pixel as it is: F = y, dF/dy = 1.
        if (weights[k] <= 0.0) {
            risks[k] = float(variance);
            continue;
        }
        double error = 0.0;
        for (int c = 0; c < channels; ++c)
            error += sqr(sums[k][size_t(c)] / weights[k] - mean.at(x, y, c));
        risks[k] = float(error + variance * (2.0 / weights[k] - 1.0));
    }
    return risks;
}

}  // namespace

float correctionFilterSigma(float sigmaAtOneSample, double samplesPerPixel) {
    return sigmaAtOneSample *
           static_cast<float>(std::pow(std::max(samplesPerPixel, 1.0), -1.0 / 6.0));
}

Image filterCorrection(const Image& image, const FilterGuide& guide, float sigma) {
    if (sigma < kMinimumSigma)
        return image;
    return filterCorrection(
        image, guide,
        std::vector<float>(static_cast<size_t>(image.width()) * image.height(), sigma));
}

Image filterCorrection(const Image& image, const FilterGuide& guide,
                       const std::vector<float>& widths) {
    const int width = image.width(), height = image.height(), channels = image.channels();
    const SurfaceLikeness likeness(guide);
    // One window per distinct width (chooseFilterWidths gives a few).
    std::vector<std::pair<float, GaussianWindow>> windows;
    for (const float sigma : widths) {
        if (sigma >= kMinimumSigma &&
            std::none_of(windows.begin(), windows.end(),
                         [sigma](const auto& w) { return w.first == sigma; }))
            windows.emplace_back(sigma, GaussianWindow(sigma, reachOf(sigma)));
    }
    Image filtered(width, height, image.channelNames());
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        std::vector<double> sum(static_cast<size_t>(channels));
        for (int y = rows.begin(); y < rows.end(); ++y) {
            for (int x = 0; x < width; ++x) {
                const float sigma = widths[static_cast<size_t>(y) * width + x];
                if (sigma < kMinimumSigma) {
                    for (int c = 0; c < channels; ++c)
                        filtered.at(x, y, c) = image.at(x, y, c);
                    continue;
                }
                const GaussianWindow& window =
                    std::find_if(windows.begin(), windows.end(), [sigma](const auto& w) {
                        return w.first == sigma;
                    })->second;
                std::fill(sum.begin(), sum.end(), 0.0);
                double weightSum = 0.0;
                forEachNeighbour(x, y, width, height, window, likeness,
                                 [&](int qx, int qy, float w) {
                                     weightSum += w;
                                     for (int c = 0; c < channels; ++c)
                                         sum[size_t(c)] += double(w) * image.at(qx, qy, c);
                                 });
                // weightSum >= 1: the pixel itself (d2 0, no gap) weighs exp(0).
                for (int c = 0; c < channels; ++c)
                    filtered.at(x, y, c) = float(sum[size_t(c)] / weightSum);
            }
        }
    });
    return filtered;
}

namespace {

// The pixels a window of half-width `reach` covers, summed over every centre along an axis of
// `length` pixels, the window clipped at both ends.
double clippedWindowSum(int length, int reach) {
    double sum = 0.0;
    for (int i = 0; i < length; ++i)
        sum += std::min(i + reach, length - 1) - std::max(i - reach, 0) + 1;
    return sum;
}

}  // namespace

double reconstructionVisits(int width, int height, float sigma, int layers) {
    if (sigma < kMinimumSigma)
        return 0.0;
    const int reach = reachOf(candidateWidths(sigma).back());
    // The window is a rectangle, clipped on each axis alone: its sum over the image factorises.
    const double window = clippedWindowSum(width, reach) * clippedWindowSum(height, reach);
    return window * (2.0 + layers);
}

double secondsPerReconstructionVisit() {
    static const double seconds = [] {
        // A flat 32 x 32 image (one surface, unit variance) at sigma 4, whose widest candidate
        // is the widest there is (kWidestChosenSigma): 1.8 million pairs, about 20 ms on 2
        // cores, and within 10 % of the cost per pair of images up to 256 x 256.
        constexpr int kSize = 32;
        constexpr float kSigma = 4.0f;
        const Image zero(kSize, kSize, {"R", "G", "B"});
        Image normal(kSize, kSize, {"X", "Y", "Z"}), variance(kSize, kSize, {"R", "G", "B"});
        for (int y = 0; y < kSize; ++y) {
            for (int x = 0; x < kSize; ++x) {
                normal.at(x, y, 2) = 1.0f;
                for (int c = 0; c < 3; ++c)
                    variance.at(x, y, c) = 1.0f;
            }
        }
        const Image depth(kSize, kSize, {"Z"});
        const FilterGuide guide{normal, depth, zero};
        const auto start = std::chrono::steady_clock::now();
        const std::vector<float> widths = chooseFilterWidths({zero, variance}, guide, kSigma);
        const Image filtered = filterCorrection(zero, guide, widths);
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return elapsed / reconstructionVisits(kSize, kSize, kSigma, 1);
    }();
    return seconds;
}

std::vector<float> chooseFilterWidths(const NoisyImage& image, const FilterGuide& guide,
                                      float sigma) {
    const int width = image.mean.width(), height = image.mean.height();
    const size_t pixels = static_cast<size_t>(width) * height;
    std::vector<float> chosen(pixels, sigma);
    if (sigma < kMinimumSigma)
        return chosen;
    const Candidates widths = candidateWidths(sigma);
    const int reach = reachOf(widths.back());
    const std::array<GaussianWindow, kCandidates> windows{
        GaussianWindow(widths[0], reach), GaussianWindow(widths[1], reach),
        GaussianWindow(widths[2], reach), GaussianWindow(widths[3], reach)};
    const SurfaceLikeness likeness(guide);
    std::vector<Candidates> risks(pixels, Candidates{NAN, NAN, NAN, NAN});
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < width; ++x)
                risks[static_cast<size_t>(y) * width + x] =
                    pixelRisks(image, likeness, windows, x, y);
    });
    // Each pixel's risks averaged over its surface (the widest candidate's filter, over the
    // pixels whose variance is known), then the least; ties keep sigma.
    const GaussianWindow& smoothing = windows.back();
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y) {
            for (int x = 0; x < width; ++x) {
                std::array<double, kCandidates> mean{};
                double weightSum = 0.0;
                forEachNeighbour(
                    x, y, width, height, smoothing, likeness, [&](int qx, int qy, float w) {
                        const Candidates& r = risks[static_cast<size_t>(qy) * width + qx];
                        if (std::isnan(r[0]))
                            return;
                        weightSum += w;
                        for (size_t k = 0; k < kCandidates; ++k)
                            mean[k] += double(w) * r[k];
                    });
                if (!(weightSum > 0.0))
                    continue;  // no estimate near: sigma
                size_t best = kDefaultCandidate;
                for (size_t k = 0; k < kCandidates; ++k)
                    if (mean[k] < mean[best])
                        best = k;
                chosen[static_cast<size_t>(y) * width + x] = widths[best];
            }
        }
    });
    return chosen;
}

}  // namespace penumbra
