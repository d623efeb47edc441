#include "core/histogram_adjustment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace penumbra {
namespace {

constexpr double kLowestLuminance = 1e-4;  // cd/m², the lower threshold of vision (§4.2)
constexpr double kTrimTolerance = 0.025;   // of the original count (§4.4, its footnote 1)

void checkDisplay(const HistogramAdjustmentSettings& settings) {
    const double Ldmin = settings.displayMinimum, Ldmax = settings.displayMaximum;
    if (!(Ldmin > 0.0 && Ldmax > Ldmin && std::isfinite(Ldmax)))
        throw std::invalid_argument("histogram adjustment: needs 0 < Ld_min < Ld_max < infinity");
}

double finiteOrZero(float value) {
    return std::isfinite(value) && value > 0.0f ? double(value) : 0.0;
}

// B = log(L) (§4.1), with the floor that keeps black finite.
double brightness(double luminance) {
    return std::log(std::max(luminance, kLowestLuminance));
}

// A float raster of `channels` values a pixel, sampled with its pixel centres at integers.
struct Grid {
    int width = 0, height = 0, channels = 0;
    std::vector<float> values;

    Grid(int w, int h, int c) : width(w), height(h), channels(c), values(size_t(w) * h * c) {}
    float& at(int x, int y, int c) { return values[(size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const { return values[(size_t(y) * width + x) * channels + c]; }

    // Bilinear interpolation at (u, v), clamped to the edge samples.
    double sample(double u, double v, int c) const {
        u = std::clamp(u, 0.0, double(width - 1));
        v = std::clamp(v, 0.0, double(height - 1));
        const int x0 = int(u), y0 = int(v);
        const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
        const double tx = u - x0, ty = v - y0;
        const double top = (1.0 - tx) * at(x0, y0, c) + tx * at(x1, y0, c);
        const double bottom = (1.0 - tx) * at(x0, y1, c) + tx * at(x1, y1, c);
        return (1.0 - ty) * top + ty * bottom;
    }
};

double luminance(const Grid& rgb, int x, int y) {
    // Rec. 709 Y, as core/math.h's luminance(), in double: the mapping's monotonicity across
    // neighbouring pixels must not rest on float rounding.
    return 0.2126 * rgb.at(x, y, 0) + 0.7152 * rgb.at(x, y, 1) + 0.0722 * rgb.at(x, y, 2);
}

// The foveal sample image (§4.2): the luminance box-filtered down to about 1° square pixels,
// S = 2 tan(θ/2) / 0.01745 of them across a view angle θ (Eq. 1); never more than the image has.
Grid fovealLuminance(const Grid& rgb, double tanHalfWidth) {
    const double across = 2.0 * tanHalfWidth / 0.01745;
    const int fw = std::clamp(int(std::lround(across)), 1, rgb.width);
    const int fh = std::clamp(int(std::lround(across * rgb.height / rgb.width)), 1, rgb.height);
    Grid fovea(fw, fh, 1);
    for (int j = 0; j < fh; ++j)
        for (int i = 0; i < fw; ++i) {
            // Every pixel falls in one block, weighted alike, as the paper's box filter
            const int x0 = i * rgb.width / fw, x1 = (i + 1) * rgb.width / fw;
            const int y0 = j * rgb.height / fh, y1 = (j + 1) * rgb.height / fh;
            double sum = 0.0;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x)
                    sum += luminance(rgb, x, y);
            fovea.at(i, j, 0) = float(sum / double((x1 - x0) * (y1 - y0)));
        }
    return fovea;
}

// The next coarser level of a mip map (Williams 1983): 2 x 2 box averages, over the pixels that
// exist at an odd edge.
Grid halve(const Grid& fine) {
    Grid coarse((fine.width + 1) / 2, (fine.height + 1) / 2, fine.channels);
    for (int y = 0; y < coarse.height; ++y)
        for (int x = 0; x < coarse.width; ++x) {
            const int x1 = std::min(2 * x + 2, fine.width), y1 = std::min(2 * y + 2, fine.height);
            const double count = double((x1 - 2 * x) * (y1 - 2 * y));
            for (int c = 0; c < fine.channels; ++c) {
                double sum = 0.0;
                for (int fy = 2 * y; fy < y1; ++fy)
                    for (int fx = 2 * x; fx < x1; ++fx)
                        sum += fine.at(fx, fy, c);
                coarse.at(x, y, c) = float(sum / count);
            }
        }
    return coarse;
}

// Loss of acuity (§5.3): each pixel keeps the detail its foveal adaptation resolves, R(L_a)
// cycles/degree (Eq. 15), by a variable-resolution filter over a mip map. R is interpolated
// between the four nearest foveal samples, as the paper does. Level k of the pyramid holds
// frequencies up to ppd / 2^(k+1) cycles/degree (Nyquist, ppd pixels a degree), so a pixel reads
// level log2(ppd / (2 R)), interpolating between the two nearest levels. ppd is the one at the
// image centre; toward the corners of a wide view a pixel spans a little less angle, so the blur
// there is slightly too weak.
Grid blurByAcuity(const Grid& rgb, const Grid& fovea, double tanHalfWidth) {
    const double pixelsPerDegree = 0.5 * rgb.width / tanHalfWidth * std::numbers::pi / 180.0;
    Grid acuity(fovea.width, fovea.height, 1);
    double lowest = std::numeric_limits<double>::infinity();
    for (int j = 0; j < fovea.height; ++j)
        for (int i = 0; i < fovea.width; ++i) {
            acuity.at(i, j, 0) = visualAcuity(fovea.at(i, j, 0));
            lowest = std::min(lowest, double(acuity.at(i, j, 0)));
        }
    const double coarsest = std::log2(pixelsPerDegree / (2.0 * lowest));
    if (coarsest <= 0.0)
        return rgb;  // every place resolves finer than a pixel
    std::vector<Grid> pyramid{rgb};
    while (int(pyramid.size()) <= int(std::ceil(coarsest)) &&
           (pyramid.back().width > 1 || pyramid.back().height > 1))
        pyramid.push_back(halve(pyramid.back()));

    Grid blurred(rgb.width, rgb.height, 3);
    for (int y = 0; y < rgb.height; ++y)
        for (int x = 0; x < rgb.width; ++x) {
            const double R = acuity.sample((x + 0.5) * fovea.width / rgb.width - 0.5,
                                           (y + 0.5) * fovea.height / rgb.height - 0.5, 0);
            const double level =
                std::clamp(std::log2(pixelsPerDegree / (2.0 * R)), 0.0, double(pyramid.size() - 1));
            const int k0 = int(level), k1 = std::min(k0 + 1, int(pyramid.size()) - 1);
            const double t = level - k0;
            for (int c = 0; c < 3; ++c) {
                // Level k's pixel i covers fine pixels [2^k i, 2^k (i + 1))
                const auto fromLevel = [&](int k) {
                    const double scale = std::ldexp(1.0, -k);
                    return pyramid[size_t(k)].sample((x + 0.5) * scale - 0.5,
                                                     (y + 0.5) * scale - 0.5, c);
                };
                blurred.at(x, y, c) = float((1.0 - t) * fromLevel(k0) + t * fromLevel(k1));
            }
        }
    return blurred;
}

}  // namespace

float detectionThreshold(float adaptationLuminance) {
    // Table 1, log10 ΔL_t as a function of log10 L_a. Its fourth row prints log(L_a), a slip for
    // log10: Ferwerda et al.'s cone fit is in log10 and is continuous with its neighbours only so.
    if (!(adaptationLuminance >= 1.148e-4f))  // log10 L_a < -3.94, including 0 and NaN
        return float(std::pow(10.0, -2.86));
    const double x = std::log10(double(adaptationLuminance));
    double logThreshold;
    if (x < -1.44)
        logThreshold = std::pow(0.405 * x + 1.6, 2.18) - 2.86;  // rods
    else if (x < -0.0184)
        logThreshold = x - 0.395;
    else if (x < 1.9)
        logThreshold = std::pow(0.249 * x + 0.65, 2.7) - 0.72;  // cones
    else
        logThreshold = x - 1.255;
    return float(std::pow(10.0, logThreshold));
}

float visualAcuity(float adaptationLuminance) {
    const double La = std::max(finiteOrZero(adaptationLuminance), kLowestLuminance);
    return float(17.25 * std::atan(1.4 * std::log10(La) + 0.35) + 25.72);  // Eq. 15
}

HistogramToneCurve::HistogramToneCurve(std::span<const float> adaptationLuminances,
                                       const HistogramAdjustmentSettings& settings)
    : displayMinimum_(settings.displayMinimum), displayMaximum_(settings.displayMaximum) {
    checkDisplay(settings);

    // The histogram's ends (§4.2): the dimmest sample, no lower than the threshold of vision, and
    // the brightest.
    std::vector<double> samples;
    samples.reserve(adaptationLuminances.size());
    for (float L : adaptationLuminances)
        samples.push_back(brightness(finiteOrZero(L)));
    brightnessMinimum_ = brightness(0.0);
    brightnessMaximum_ = brightness(0.0);
    if (!samples.empty()) {
        const auto [lo, hi] = std::minmax_element(samples.begin(), samples.end());
        brightnessMinimum_ = *lo;
        brightnessMaximum_ = *hi;
    }

    // When the scene's range fits the display's, no histogram meets the ceiling (Eq. 5d) and
    // "a simple linear operator" is applied from the outset (§4.4).
    if (brightnessMaximum_ - brightnessMinimum_ > std::log(displayMaximum_ / displayMinimum_)) {
        std::array<double, kBins> counts{};
        const double binsPerUnit = kBins / (brightnessMaximum_ - brightnessMinimum_);
        for (double b : samples)
            counts[size_t(std::min(int((b - brightnessMinimum_) * binsPerUnit), kBins - 1))] += 1.0;
        linear_ = !trimToCeiling(counts, settings.humanContrast);
    }
    if (!linear_)
        return;

    // The paper leaves the linear operator open; this is its authors' (Radiance's pcond): the
    // log-average world luminance maps to the display's log-middle, either in luminance or, with
    // the human model, in detection threshold, Ward's 1991 and Ferwerda et al.'s global scale
    // factor that §4.5 builds on.
    const double average = samples.empty() ? brightnessMinimum_
                                           : std::accumulate(samples.begin(), samples.end(), 0.0) /
                                                 double(samples.size());
    const double displayMiddle = std::sqrt(displayMinimum_ * displayMaximum_);
    const double worldAverage = std::exp(average);
    if (settings.humanContrast) {
        scale_ = detectionThreshold(float(displayMiddle)) / detectionThreshold(float(worldAverage));
    } else {
        // Keep every sample above the display's black: a range that fits should all be seen. The
        // human model does not, since that would raise contrast above the thresholds' ratio.
        scale_ =
            std::max(displayMiddle / worldAverage, displayMinimum_ / std::exp(brightnessMinimum_));
    }
    // Neither puts a sample above the display's white.
    scale_ = std::min(scale_, displayMaximum_ / std::exp(brightnessMaximum_));
}

// histogram_ceiling() of §4.4: truncate the bins above the ceiling, which lowers the total T and
// so the ceiling, until a pass trims no more than 2.5% of the original count. False when the
// total falls below that tolerance first. Leaves P(b) of the adjusted histogram in cumulative_.
bool HistogramToneCurve::trimToCeiling(std::array<double, kBins>& counts, bool humanContrast) {
    const double binWidth = (brightnessMaximum_ - brightnessMinimum_) / kBins;  // Δb
    const double displayRange = std::log(displayMaximum_ / displayMinimum_);
    const double original = std::accumulate(counts.begin(), counts.end(), 0.0);
    const double tolerance = kTrimTolerance * original;
    double trimmings = 0.0;
    do {
        const double total = std::accumulate(counts.begin(), counts.end(), 0.0);
        if (total < tolerance)
            return false;
        setCumulative(counts);  // Eq. 7c's Ld depends on the current P(b)
        trimmings = 0.0;
        for (int i = 0; i < kBins; ++i) {
            // Eq. 5c, the linear ceiling: Eq. 5a's dLd/dLw <= Ld/Lw for the curve of Eq. 4,
            // whose slope comes from Eq. 3's dP/db = f(b) / (T Δb)
            const double b = brightnessMinimum_ + (i + 0.5) * binWidth;
            double ceiling = total * binWidth / displayRange;
            if (humanContrast) {
                // Eq. 7c: dLd/dLw <= ΔL_t(Ld) / ΔL_t(Lw) (7a) instead
                const double Lw = std::exp(b), Ld = std::exp(displayBrightness(b));
                ceiling *= detectionThreshold(float(Ld)) / detectionThreshold(float(Lw)) * Lw / Ld;
            }
            if (counts[size_t(i)] > ceiling) {
                trimmings += counts[size_t(i)] - ceiling;
                counts[size_t(i)] = ceiling;
            }
        }
    } while (trimmings > tolerance);
    // The curve is the trimmed histogram's: its bins are under the ceilings of the last pass, made
    // with a total larger by at most the tolerance.
    setCumulative(counts);
    keptFraction_ = std::accumulate(counts.begin(), counts.end(), 0.0) / original;
    return true;
}

void HistogramToneCurve::setCumulative(const std::array<double, kBins>& counts) {
    const double total = std::accumulate(counts.begin(), counts.end(), 0.0);
    double sum = 0.0;
    for (int i = 0; i < kBins; ++i) {
        cumulative_[size_t(i)] = sum / total;
        sum += counts[size_t(i)];
    }
    cumulative_[kBins] = 1.0;
}

// B_de of Eq. 4, with P(b) interpolated linearly between the bin edges: within bin i its slope is
// then exactly Eq. 3's f(b_i) / (T Δb), the derivative the ceilings bound.
double HistogramToneCurve::displayBrightness(double worldBrightness) const {
    const double x = std::clamp(
        (worldBrightness - brightnessMinimum_) / (brightnessMaximum_ - brightnessMinimum_) * kBins,
        0.0, double(kBins));
    const int i = std::min(int(x), kBins - 1);
    const double P =
        cumulative_[size_t(i)] + (x - i) * (cumulative_[size_t(i) + 1] - cumulative_[size_t(i)]);
    return std::log(displayMinimum_) + std::log(displayMaximum_ / displayMinimum_) * P;
}

float HistogramToneCurve::displayLuminance(float worldLuminance) const {
    const double Lw = finiteOrZero(worldLuminance);
    if (linear_)
        return float(std::min(scale_ * Lw, displayMaximum_));
    return float(std::exp(displayBrightness(brightness(Lw))));
}

Image histogramAdjust(const Image& sceneLinear, const HistogramAdjustmentSettings& settings) {
    const int channels[3] = {sceneLinear.channelIndex("R"), sceneLinear.channelIndex("G"),
                             sceneLinear.channelIndex("B")};
    if (std::min({channels[0], channels[1], channels[2]}) < 0)
        throw std::invalid_argument("histogramAdjust: the image needs channels R, G and B");
    const float fov = settings.horizontalFieldOfViewDegrees;
    if (!(fov > 0.0f && fov < 180.0f))
        throw std::invalid_argument("histogramAdjust: the field of view must be in (0, 180) deg");
    checkDisplay(settings);

    const int width = sceneLinear.width(), height = sceneLinear.height();
    Image display(width, height, {"R", "G", "B"});
    if (width == 0 || height == 0)
        return display;

    Grid rgb(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                rgb.at(x, y, c) = float(finiteOrZero(sceneLinear.at(x, y, channels[c])));

    // The order of §6's match_visibility(): foveal samples, acuity blur, histogram, mapping
    const double tanHalfWidth = std::tan(0.5 * double(fov) * std::numbers::pi / 180.0);
    const Grid fovea = fovealLuminance(rgb, tanHalfWidth);
    if (settings.humanAcuity)
        rgb = blurByAcuity(rgb, fovea, tanHalfWidth);
    const HistogramToneCurve curve(fovea.values, settings);

    const double Ldmin = settings.displayMinimum, Ldmax = settings.displayMaximum;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double Lw = luminance(rgb, x, y);
            if (!(Lw > 0.0))
                continue;  // black stays black
            const double Ld = curve.displayLuminance(
                float(std::min(Lw, double(std::numeric_limits<float>::max()))));
            const double v = std::clamp((Ld - Ldmin) / (Ldmax - Ldmin), 0.0, 1.0);
            // Every channel scaled by one factor keeps the hue (chromaticity)
            for (int c = 0; c < 3; ++c)
                display.at(x, y, c) = float(std::min(rgb.at(x, y, c) * v / Lw, 1.0));
        }
    return display;
}

}  // namespace penumbra
