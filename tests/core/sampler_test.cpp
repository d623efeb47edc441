// The Owen-scrambled Sobol sampler: range, determinism, (0,k,2)-net stratification, decorrelation
// of pixels and dimensions, and the integration error of a smooth integrand.
#include "core/sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <vector>

namespace penumbra {
namespace {

std::vector<Vec2> firstSamples2D(uint32_t seed, IVec2 pixel, int dimension, int count) {
    Sampler sampler(seed);
    std::vector<Vec2> points;
    for (int i = 0; i < count; ++i) {
        sampler.startPixelSample(pixel, uint32_t(i));
        for (int d = 0; d < dimension; ++d) {
            sampler.get2D();
        }
        points.push_back(sampler.get2D());
    }
    return points;
}

TEST(Sampler, OneDimensionsSequenceIsWhatGet2DGives) {
    const IVec2 pixel(5, 9);
    for (uint32_t dimension = 1; dimension <= 4; ++dimension) {
        const SampleSequence2D sequence(7, pixel, dimension);
        const std::vector<Vec2> drawn = firstSamples2D(7, pixel, int(dimension) - 1, 64);
        for (uint32_t k = 0; k < drawn.size(); ++k) {
            ASSERT_EQ(sequence[k].x, drawn[k].x) << "dimension " << dimension << " sample " << k;
            ASSERT_EQ(sequence[k].y, drawn[k].y) << "dimension " << dimension << " sample " << k;
        }
    }
    // Dimension 0 is the camera sample's.
    Sampler sampler(7);
    sampler.startPixelSample(pixel, 3);
    const Vec2 camera = sampler.getPixel2D();
    EXPECT_EQ(SampleSequence2D(7, pixel, 0)[3].x, camera.x);
    EXPECT_EQ(SampleSequence2D(7, pixel, 0)[3].y, camera.y);
}

TEST(Sampler, ValuesLieInTheHalfOpenUnitInterval) {
    Sampler sampler(3);
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 8; ++x) {
            for (uint32_t i = 0; i < 256; ++i) {
                sampler.startPixelSample({x, y}, i);
                const Vec2 p = sampler.getPixel2D();
                const float u = sampler.get1D();
                const Vec2 v = sampler.get2D();
                for (float value : {p.x, p.y, u, v.x, v.y}) {
                    ASSERT_GE(value, 0.0f);
                    ASSERT_LT(value, 1.0f);
                }
            }
        }
    }
}

TEST(Sampler, OutputDependsOnlyOnSeedPixelIndexAndCallOrder) {
    // Two samplers visiting pixels in different orders (as two thread counts would) agree.
    Sampler a(42), b(42);
    const IVec2 pixels[] = {{0, 0}, {5, 3}, {17, 2}};
    std::vector<float> first, second;
    for (const IVec2& pixel : pixels) {
        for (uint32_t i = 0; i < 16; ++i) {
            a.startPixelSample(pixel, i);
            first.push_back(a.get1D());
            const Vec2 v = a.get2D();
            first.push_back(v.x);
            first.push_back(v.y);
        }
    }
    for (int p = 2; p >= 0; --p) {
        for (uint32_t i = 0; i < 16; ++i) {
            b.startPixelSample(pixels[p], i);
            const float u = b.get1D();
            const Vec2 v = b.get2D();
            const size_t at = (size_t(p) * 16 + i) * 3;
            EXPECT_EQ(u, first[at]);
            EXPECT_EQ(v.x, first[at + 1]);
            EXPECT_EQ(v.y, first[at + 2]);
        }
    }
}

TEST(Sampler, PixelSampleIsIndependentOfEarlierCalls) {
    Sampler a(1), b(1);
    a.startPixelSample({4, 4}, 7);
    b.startPixelSample({4, 4}, 7);
    b.get1D();
    b.get2D();
    EXPECT_EQ(a.getPixel2D(), b.getPixel2D());
}

// Every elementary interval of area 2^-k (2^a columns by 2^b rows, a + b = k) holds exactly one of
// the first 2^k points: the (0,k,2)-net property, which Owen scrambling and the index shuffle keep.
TEST(Sampler, First2ToTheKSamplesAreStratifiedInEveryElementaryInterval) {
    constexpr int kMaxLog2 = 10;
    for (const IVec2 pixel : {IVec2(0, 0), IVec2(13, 7)}) {
        for (int dimension = 0; dimension < 3; ++dimension) {
            const std::vector<Vec2> points = firstSamples2D(9, pixel, dimension, 1 << kMaxLog2);
            for (int k = 0; k <= kMaxLog2; ++k) {
                for (int a = 0; a <= k; ++a) {
                    const int b = k - a;
                    std::vector<int> cells(size_t(1) << k, 0);
                    for (int i = 0; i < (1 << k); ++i) {
                        const int cx = int(points[i].x * float(1 << a));
                        const int cy = int(points[i].y * float(1 << b));
                        cells[(size_t(cy) << a) + size_t(cx)]++;
                    }
                    for (int count : cells) {
                        ASSERT_EQ(count, 1)
                            << "pixel " << pixel.x << "," << pixel.y << " dimension " << dimension
                            << " k " << k << " shape 2^" << a << " x 2^" << b;
                    }
                }
            }
        }
    }
}

