#include "tests/support/chi2.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

namespace penumbra {
namespace {

constexpr double kPiD = std::numbers::pi;

Vec3 sphericalDirection(double cosTheta, double phi) {
    const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
    return Vec3(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)), float(cosTheta));
}

// Composite 3-point Gauss-Legendre rule with n x n panels over [c0, c1] x [p0, p1] in
// (cos theta, phi), where d(solid angle) = dcos dphi. An open rule: it never evaluates the bin
// edges, where a density is typically discontinuous (the horizon, cos theta = 0, is one).
double gaussLegendre2D(const std::function<float(const Vec3&)>& pdf, double c0, double c1,
                       double p0, double p1, int n) {
    static const double kNodes[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    static const double kWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    const double hc = (c1 - c0) / n, hp = (p1 - p0) / n;
    double sum = 0.0;
    for (int i = 0; i < 3 * n; ++i) {
        const double c = c0 + hc * (i / 3 + 0.5 + 0.5 * kNodes[i % 3]);
        for (int j = 0; j < 3 * n; ++j) {
            const double p = p0 + hp * (j / 3 + 0.5 + 0.5 * kNodes[j % 3]);
            sum += kWeights[i % 3] * kWeights[j % 3] * pdf(sphericalDirection(c, p));
        }
    }
    return sum * 0.25 * hc * hp;
}

// Integral of pdf over one bin, the panel count doubled until two successive results agree to
// a tenth of the Poisson noise of the bin's expected count, sqrt(n I) / n for n samples, so that
// integration error cannot fail the test; smooth bins stop at once, narrow lobes such as GGX at
// alpha = 0.01 refine a few bins.
double integrateBin(const std::function<float(const Vec3&)>& pdf, double c0, double c1, double p0,
                    double p1, double n) {
    constexpr int kMaxPanels = 128;
    int panels = 2;
    double coarse = gaussLegendre2D(pdf, c0, c1, p0, p1, panels);
    while (true) {
        panels *= 2;
        const double fine = gaussLegendre2D(pdf, c0, c1, p0, p1, panels);
        const double tolerance = 0.1 * std::sqrt(std::max(n * std::abs(fine), 1.0)) / n;
        if (std::abs(fine - coarse) <= tolerance || panels >= kMaxPanels)
            return fine;
        coarse = fine;
    }
}

std::string formatTable(const char* title, const std::vector<double>& cells, int rows, int cols) {
    std::string out = std::string(title) + " (rows: cos theta from -1 to 1, columns: phi)\n";
    char buffer[32];
    for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < cols; ++c) {
            std::snprintf(buffer, sizeof(buffer), "%9.1f", cells[r * cols + c]);
            out += buffer;
        }
        out += '\n';
    }
    return out;
}

}  // namespace

// Numerical Recipes, 3rd edition (Press et al. 2007), section 6.2: the series of Eq. 6.2.5 for
// x < a + 1, where it converges fast, and the continued fraction of Eq. 6.2.7, evaluated by the
// modified Lentz method (section 5.2), otherwise.
double regularizedGammaQ(double a, double x) {
    if (x <= 0.0)
        return 1.0;
    const double logPrefactor = a * std::log(x) - x - std::lgamma(a);
    constexpr int kMaxIterations = 10000;
    constexpr double kEpsilon = 1e-15;
    if (x < a + 1.0) {
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < kMaxIterations && std::abs(term) > std::abs(sum) * kEpsilon; ++n) {
            term *= x / (a + n);
            sum += term;
        }
        return std::max(0.0, 1.0 - sum * std::exp(logPrefactor));
    }
    constexpr double kTiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
    for (int i = 1; i < kMaxIterations; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < kTiny)
            d = kTiny;
        c = b + an / c;
        if (std::abs(c) < kTiny)
            c = kTiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < kEpsilon)
            break;
    }
    return std::exp(logPrefactor) * h;
}

