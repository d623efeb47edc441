#include "core/image_metrics.h"

#include "core/errors.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <stdexcept>

namespace penumbra {
namespace {

// Rec. ITU-R BT.709-6, item 3.2: luminance from linear R, G, B.
constexpr double kLuminanceWeights[3] = {0.2126, 0.7152, 0.0722};

// SSIM constants of Wang et al. 2004, Sec. III-C: an 11 x 11 circular-symmetric Gaussian window
// of standard deviation 1.5, K1 = 0.01, K2 = 0.03, dynamic range L = 1 (see the header).
constexpr int kSsimRadius = 5;
constexpr double kSsimSigma = 1.5;
constexpr double kSsimC1 = 0.01 * 0.01;  // (K1 L)^2
constexpr double kSsimC2 = 0.03 * 0.03;  // (K2 L)^2

using Plane = std::vector<double>;
using Mask = std::vector<uint8_t>;

constexpr std::array<std::string_view, kAllMetrics.size()> kMetricNames = {
    "rmse", "relmse", "mae", "mre", "psnr", "ssim"};

std::string describeSize(const std::string& name, const Image& image) {
    return name + " (" + std::to_string(image.width()) + " x " + std::to_string(image.height()) +
           ")";
}

std::string channelList(const Image& image) {
    std::string list;
    for (const std::string& name : image.channelNames())
        list += (list.empty() ? "" : ", ") + name;
    return list;
}

// Channel indices in the test and reference images, in the order compared.
void resolveChannels(const Image& test, const Image& reference, const MetricOptions& options,
                     std::vector<std::string>& names, std::vector<int>& testIndex,
                     std::vector<int>& referenceIndex) {
    names = options.channels;
    if (names.empty()) {
        const bool rgb = reference.channelIndex("R") >= 0 && reference.channelIndex("G") >= 0 &&
                         reference.channelIndex("B") >= 0;
        names = rgb ? std::vector<std::string>{"R", "G", "B"} : reference.channelNames();
    }
    for (const std::string& name : names) {
        const int t = test.channelIndex(name), r = reference.channelIndex(name);
        if (t < 0 || r < 0) {
            const bool inTest = t >= 0;
            const std::string& file = inTest ? options.referenceName : options.testName;
            throw InputError(file + ": no channel \"" + name +
                             "\" (channels: " + channelList(inTest ? reference : test) + ")");
        }
        testIndex.push_back(t);
        referenceIndex.push_back(r);
    }
}

// One channel of an image as doubles, row-major.
Plane extractChannel(const Image& image, int channel) {
    Plane plane(size_t(image.width()) * size_t(image.height()));
    const size_t n = size_t(image.channels());
    for (size_t i = 0; i < plane.size(); ++i)
        plane[i] = image.pixels()[i * n + size_t(channel)];
    return plane;
}

// Region label of every compared pixel (block): index into `values`, or -1 for a block that
// straddles regions. Without a mask, one region.
std::vector<int> regionLabels(const Image* mask, int k, int width, int height,
                              const MetricOptions& options, std::vector<float>& values,
                              size_t& mixedBlocks) {
    std::vector<int> labels(size_t(width) * size_t(height), 0);
    if (!mask) {
        values = {0.0f};
        return labels;
    }
    std::vector<float> blockValue(labels.size());
    for (int by = 0; by < height; ++by) {
        for (int bx = 0; bx < width; ++bx) {
            const float first = mask->at(bx * k, by * k, 0);
            bool uniform = true;
            for (int y = by * k; y < std::min((by + 1) * k, mask->height()); ++y) {
                for (int x = bx * k; x < std::min((bx + 1) * k, mask->width()); ++x) {
                    const float v = mask->at(x, y, 0);
                    if (!std::isfinite(v)) {
                        throw InputError(options.maskName + ": pixel (" + std::to_string(x) + ", " +
                                         std::to_string(y) + ") is not a finite number");
                    }
                    uniform = uniform && v == first;
                }
            }
            const size_t i = size_t(by) * size_t(width) + size_t(bx);
            blockValue[i] = first;
            labels[i] = uniform ? 0 : -1;
        }
    }
    std::map<float, int> index;
    for (size_t i = 0; i < labels.size(); ++i) {
        if (labels[i] >= 0)
            index.emplace(blockValue[i], 0);
    }
    values.clear();
    for (auto& [value, label] : index) {
        label = int(values.size());
        values.push_back(value);
    }
    mixedBlocks = 0;
    for (size_t i = 0; i < labels.size(); ++i) {
        if (labels[i] < 0)
            ++mixedBlocks;
        else
            labels[i] = index.at(blockValue[i]);
    }
    return labels;
}

using Kernel = std::array<double, 2 * kSsimRadius + 1>;

// One pass of the separable window, along x or along y: out = sum of kernel-weighted
// neighbours of in. Taps outside the image count 0.
void gaussianPass(const Plane& in, Plane& out, int width, int height, bool alongX,
                  const Kernel& kernel) {
    const int length = alongX ? width : height;
    const std::ptrdiff_t stride = alongX ? 1 : width;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const int position = alongX ? x : y;
            const std::ptrdiff_t i = std::ptrdiff_t(y) * width + x;
            double sum = 0.0;
            for (int d = std::max(-kSsimRadius, -position);
                 d <= std::min(kSsimRadius, length - 1 - position); ++d)
                sum += kernel[size_t(d + kSsimRadius)] * in[size_t(i + d * stride)];
            out[size_t(i)] = sum;
        }
    }
}

