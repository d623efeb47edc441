// WindowedDistribution2D against the exact integral of a piecewise-constant function over a box
// (the sum of each cell's value times its overlap with the box), and its samples against the
// cells' probabilities by a chi-square test.
#include "core/windowed_distribution.h"
#include "tests/support/chi2.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace penumbra::test {
namespace {

constexpr int kWidth = 7, kHeight = 5;

// Cell values from 0 to 9, some cells empty.
std::vector<float> someValues() {
    std::vector<float> values(kWidth * kHeight);
    for (int i = 0; i < kWidth * kHeight; ++i)
        values[size_t(i)] = float((i * 7) % 10);
    return values;
}

// The length of [a0, a1] within [b0, b1].
double overlap(double a0, double a1, double b0, double b1) {
    return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}

// The exact integral over `w`, and each cell's share of it.
std::vector<double> cellIntegrals(const std::vector<float>& values, const Window& w) {
    std::vector<double> cells(values.size());
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            cells[size_t(y * kWidth + x)] =
                double(values[size_t(y * kWidth + x)]) *
                overlap(double(x) / kWidth, double(x + 1) / kWidth, w.lower.x, w.upper.x) *
                overlap(double(y) / kHeight, double(y + 1) / kHeight, w.lower.y, w.upper.y);
    return cells;
}

double sum(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v)
        s += x;
    return s;
}

Window randomWindow(std::mt19937& rng) {
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const float x0 = uniform(rng), x1 = uniform(rng), y0 = uniform(rng), y1 = uniform(rng);
    return Window{Vec2(std::min(x0, x1), std::min(y0, y1)),
                  Vec2(std::max(x0, x1), std::max(y0, y1))};
}

TEST(WindowedDistribution2D, TheIntegralOverAnyBoxIsExact) {
    const std::vector<float> values = someValues();
    const WindowedDistribution2D distribution(values, kWidth, kHeight);
    std::mt19937 rng(1);
    double worst = 0.0;
    for (int i = 0; i < 1000; ++i) {
        const Window w = randomWindow(rng);
        const double exact = sum(cellIntegrals(values, w));
        worst = std::max(worst, std::abs(distribution.integral(w) - exact));
    }
    std::printf("[ measured ] worst absolute error of the integral %.3g (the whole: %.3f)\n", worst,
                distribution.integral(Window{}));
    // Float box corners, double sums: rounding only.
    EXPECT_LT(worst, 1e-6);
    EXPECT_NEAR(distribution.integral(Window{}), sum(cellIntegrals(values, Window{})), 1e-12);
}

TEST(WindowedDistribution2D, SamplesFollowTheFunctionWithinTheWindow) {
    const std::vector<float> values = someValues();
    const WindowedDistribution2D distribution(values, kWidth, kHeight);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    constexpr int kWindows = 5, kSamples = 2000000;
    for (int trial = 0; trial < kWindows; ++trial) {
        const Window w = randomWindow(rng);
        const std::vector<double> cells = cellIntegrals(values, w);
        const double total = sum(cells);
        if (!(total > 0.0))
            continue;
        // Observed counts per cell against N times the cells' shares.
        std::vector<double> observed(cells.size(), 0.0);
        int mismatches = 0;
        for (int i = 0; i < kSamples; ++i) {
            const auto s = distribution.sample(Vec2(uniform(rng), uniform(rng)), w);
            ASSERT_TRUE(s);
            ASSERT_GE(s->point.x, w.lower.x);
            ASSERT_LE(s->point.x, w.upper.x);
            ASSERT_GE(s->point.y, w.lower.y);
            ASSERT_LE(s->point.y, w.upper.y);
            // The density is the value of the sample's cell, unless float rounding put the point
            // on the next cell's edge.
            mismatches += std::abs(s->pdf - distribution.value(s->point) / total) > 1e-4 * s->pdf;
            const int x = std::min(int(s->point.x * kWidth), kWidth - 1);
            const int y = std::min(int(s->point.y * kHeight), kHeight - 1);
            observed[size_t(y * kWidth + x)] += 1.0;
        }
        // Cells expecting fewer than 5 samples (those the window barely touches, or empty) are
        // pooled into one (Cochran's rule).
        double statistic = 0.0, pooledObserved = 0.0, pooledExpected = 0.0;
        int dof = -1;
        const auto add = [&](double o, double e) {
            statistic += (o - e) * (o - e) / e;
            ++dof;
        };
        for (size_t c = 0; c < cells.size(); ++c) {
            const double expected = kSamples * cells[c] / total;
            if (expected < 5.0) {
                pooledObserved += observed[c];
                pooledExpected += expected;
            } else {
                add(observed[c], expected);
            }
        }
        if (pooledExpected >= 5.0)
            add(pooledObserved, pooledExpected);
        else
            EXPECT_LT(pooledObserved, 20.0);  // a Poisson count of mean < 5 exceeds 20 at 1e-7
        const double p = regularizedGammaQ(0.5 * dof, 0.5 * statistic);
        std::printf("[ measured ] window %d: chi-square %.1f, %d dof, p = %.3f\n", trial, statistic,
                    dof, p);
        EXPECT_LE(mismatches, kSamples / 10000);
        // Sidak over the windows at 1 %.
        EXPECT_GT(p, 1.0 - std::pow(0.99, 1.0 / kWindows));
    }
}

TEST(WindowedDistribution2D, AWindowWithoutTheFunctionDrawsNothing) {
    std::vector<float> values(16, 0.0f);
    values[15] = 1.0f;  // only the top-right cell
    const WindowedDistribution2D distribution(values, 4, 4);
    const Window empty{Vec2(0.0f), Vec2(0.7f)};
    EXPECT_EQ(distribution.integral(empty), 0.0);
    EXPECT_FALSE(distribution.sample(Vec2(0.5f), empty));
    const auto s = distribution.sample(Vec2(0.5f), Window{});
    ASSERT_TRUE(s);
    EXPECT_GE(s->point.x, 0.75f);
    EXPECT_GE(s->point.y, 0.75f);
    EXPECT_NEAR(s->pdf, 16.0f, 1e-4f);
    EXPECT_THROW(WindowedDistribution2D(values, 3, 4), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::test