TEST(Sampler, First2ToTheKOneDimensionalSamplesAreStratified) {
    constexpr int kCount = 1024;
    Sampler sampler(5);
    std::vector<float> values;
    for (int i = 0; i < kCount; ++i) {
        sampler.startPixelSample({2, 9}, uint32_t(i));
        values.push_back(sampler.get1D());
    }
    for (int k = 0; k <= 10; ++k) {
        std::vector<int> cells(size_t(1) << k, 0);
        for (int i = 0; i < (1 << k); ++i) {
            cells[size_t(values[i] * float(1 << k))]++;
        }
        for (int count : cells) {
            ASSERT_EQ(count, 1) << "k " << k;
        }
    }
}

TEST(Sampler, PixelsAndDimensionsGetDifferentSequences) {
    const std::vector<Vec2> base = firstSamples2D(1, {3, 3}, 0, 16);
    EXPECT_NE(base, firstSamples2D(1, {4, 3}, 0, 16));
    EXPECT_NE(base, firstSamples2D(1, {3, 4}, 0, 16));
    EXPECT_NE(base, firstSamples2D(1, {3, 3}, 1, 16));
    EXPECT_NE(base, firstSamples2D(2, {3, 3}, 0, 16));
    // Consecutive 1D dimensions are uncorrelated: the sample correlation of 1024 pairs has a
    // standard deviation of 1/sqrt(1024) ~ 0.03 when they are independent.
    Sampler sampler(1);
    double sx = 0, sy = 0, sxy = 0, sxx = 0, syy = 0;
    constexpr int kCount = 1024;
    for (int i = 0; i < kCount; ++i) {
        sampler.startPixelSample({3, 3}, uint32_t(i));
        const double x = sampler.get1D(), y = sampler.get1D();
        sx += x, sy += y, sxy += x * y, sxx += x * x, syy += y * y;
    }
    const double mx = sx / kCount, my = sy / kCount;
    const double correlation =
        (sxy / kCount - mx * my) / std::sqrt((sxx / kCount - mx * mx) * (syy / kCount - my * my));
    EXPECT_LT(std::abs(correlation), 0.15);
}

// A smooth, non-separable integrand with a closed-form integral over the unit square:
// the integral of cos(3x + 2y) is (cos 3 + cos 2 - cos 5 - 1) / 6.
double smooth(Vec2 p) {
    return std::cos(3.0 * p.x + 2.0 * p.y);
}
const double kSmoothIntegral = (std::cos(3.0) + std::cos(2.0) - std::cos(5.0) - 1.0) / 6.0;

// RMS error over many pixels of the N-sample estimate of the integral.
double rmsError(int samples) {
    constexpr int kPixels = 64;
    Sampler sampler(11);
    double sumSquares = 0.0;
    for (int p = 0; p < kPixels; ++p) {
        double sum = 0.0;
        for (int i = 0; i < samples; ++i) {
            sampler.startPixelSample({p, 0}, uint32_t(i));
            sampler.get1D();
            sum += smooth(sampler.get2D());
        }
        const double error = sum / samples - kSmoothIntegral;
        sumSquares += error * error;
    }
    return std::sqrt(sumSquares / kPixels);
}

TEST(Sampler, SmoothIntegrandConvergesFasterThanIndependentSampling) {
    // Standard deviation of the integrand under uniform sampling, by a fine midpoint rule.
    constexpr int kGrid = 1000;
    double sum = 0.0, sumSquares = 0.0;
    for (int y = 0; y < kGrid; ++y) {
        for (int x = 0; x < kGrid; ++x) {
            const double f = smooth({(x + 0.5f) / kGrid, (y + 0.5f) / kGrid});
            sum += f;
            sumSquares += f * f;
        }
    }
    const double n = double(kGrid) * kGrid;
    const double sigma = std::sqrt(sumSquares / n - (sum / n) * (sum / n));
    // Independent samples have RMS error sigma / sqrt(N); scrambled (0,2)-sequences reach
    // O(N^-1.5) on smooth integrands (Owen 1997, "Scrambled Net Variance for Integrals of Smooth
    // Functions", Ann. Statist. 25(4)), here a factor ~30 lower at N = 1024.
    const double error64 = rmsError(64), error1024 = rmsError(1024);
    EXPECT_LT(error1024, 0.1 * sigma / std::sqrt(1024.0));
    // From 64 to 1024 samples independent sampling gains a factor 4; demand at least 8.
    EXPECT_LT(error1024, error64 / 8.0);
}

}  // namespace
}  // namespace penumbra
