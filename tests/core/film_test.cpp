// Pixel filters (sampled distribution against the filter) and the film's weighted means.
#include "core/film.h"

#include "core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <thread>
#include <vector>

namespace penumbra {
namespace {

TEST(PixelFilter, ParsesNamesAndListsThemOnError) {
    EXPECT_EQ(parseFilter("box"), FilterType::Box);
    EXPECT_EQ(parseFilter("gaussian"), FilterType::Gaussian);
    EXPECT_EQ(parseFilter("blackman-harris"), FilterType::BlackmanHarris);
    try {
        parseFilter("mitchell");
        FAIL() << "expected UsageError";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("mitchell"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("box, gaussian, blackman-harris"), std::string::npos);
    }
}

TEST(PixelFilter, RadiiAndValues) {
    EXPECT_EQ(PixelFilter(FilterType::Box).radius(), 0.5f);
    EXPECT_EQ(PixelFilter(FilterType::Gaussian).radius(), 1.5f);
    EXPECT_EQ(PixelFilter(FilterType::BlackmanHarris).radius(), 2.0f);
    const PixelFilter gaussian(FilterType::Gaussian);
    // pbrt-v4's Gaussian, shifted down by its value at the radius, decreases to exactly 0 there.
    EXPECT_GT(gaussian.evaluate({0.0f, 0.0f}), gaussian.evaluate({1.0f, 0.0f}));
    EXPECT_NEAR(gaussian.evaluate({1.5f, 0.0f}), 0.0f, 1e-7f);
    const PixelFilter bh(FilterType::BlackmanHarris);
    // The window peaks at a0 + a1 + a2 + a3 = 1 at the centre and falls to 6e-5 at the edge.
    EXPECT_NEAR(bh.evaluate({0.0f, 0.0f}), 1.0f, 1e-5f);
    EXPECT_NEAR(bh.evaluate({2.0f, 0.0f}), 0.00006f, 1e-5f);
    EXPECT_EQ(bh.evaluate({2.5f, 0.0f}), 0.0f);
}

TEST(PixelFilter, BoxOffsetIsTheUniformSampleMinusOneHalf) {
    const PixelFilter box;
    for (float u : {0.0f, 0.1f, 0.5f, 0.77f, 0.999f}) {
        const Vec2 offset = box.sampleOffset({u, 1.0f - u});
        EXPECT_NEAR(offset.x, u - 0.5f, 1e-6f);
        EXPECT_NEAR(offset.y, 0.5f - u, 1e-6f);
    }
}

// A stratified sweep of u through the inverse CDF reproduces the filter's marginal: the share of
// offsets in each of 16 bins across [-radius, radius] equals the filter's integral over the bin.
TEST(PixelFilter, OffsetsAreDistributedAsTheFilter) {
    for (FilterType type : {FilterType::Box, FilterType::Gaussian, FilterType::BlackmanHarris}) {
        const PixelFilter filter(type);
        const float r = filter.radius();
        constexpr int kBins = 16, kSweep = 200000, kQuadrature = 1000;
        std::vector<double> observed(kBins, 0.0), expected(kBins, 0.0);
        double mean = 0.0;
        for (int i = 0; i < kSweep; ++i) {
            const Vec2 offset = filter.sampleOffset({(i + 0.5f) / kSweep, 0.5f});
            ASSERT_GE(offset.x, -r);
            ASSERT_LE(offset.x, r);
            const int bin = std::min(kBins - 1, int((offset.x + r) / (2.0f * r) * kBins));
            observed[size_t(bin)] += 1.0 / kSweep;
            mean += offset.x / kSweep;
        }
        // Midpoint quadrature of the marginal f(x, 0).
        double total = 0.0;
        for (int b = 0; b < kBins; ++b) {
            for (int q = 0; q < kQuadrature; ++q) {
                const float x = -r + 2.0f * r * (b + (q + 0.5f) / kQuadrature) / kBins;
                expected[size_t(b)] += filter.evaluate({x, 0.0f});
            }
            total += expected[size_t(b)];
        }
        for (int b = 0; b < kBins; ++b) {
            EXPECT_NEAR(observed[size_t(b)], expected[size_t(b)] / total, 1e-4)
                << filterName(type) << " bin " << b;
        }
        EXPECT_NEAR(mean, 0.0, 1e-4) << filterName(type);
    }
}

TEST(PixelFilter, AxesAreSampledIndependently) {
    const PixelFilter filter(FilterType::BlackmanHarris);
    EXPECT_EQ(filter.sampleOffset({0.3f, 0.1f}).x, filter.sampleOffset({0.3f, 0.9f}).x);
    EXPECT_EQ(filter.sampleOffset({0.3f, 0.1f}).y, filter.sampleOffset({0.7f, 0.1f}).y);
}

TEST(Film, ResolveGivesWeightedMeansAndCountsSamples) {
    Film film(3, 2);
    film.addSample({1, 0}, Color(1.0f, 2.0f, 3.0f), 1.0f);
    film.addSample({1, 0}, Color(3.0f, 2.0f, 1.0f), 3.0f);
    film.addSample({2, 1}, Color(0.5f), 0.25f);
    const Image image = film.resolve();
    ASSERT_EQ(image.width(), 3);
    ASSERT_EQ(image.height(), 2);
    EXPECT_EQ(image.channelNames(), (std::vector<std::string>{"R", "G", "B"}));
    // (1*1 + 3*3) / 4, (1*2 + 3*2) / 4, (1*3 + 3*1) / 4
    EXPECT_FLOAT_EQ(image.at(1, 0, 0), 2.5f);
    EXPECT_FLOAT_EQ(image.at(1, 0, 1), 2.0f);
    EXPECT_FLOAT_EQ(image.at(1, 0, 2), 1.5f);
    EXPECT_FLOAT_EQ(image.at(2, 1, 1), 0.5f);
    EXPECT_EQ(image.at(0, 0, 0), 0.0f);  // no sample
    EXPECT_EQ(film.sampleCount({1, 0}), 2u);
    EXPECT_EQ(film.sampleCount({2, 1}), 1u);
    EXPECT_EQ(film.sampleCount({0, 1}), 0u);
}

TEST(Film, AovsAreAveragedWithTheirOwnChannelNames) {
    Film film(2, 2, {{"albedo"}, {"depth", {"Z"}}});
    film.addAov({0, 1}, 0, Vec3(0.2f, 0.4f, 0.6f));
    film.addAov({0, 1}, 0, Vec3(0.4f, 0.4f, 0.4f));
    film.addAov({1, 1}, 1, Vec3(7.0f, -1.0f, -1.0f));
    const Image albedo = film.resolveAov(0);
    const Image depth = film.resolveAov(1);
    EXPECT_EQ(albedo.channelNames(), (std::vector<std::string>{"R", "G", "B"}));
    EXPECT_EQ(depth.channelNames(), (std::vector<std::string>{"Z"}));
    EXPECT_FLOAT_EQ(albedo.at(0, 1, 0), 0.3f);
    EXPECT_FLOAT_EQ(albedo.at(0, 1, 2), 0.5f);
    EXPECT_EQ(depth.at(1, 1, 0), 7.0f);
    EXPECT_EQ(depth.at(0, 0, 0), 0.0f);
}

TEST(Film, NonFiniteSamplesAssertInDebugAndAreDroppedInRelease) {
    Film film(1, 1, {{"normal", {"X", "Y", "Z"}}});
    film.addSample({0, 0}, Color(1.0f), 1.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    EXPECT_DEBUG_DEATH(film.addSample({0, 0}, Color(nan, 0.0f, 0.0f), 1.0f), "non-finite");
    EXPECT_DEBUG_DEATH(film.addSample({0, 0}, Color(1.0f), inf), "non-finite");
    EXPECT_DEBUG_DEATH(film.addAov({0, 0}, 0, Vec3(0.0f, inf, 0.0f)), "non-finite");
#ifdef NDEBUG
    EXPECT_EQ(film.droppedSamples(), 3u);
#endif
    EXPECT_EQ(film.sampleCount({0, 0}), 1u);
    EXPECT_EQ(film.resolve().at(0, 0, 0), 1.0f);
}

TEST(Film, ResultDoesNotDependOnTheNumberOfThreads) {
    // Rows are split among threads; each pixel still receives its samples in the same order.
    constexpr int kWidth = 16, kHeight = 16, kSamples = 32;
    auto render = [&](int threads) {
        Film film(kWidth, kHeight);
        std::vector<std::thread> workers;
        for (int t = 0; t < threads; ++t) {
            workers.emplace_back([&, t] {
                for (int y = t; y < kHeight; y += threads) {
                    for (int x = 0; x < kWidth; ++x) {
                        for (int s = 0; s < kSamples; ++s) {
                            const float v = std::sin(float(x * 131 + y * 17 + s * 7));
                            film.addSample({x, y}, Color(v, v * v, 0.1f * v), 1.0f);
                        }
                    }
                }
            });
        }
        for (std::thread& worker : workers) {
            worker.join();
        }
        return film.resolve();
    };
    const Image one = render(1), four = render(4);
    ASSERT_EQ(one.pixels().size(), four.pixels().size());
    for (size_t i = 0; i < one.pixels().size(); ++i) {
        EXPECT_EQ(one.pixels()[i], four.pixels()[i]);
    }
}

}  // namespace
}  // namespace penumbra
