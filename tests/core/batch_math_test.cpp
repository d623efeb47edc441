// The batched atan2 (core/batch_math.h) against the C library's, lane by lane: the quadrants, the
// axes and the magnitudes Lambert's edge terms give it (a sine of 1e-12 next to a cosine of 1).
#include "core/batch_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace penumbra {
namespace {

// SLEEF's u35 functions are within 3.5 ulp; the bound adds the C library's own half ulp.
constexpr double kUlps = 4.0;

void expectLanesMatch(const std::vector<double>& y, const std::vector<double>& x) {
    for (size_t start = 0; start < y.size(); start += kAtan2BatchSize) {
        Atan2Batch yb{}, xb{};
        for (size_t i = 0; i < kAtan2BatchSize; ++i) {
            yb[i] = y[(start + i) % y.size()];
            xb[i] = x[(start + i) % x.size()];
        }
        const Atan2Batch out = atan2Batch(yb, xb);
        for (size_t i = 0; i < kAtan2BatchSize; ++i) {
            const double expected = std::atan2(yb[i], xb[i]);
            const double ulp = std::nextafter(std::abs(expected), INFINITY) - std::abs(expected);
            EXPECT_LE(std::abs(out[i] - expected), kUlps * ulp)
                << "atan2(" << yb[i] << ", " << xb[i] << ") = " << expected << ", got " << out[i];
        }
    }
}

TEST(BatchMath, Atan2MatchesTheCLibraryOnTheAxesAndInEveryQuadrant) {
    const std::vector<double> y = {0.0,  0.0,  1.0,   -1.0,  1.0, 1.0,
                                   -1.0, -1.0, 1e-12, 1e-12, 3.0, 1e8};
    const std::vector<double> x = {1.0, -1.0, 0.0, 0.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1e-9, 2.0};
    expectLanesMatch(y, x);
}

TEST(BatchMath, Atan2MatchesTheCLibraryOnRandomArguments) {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::uniform_real_distribution<double> exponent(-20.0, 20.0);
    std::vector<double> y, x;
    for (int i = 0; i < 40000; ++i) {
        y.push_back(uniform(rng) * std::pow(10.0, exponent(rng)));
        x.push_back(uniform(rng) * std::pow(10.0, exponent(rng)));
    }
    expectLanesMatch(y, x);
}

}  // namespace
}  // namespace penumbra