Chi2Result chi2Test(const std::function<std::optional<Vec3>(const Vec3& u)>& sample,
                    const std::function<float(const Vec3& w)>& pdf, const Chi2Options& options) {
    const int rows = options.thetaBins, cols = options.phiBins;
    const int binCount = rows * cols;
    const double n = options.sampleCount;

    // Observed counts; the last cell holds the samples that produced no direction.
    std::vector<double> observed(binCount + 1, 0.0);
    std::mt19937 rng(options.seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < options.sampleCount; ++i) {
        const Vec3 u(uniform(rng), uniform(rng), uniform(rng));
        const std::optional<Vec3> w = sample(u);
        if (!w) {
            observed[binCount] += 1.0;
            continue;
        }
        const double cosTheta = std::clamp(double(w->z), -1.0, 1.0);
        double phi = std::atan2(double(w->y), double(w->x));
        if (phi < 0.0)
            phi += 2.0 * kPiD;
        const int r = std::min(int((cosTheta + 1.0) * 0.5 * rows), rows - 1);
        const int c = std::min(int(phi / (2.0 * kPiD) * cols), cols - 1);
        observed[r * cols + c] += 1.0;
    }

    // Expected counts by integrating pdf() over each bin.
    std::vector<double> expected(binCount + 1, 0.0);
    for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < cols; ++c) {
            const double c0 = -1.0 + 2.0 * r / rows, c1 = -1.0 + 2.0 * (r + 1) / rows;
            const double p0 = 2.0 * kPiD * c / cols, p1 = 2.0 * kPiD * (c + 1) / cols;
            expected[r * cols + c] = n * integrateBin(pdf, c0, c1, p0, p1, n);
        }
    }
    const double total = std::accumulate(expected.begin(), expected.end() - 1, 0.0);
    expected[binCount] = std::max(0.0, n - total);

    Chi2Result result;
    const std::string tables = formatTable("observed", observed, rows, cols) +
                               formatTable("expected", expected, rows, cols) +
                               "rejected or delta samples: observed " +
                               std::to_string(observed[binCount]) + ", expected " +
                               std::to_string(expected[binCount]) + "\n";

    // Pool the cells expecting few samples, smallest first, into cells of at least minExpected
    // (pbrt-v4's Chi2Test). Samples where the integrated density is zero fail the test outright.
    std::vector<int> order(binCount + 1);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
    double pooledObserved = 0.0, pooledExpected = 0.0;
    for (int index : order) {
        const double e = expected[index], o = observed[index];
        if (e == 0.0) {
            if (o > n * 1e-5) {
                result.report = "samples in a region of zero density (cell " +
                                std::to_string(index) + ")\n" + tables;
                return result;
            }
            pooledObserved += o;
        } else if (e < options.minExpected ||
                   (pooledExpected > 0.0 && pooledExpected < options.minExpected)) {
            pooledObserved += o;
            pooledExpected += e;
        } else {
            result.statistic += (o - e) * (o - e) / e;
            ++result.dof;
        }
    }
    if (pooledExpected > 0.0) {
        result.statistic +=
            (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
        ++result.dof;
    }
    // The counts sum to the sample count, which removes one degree of freedom.
    result.dof -= 1;
    if (result.dof < 1) {
        result.passed = true;
        result.pValue = 1.0;
        return result;
    }
    result.pValue = regularizedGammaQ(0.5 * result.dof, 0.5 * result.statistic);
    result.level = 1.0 - std::pow(1.0 - options.significance, 1.0 / options.testCount);
    result.passed = result.pValue >= result.level;
    if (!result.passed) {
        char buffer[160];
        std::snprintf(buffer, sizeof(buffer),
                      "chi-square %.2f with %d degrees of freedom: p = %.3g < %.3g\n",
                      result.statistic, result.dof, result.pValue, result.level);
        result.report = buffer + tables;
    }
    return result;
}

}  // namespace penumbra