// In place: the Gaussian-weighted window sum of Wang et al. eq. 14 at each pixel, unnormalised
// (callers divide by the window sum of the validity).
void gaussianSum(Plane& plane, int width, int height, const Kernel& kernel) {
    Plane rows(plane.size());
    gaussianPass(plane, rows, width, height, true, kernel);
    gaussianPass(rows, plane, width, height, false, kernel);
}

// The SSIM map of Wang et al. 2004, eq. 13, with the local statistics of eq. 14-16 (mean,
// standard deviation and covariance weighted by the Gaussian window), over valid pixels only;
// NaN at invalid ones. x and y are already in [0, 1].
Plane ssimMap(const Plane& x, const Plane& y, const Mask& valid, int width, int height) {
    Kernel kernel;
    for (int d = -kSsimRadius; d <= kSsimRadius; ++d)
        kernel[size_t(d + kSsimRadius)] = std::exp(-0.5 * d * d / (kSsimSigma * kSsimSigma));
    // Window sums of w, w x, w y, w x^2, w y^2, w x y with w = 0 at invalid pixels.
    std::array<Plane, 6> sums;
    for (Plane& s : sums)
        s.assign(x.size(), 0.0);
    for (size_t i = 0; i < x.size(); ++i) {
        if (!valid[i])
            continue;
        sums[0][i] = 1.0;
        sums[1][i] = x[i];
        sums[2][i] = y[i];
        sums[3][i] = x[i] * x[i];
        sums[4][i] = y[i] * y[i];
        sums[5][i] = x[i] * y[i];
    }
    for (Plane& s : sums)
        gaussianSum(s, width, height, kernel);
    Plane map(x.size(), std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < x.size(); ++i) {
        if (!valid[i])
            continue;
        const double w = sums[0][i];
        const double mx = sums[1][i] / w, my = sums[2][i] / w;
        // Clamped at 0: E[x^2] - E[x]^2 can round below zero on flat regions.
        const double vx = std::max(0.0, sums[3][i] / w - mx * mx);
        const double vy = std::max(0.0, sums[4][i] / w - my * my);
        const double cxy = sums[5][i] / w - mx * my;
        map[i] = (2.0 * mx * my + kSsimC1) * (2.0 * cxy + kSsimC2) /
                 ((mx * mx + my * my + kSsimC1) * (vx + vy + kSsimC2));
    }
    return map;
}

double ssimValue(double v, SsimInput input) {
    if (input == SsimInput::Display)
        return v;
    v = std::max(v, 0.0);
    return v / (1.0 + v);
}

// Per-pixel terms whose means are the metrics: squared error, relMSE term, absolute error, MRE
// term, SSIM (0 when not computed).
enum Term { kSquared, kRelSquared, kAbsolute, kRelative, kSsim, kTermCount };

// Sums of each term over each region, for one row.
struct RowSums {
    std::vector<std::array<double, kTermCount>> sums;  // per region
};

// Adds the terms of the planes x (test) and y (reference) at valid pixels to their region's sums
// in `row` (unless the pixel is a mixed block), and to `pooled` (per pixel, for row "all" and the
// error map) if not null.
void accumulateRow(const Plane& x, const Plane& y, const Mask& valid,
                   const std::vector<int>& labels, int width, int height,
                   const MetricOptions& options, RowSums& row,
                   std::array<Plane, kTermCount>* pooled) {
    Plane ssim;
    if (options.computeSsim) {
        Plane xs(x.size()), ys(y.size());
        for (size_t i = 0; i < x.size(); ++i) {
            xs[i] = ssimValue(x[i], options.ssimInput);
            ys[i] = ssimValue(y[i], options.ssimInput);
        }
        ssim = ssimMap(xs, ys, valid, width, height);
    }
    for (size_t i = 0; i < x.size(); ++i) {
        if (!valid[i])
            continue;
        const double d = x[i] - y[i];
        const double denominator = y[i] * y[i] + options.relMseEpsilon;
        std::array<double, kTermCount> terms = {d * d, d * d / denominator, std::abs(d),
                                                std::abs(d) / std::sqrt(denominator),
                                                options.computeSsim ? ssim[i] : 0.0};
        for (int term = 0; term < kTermCount; ++term) {
            if (labels[i] >= 0)
                row.sums[size_t(labels[i])][size_t(term)] += terms[size_t(term)];
            if (pooled)
                (*pooled)[size_t(term)][i] += terms[size_t(term)];
        }
    }
}

// Metrics from the mean of each term: RMSE and PSNR from the mean squared error.
MetricValues metricsFromMeans(const std::array<double, kTermCount>& means, double peak,
                              bool computeSsim) {
    MetricValues values;
    values[Metric::Rmse] = std::sqrt(means[kSquared]);
    values[Metric::RelMse] = means[kRelSquared];
    values[Metric::Mae] = means[kAbsolute];
    values[Metric::Mre] = means[kRelative];
    // 10 log10(peak^2 / MSE); MSE = 0 gives +infinity, as it should.
    values[Metric::Psnr] = 10.0 * std::log10(peak * peak / means[kSquared]);
    if (computeSsim)
        values[Metric::Ssim] = means[kSsim];
    return values;
}

}  // namespace

std::string_view metricName(Metric metric) {
    return kMetricNames[size_t(metric)];
}

std::optional<Metric> findMetric(std::string_view name) {
    for (const Metric m : kAllMetrics) {
        if (metricName(m) == name)
            return m;
    }
    return std::nullopt;
}

std::string metricNameList() {
    std::string list;
    for (const Metric m : kAllMetrics)
        list += (list.empty() ? "" : ", ") + std::string(metricName(m));
    return list;
}

bool higherIsBetter(Metric metric) {
    return metric == Metric::Psnr || metric == Metric::Ssim;
}

int MetricReport::rowIndex(std::string_view name) const {
    for (size_t i = 0; i < rowNames.size(); ++i) {
        if (rowNames[i] == name)
            return int(i);
    }
    return -1;
}

Image downsampleBlocks(const Image& image, int k) {
    if (k < 1)
        throw std::invalid_argument("downsampleBlocks: block size below 1");
    const int width = (image.width() + k - 1) / k, height = (image.height() + k - 1) / k;
    Image result(width, height, image.channelNames());
    for (int by = 0; by < height; ++by) {
        for (int bx = 0; bx < width; ++bx) {
            const int x1 = std::min((bx + 1) * k, image.width());
            const int y1 = std::min((by + 1) * k, image.height());
            const double n = double(x1 - bx * k) * double(y1 - by * k);
            for (int c = 0; c < image.channels(); ++c) {
                double sum = 0.0;
                for (int y = by * k; y < y1; ++y) {
                    for (int x = bx * k; x < x1; ++x)
                        sum += image.at(x, y, c);
                }
                result.at(bx, by, c) = float(sum / n);
            }
        }
    }
    return result;
}

size_t countNonFinitePixels(const Image& image, const std::vector<int>& channels) {
    const size_t n = size_t(image.channels());
    const size_t pixels = size_t(image.width()) * size_t(image.height());
    size_t count = 0;
    for (size_t i = 0; i < pixels; ++i) {
        bool finite = true;
        for (const int c : channels)
            finite = finite && std::isfinite(image.pixels()[i * n + size_t(c)]);
        count += finite ? 0 : 1;
    }
    return count;
}

MetricReport computeMetrics(const Image& test, const Image& reference, const Image* mask,
                            const MetricOptions& options, Image* errorMap) {
    // Refuse what cannot be compared, naming the files.
    if (test.width() != reference.width() || test.height() != reference.height()) {
        throw InputError(describeSize(options.testName, test) + " and " +
                         describeSize(options.referenceName, reference) + " differ in size");
    }
    if (mask && (mask->width() != reference.width() || mask->height() != reference.height())) {
        throw InputError(describeSize(options.maskName, *mask) + " and " +
                         describeSize(options.referenceName, reference) + " differ in size");
    }
    if (options.downsample < 1)
        throw InputError("the block size for downsampling must be at least 1");
    if (!(options.relMseEpsilon > 0.0))
        throw InputError("the epsilon of the relative MSE must be positive");
    std::vector<std::string> channels;
    std::vector<int> testIndex, referenceIndex;
    resolveChannels(test, reference, options, channels, testIndex, referenceIndex);

    MetricReport report;
    report.masked = mask != nullptr;
    report.testNonFinite = countNonFinitePixels(test, testIndex);
    report.referenceNonFinite = countNonFinitePixels(reference, referenceIndex);

    // The compared images: block means, one plane per compared channel.
    const int k = options.downsample;
    const Image testBlocks = k > 1 ? downsampleBlocks(test, k) : Image();
    const Image referenceBlocks = k > 1 ? downsampleBlocks(reference, k) : Image();
    const Image& t = k > 1 ? testBlocks : test;
    const Image& r = k > 1 ? referenceBlocks : reference;
    report.width = t.width();
    report.height = t.height();
    const size_t pixels = size_t(t.width()) * size_t(t.height());
    std::vector<Plane> x, y;
    for (size_t c = 0; c < channels.size(); ++c) {
        x.push_back(extractChannel(t, testIndex[c]));
        y.push_back(extractChannel(r, referenceIndex[c]));
    }
    Mask valid(pixels, 1);
    for (size_t i = 0; i < pixels; ++i) {
        for (size_t c = 0; c < channels.size(); ++c)
            valid[i] = valid[i] && std::isfinite(x[c][i]) && std::isfinite(y[c][i]);
    }

    std::vector<float> regionValues;
    const std::vector<int> labels =
        regionLabels(mask, k, t.width(), t.height(), options, regionValues, report.mixedBlocks);

    // Luminance planes when R, G and B are all compared.
    const auto rgb = [&](const char* name) {
        return std::find(channels.begin(), channels.end(), name) - channels.begin();
    };
    const size_t red = size_t(rgb("R")), green = size_t(rgb("G")), blue = size_t(rgb("B"));
    const bool luminance =
        red < channels.size() && green < channels.size() && blue < channels.size();
    report.rowNames = channels;
    if (luminance)
        report.rowNames.push_back("luminance");
    report.rowNames.push_back("all");

    // PSNR peak: the reference's largest compared value unless given.
    report.peak = options.peak;
    if (!(report.peak > 0.0)) {
        report.peak = 0.0;
        for (size_t c = 0; c < channels.size(); ++c) {
            for (size_t i = 0; i < pixels; ++i) {
                if (valid[i])
                    report.peak = std::max(report.peak, y[c][i]);
            }
        }
    }

    // Sums of the per-pixel terms, per row and region.
    const size_t regionCount = regionValues.size();
    std::vector<RowSums> rows(report.rowNames.size());
    for (RowSums& row : rows)
        row.sums.assign(regionCount, {});
    std::array<Plane, kTermCount> pooled;
    for (Plane& p : pooled)
        p.assign(pixels, 0.0);
    for (size_t c = 0; c < channels.size(); ++c)
        accumulateRow(x[c], y[c], valid, labels, t.width(), t.height(), options, rows[c], &pooled);
    if (luminance) {
        Plane xl(pixels), yl(pixels);
        for (size_t i = 0; i < pixels; ++i) {
            xl[i] = kLuminanceWeights[0] * x[red][i] + kLuminanceWeights[1] * x[green][i] +
                    kLuminanceWeights[2] * x[blue][i];
            yl[i] = kLuminanceWeights[0] * y[red][i] + kLuminanceWeights[1] * y[green][i] +
                    kLuminanceWeights[2] * y[blue][i];
        }
        accumulateRow(xl, yl, valid, labels, t.width(), t.height(), options, rows[channels.size()],
                      nullptr);
    }
    // Row "all": the channel terms' sums divided by the channel count.
    std::vector<size_t> regionPixels(regionCount, 0);
    for (size_t i = 0; i < pixels; ++i) {
        if (!valid[i] || labels[i] < 0)
            continue;
        ++regionPixels[size_t(labels[i])];
        for (int term = 0; term < kTermCount; ++term)
            rows.back().sums[size_t(labels[i])][size_t(term)] +=
                pooled[size_t(term)][i] / double(channels.size());
    }

    // Region means, then the mean over regions that have pixels.
    report.regions.resize(regionCount);
    report.rows.resize(report.rowNames.size());
    for (size_t g = 0; g < regionCount; ++g) {
        report.regions[g].maskValue = regionValues[g];
        report.regions[g].pixels = regionPixels[g];
        report.comparedPixels += regionPixels[g];
    }
    for (size_t row = 0; row < rows.size(); ++row) {
        std::array<double, kTermCount> meanOfMeans = {};
        size_t usedRegions = 0;
        for (size_t g = 0; g < regionCount; ++g) {
            std::array<double, kTermCount> means;
            for (int term = 0; term < kTermCount; ++term)
                means[size_t(term)] = rows[row].sums[g][size_t(term)] / double(regionPixels[g]);
            report.regions[g].rows.push_back(
                metricsFromMeans(means, report.peak, options.computeSsim));
            if (regionPixels[g] == 0)
                continue;
            ++usedRegions;
            for (int term = 0; term < kTermCount; ++term)
                meanOfMeans[size_t(term)] += means[size_t(term)];
        }
        for (double& m : meanOfMeans)
            m = usedRegions > 0 ? m / double(usedRegions)
                                : std::numeric_limits<double>::quiet_NaN();
        report.rows[row] = metricsFromMeans(meanOfMeans, report.peak, options.computeSsim);
    }

    if (errorMap) {
        *errorMap = Image(t.width(), t.height(), {"relmse"});
        for (size_t i = 0; i < pixels; ++i) {
            errorMap->pixels()[i] = valid[i]
                                        ? float(pooled[kRelSquared][i] / double(channels.size()))
                                        : std::numeric_limits<float>::quiet_NaN();
        }
    }
    return report;
}

}  // namespace penumbra
