// A heterogeneous medium's density grid (core/density_grid.h) and the medium on it
// (core/medium.h) against oracles the grid's code does not share: trilinear functions, which the
// lattice reproduces exactly, integrated along rays by Simpson's rule (exact for the cubics they
// become) for the optical depth and its inverse; and, in a procedural smoke, the textbook
// stochastic estimators the exact tracking replaces, written here from their papers: ratio
// tracking's transmittance (Novák, Selle and Jarosz 2014) and delta tracking's collision
// estimate of the in-scattered light (Woodcock et al. 1965; Novák et al. 2018).
#include "core/density_grid.h"
#include "core/medium.h"
#include "tests/support/sample_estimate.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <random>

namespace penumbra::test {
namespace {

// A trilinear function (degree one in each coordinate), positive on the grid's box below.
double trilinear(const Vec3& p) {
    const double x = p.x, y = p.y, z = p.z;
    return 1.0 + 0.3 * x - 0.2 * y + 0.25 * z + 0.15 * x * y - 0.05 * y * z + 0.1 * x * y * z;
}

const Bounds3 kBox{Vec3(0.5f, 0.25f, 1.0f), Vec3(2.5f, 1.75f, 2.2f)};

// Node values of f on a lattice of `nodes` over `box`, x fastest.
template <typename F>
std::shared_ptr<DensityGrid> sampledGrid(const Bounds3& box, const glm::ivec3& nodes, F f) {
    std::vector<float> values;
    for (int z = 0; z < nodes.z; ++z)
        for (int y = 0; y < nodes.y; ++y)
            for (int x = 0; x < nodes.x; ++x) {
                const Vec3 s = Vec3(x, y, z) / Vec3(nodes - 1);
                values.push_back(float(f(box.lo + s * box.diagonal())));
            }
    return std::make_shared<DensityGrid>(box, nodes, std::move(values));
}

// The integral of f along the ray from t0 to t1 by Simpson's rule over `intervals` (even).
template <typename F>
double simpson(F f, const Ray& ray, double t0, double t1, int intervals) {
    const double h = (t1 - t0) / intervals;
    double sum = 0.0;
    for (int i = 0; i <= intervals; ++i) {
        const double weight = (i == 0 || i == intervals) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += weight * f(ray.o + float(t0 + i * h) * ray.d);
    }
    return sum * h / 3.0;
}

// Rays from random points in a larger box towards random points in the grid's box, with the
// parameters at which they enter and leave it.
struct Chord {
    Ray ray;
    float t0, t1;
};
std::vector<Chord> chords(int count, uint64_t seed) {
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    const Medium box(MediumDesc{}, kBox);
    std::vector<Chord> result;
    while (int(result.size()) < count) {
        const Vec3 from =
            kBox.lo - 1.0f +
            Vec3(uniform(random), uniform(random), uniform(random)) * (kBox.diagonal() + 2.0f);
        const Vec3 to =
            kBox.lo + Vec3(uniform(random), uniform(random), uniform(random)) * kBox.diagonal();
        const Ray ray{from, glm::normalize(to - from)};
        if (const auto span = box.span(ray, INFINITY))
            result.push_back({ray, span->t0, span->t1});
    }
    return result;
}

TEST(DensityGrid, ReproducesTrilinearFunctionsAndIsZeroOutside) {
    const auto grid = sampledGrid(kBox, {5, 7, 4}, trilinear);
    std::mt19937_64 random(3);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 p =
            kBox.lo + Vec3(uniform(random), uniform(random), uniform(random)) * kBox.diagonal();
        EXPECT_NEAR(grid->at(p), trilinear(p), 2e-6 * trilinear(p));
    }
    EXPECT_NEAR(grid->at(kBox.hi), trilinear(kBox.hi), 2e-6 * trilinear(kBox.hi));
    EXPECT_EQ(grid->at(kBox.lo - Vec3(0.01f, 0.0f, 0.0f)), 0.0f);
    EXPECT_EQ(grid->at(kBox.hi + Vec3(0.0f, 0.0f, 0.01f)), 0.0f);
    EXPECT_FLOAT_EQ(grid->maxValue(), float(trilinear(kBox.hi)));
}

// Along a ray a trilinear function is a cubic, which Simpson's rule integrates exactly.
TEST(DensityGrid, IntegralAlongARayIsExact) {
    const auto grid = sampledGrid(kBox, {5, 7, 4}, trilinear);
    for (const Chord& c : chords(500, 11)) {
        const double exact = simpson(trilinear, c.ray, c.t0, c.t1, 2);
        EXPECT_NEAR(grid->integral(c.ray, c.t0, c.t1), exact, 2e-5 * exact + 1e-6);
        // A piece from inside the box to inside it.
        const float tm = 0.5f * (c.t0 + c.t1);
        const double part = simpson(trilinear, c.ray, c.t0, tm, 2);
        EXPECT_NEAR(grid->integral(c.ray, c.t0, tm), part, 2e-5 * part + 1e-6);
    }
    // Along an axis (the DDA's parallel planes) and along a lattice line.
    for (const Vec3 d : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, 1)}) {
        const Vec3 o = kBox.center() - 3.0f * d;
        const Ray ray{o, d};
        const auto span = Medium(MediumDesc{}, kBox).span(ray, INFINITY);
        ASSERT_TRUE(span);
        const double exact = simpson(trilinear, ray, span->t0, span->t1, 2);
        EXPECT_NEAR(grid->integral(ray, span->t0, span->t1), exact, 2e-5 * exact);
    }
}

// Along each chord, the grid's integral and, for a random share of it, its inverse match
// Simpson's rule over `intervals` on the grid's own interpolated density, within 1e-4 (and 1e-6
// absolute: a chord grazing the density, whose integral was 4e-7, missed 1e-4 of it by 5e-11
// once the DDA's pieces began where the crossing formula put them; the integral is held to the
// same floor). Returns the chords that met some density.
int expectSimpsonsAlong(const DensityGrid& grid, const std::vector<Chord>& chords, int intervals) {
    const auto interpolated = [&](const Vec3& p) { return double(grid.at(p)); };
    std::mt19937_64 random(37);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    int crossing = 0;
    for (const Chord& c : chords) {
        const double exact = simpson(interpolated, c.ray, c.t0, c.t1, intervals);
        EXPECT_NEAR(grid.integral(c.ray, c.t0, c.t1), exact, 1e-4 * exact + 1e-6);
        if (exact <= 0.0)
            continue;
        ++crossing;
        const float target = float(exact) * uniform(random);
        const std::optional<float> t = grid.invertIntegral(c.ray, c.t0, c.t1, target);
        EXPECT_TRUE(t);
        if (t) {
            EXPECT_NEAR(simpson(interpolated, c.ray, c.t0, *t, intervals), target,
                        1e-4 * exact + 1e-6);
        }
    }
    return crossing;
}

// A sparse grid (nonzero nodes only in a 3 x 3 x 3 block of a 12^3 lattice, as a VDB's active
// voxels in their bounding box): the cells whose nodes are all zero are stepped over, and the
// integral and its inverse still match Simpson's rule on the interpolated density.
TEST(DensityGrid, EmptyCellsAreSteppedOver) {
    const glm::ivec3 nodes(12);
    std::vector<float> values;
    for (int z = 0; z < nodes.z; ++z)
        for (int y = 0; y < nodes.y; ++y)
            for (int x = 0; x < nodes.x; ++x) {
                const bool inBlock = x >= 5 && x <= 7 && y >= 4 && y <= 6 && z >= 5 && z <= 7;
                values.push_back(inBlock ? float(1 + x + 2 * y + 3 * z) : 0.0f);
            }
    const DensityGrid grid(kBox, nodes, values);
    // Enough chords meet the block to mean something.
    EXPECT_GT(expectSimpsonsAlong(grid, chords(300, 41), 20000), 30);
}

// A large sparse grid (two puffs in a 48^3 lattice, most of its blocks of 8^3 cells empty), which
// the DDA crosses a block at a time: the integral and its inverse still match Simpson's rule on
// the interpolated density, along random chords, along the axes and along diagonals through the
// lattice's corners, where a jump out of a block lands on a corner of several (rounding must
// neither send it back nor lose a cell).
TEST(DensityGrid, EmptyBlocksAreCrossedWhole) {
    const glm::ivec3 nodes(49);
    const auto puff = [](const Vec3& g, const Vec3& centre, float radius) {
        return std::max(0.0f, 1.0f - glm::length(g - centre) / radius);
    };
    std::vector<float> values;
    for (int z = 0; z < nodes.z; ++z)
        for (int y = 0; y < nodes.y; ++y)
            for (int x = 0; x < nodes.x; ++x) {
                const Vec3 g(x, y, z);
                values.push_back(2.0f * puff(g, Vec3(10.0f, 12.0f, 9.0f), 3.5f) +
                                 puff(g, Vec3(36.0f, 30.0f, 35.0f), 5.0f));
            }
    const DensityGrid grid(kBox, nodes, values);
    const Medium box(MediumDesc{}, kBox);
    std::vector<Chord> all = chords(300, 43);
    const Vec3 cell = kBox.diagonal() / 48.0f;
    for (const Vec3 d : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0, 0, 1), Vec3(1, 1, 1),
                         Vec3(-1, 1, -1), Vec3(1, -1, 1)}) {
        // Through the first puff's centre, and through a lattice corner shared by eight blocks.
        for (const Vec3 through : {kBox.lo + Vec3(10.0f, 12.0f, 9.0f) * cell,
                                   kBox.lo + Vec3(16.0f, 16.0f, 16.0f) * cell}) {
            const Vec3 dir = glm::normalize(d * cell);
            const Ray ray{through - 5.0f * dir, dir};
            if (const auto span = box.span(ray, INFINITY))
                all.push_back({ray, span->t0, span->t1});
        }
    }
    EXPECT_GT(expectSimpsonsAlong(grid, all, 40000), 20);
}

TEST(DensityGrid, InverseFindsWhereTheIntegralReachesTheTarget) {
    const auto grid = sampledGrid(kBox, {5, 7, 4}, trilinear);
    std::mt19937_64 random(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (const Chord& c : chords(500, 13)) {
        const double total = simpson(trilinear, c.ray, c.t0, c.t1, 2);
        const float target = float(total) * uniform(random);
        const std::optional<float> t = grid->invertIntegral(c.ray, c.t0, c.t1, target);
        ASSERT_TRUE(t);
        EXPECT_GE(*t, c.t0);
        EXPECT_LE(*t, c.t1);
        EXPECT_NEAR(simpson(trilinear, c.ray, c.t0, *t, 2), target, 1e-4 * total);
        EXPECT_FALSE(grid->invertIntegral(c.ray, c.t0, c.t1, float(total) * 1.001f + 1e-4f));
    }
}

// A procedural smoke: three Gaussian puffs on a thin background, sampled on a 24^3 lattice.
double smoke(const Vec3& p) {
    const auto puff = [&](const Vec3& centre, double radius, double peak) {
        const double r2 = glm::dot(p - centre, p - centre);
        return peak * std::exp(-r2 / (radius * radius));
    };
    return 0.05 + puff(Vec3(1.2f, 0.8f, 1.5f), 0.3, 3.0) + puff(Vec3(2.0f, 1.2f, 1.8f), 0.5, 1.5) +
           puff(Vec3(0.9f, 1.5f, 1.2f), 0.2, 6.0);
}

MediumDesc smokyMedium() {
    MediumDesc desc;
    desc.sigmaA = Color(0.4f, 0.1f, 0.0f);
    desc.sigmaS = Color(0.6f, 1.4f, 0.0f);  // one channel clear
    desc.density = sampledGrid(kBox, {24, 24, 24}, smoke);
    return desc;
}

// Ratio tracking (Novák, Selle and Jarosz 2014) against the majorant sigma_t max(density): the
// mean of the products of (1 - sigma_t(x) / majorant) over the tentative collisions is T.
TEST(DensityGrid, TransmittanceAgreesWithRatioTracking) {
    const Medium medium(smokyMedium(), kBox);
    const DensityGrid& grid = *medium.density();
    std::mt19937_64 random(17);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (const Chord& c : chords(6, 19)) {
        const Color T = medium.transmittance(c.ray, INFINITY);
        for (int channel = 0; channel < 2; ++channel) {
            const double majorant = medium.sigmaT()[channel] * grid.maxValue();
            Estimate ratio;
            for (int i = 0; i < 20000; ++i) {
                double weight = 1.0, t = c.t0;
                while (true) {
                    t -= std::log(1.0 - uniform(random)) / majorant;
                    if (t >= c.t1)
                        break;
                    const double sigma =
                        medium.sigmaT()[channel] * grid.at(c.ray.o + float(t) * c.ray.d);
                    weight *= 1.0 - sigma / majorant;
                }
                ratio.add(weight);
            }
            EXPECT_NEAR(T[channel], ratio.mean(), 4.5 * ratio.standardError() + 1e-5)
                << "channel " << channel;
        }
        EXPECT_EQ(T[2], 1.0f);
    }
}

// The free flight's scattered light, sum of weight x h(t) over events, h(t) = 1 + t, against
// delta tracking's collision estimate of the same integral of T sigma_s h: at each real collision
// (probability sigma_t(x) / majorant) the albedo times h; and the light that passes against T.
// Also: the flight's density and the chance to pass sum to one.
TEST(DensityGrid, FreeFlightsAgreeWithDeltaTracking) {
    const Medium medium(smokyMedium(), kBox);
    const DensityGrid& grid = *medium.density();
    std::mt19937_64 random(23);
    std::uniform_real_distribution<float> uniformF(0.0f, 1.0f);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const auto h = [](double t) { return 1.0 + t; };
    for (const Chord& c : chords(4, 29)) {
        SCOPED_TRACE("chord from " + std::to_string(c.t0) + " to " + std::to_string(c.t1));
        const Medium::Span span{c.t0, c.t1};
        std::array<Estimate, 3> scattered, passed;
        for (int i = 0; i < 100000; ++i) {
            const Medium::Flight flight =
                medium.sampleFlight(c.ray, span, uniformF(random), uniformF(random));
            for (int channel = 0; channel < 3; ++channel) {
                scattered[channel].add(flight.scattered ? flight.weight[channel] * h(flight.t)
                                                        : 0.0);
                passed[channel].add(flight.scattered ? 0.0 : flight.weight[channel]);
            }
        }
        const Color T = medium.transmittance(c.ray, INFINITY);
        for (int channel = 0; channel < 2; ++channel) {
            const double sigmaT = medium.sigmaT()[channel];
            const double albedo = medium.sigmaS()[channel] / sigmaT;
            const double majorant = sigmaT * grid.maxValue();
            Estimate delta;
            for (int i = 0; i < 100000; ++i) {
                double t = c.t0, value = 0.0;
                while (true) {
                    t -= std::log(1.0 - uniform(random)) / majorant;
                    if (t >= c.t1)
                        break;
                    const double sigma = sigmaT * grid.at(c.ray.o + float(t) * c.ray.d);
                    if (uniform(random) < sigma / majorant) {
                        value = albedo * h(t);
                        break;
                    }
                }
                delta.add(value);
            }
            const double error =
                std::hypot(delta.standardError(), scattered[channel].standardError());
            EXPECT_NEAR(scattered[channel].mean(), delta.mean(), 4.5 * error)
                << "channel " << channel;
            EXPECT_NEAR(passed[channel].mean(), T[channel], 4.5 * passed[channel].standardError());
        }
        EXPECT_EQ(scattered[2].mean(), 0.0);
        EXPECT_NEAR(passed[2].mean(), 1.0, 4.5 * passed[2].standardError() + 1e-6);

        const double eventChance = simpson(
            [&](const Vec3& p) {
                return medium.flightPdf(c.ray, c.t0, glm::dot(p - c.ray.o, c.ray.d));
            },
            c.ray, c.t0, c.t1, 4000);
        EXPECT_NEAR(eventChance + (T[0] + T[1] + T[2]) / 3.0, 1.0, 2e-3);
    }
}

// A glowing medium on a grid: its emission along a chord is the integral of
// exp(-sigma_t D(t0, s)) sigma_a rho(s) Le over the chord, here by Simpson's rule on the
// trilinear function, D by Simpson's rule too (exact for its cubics).
TEST(DensityGrid, EmissionAlongAChordIsTheTransferEquationsIntegral) {
    MediumDesc desc;
    desc.sigmaA = Color(0.5f, 1.5f, 0.0f);
    desc.sigmaS = Color(0.5f);
    desc.emission = Color(2.0f, 1.0f, 0.0f);
    desc.density = sampledGrid(kBox, {5, 7, 4}, trilinear);
    const Medium medium(desc, kBox);
    for (const Chord& c : chords(20, 31)) {
        const Color L = medium.emitted(c.ray, Medium::Span{c.t0, c.t1});
        for (int channel = 0; channel < 2; ++channel) {
            const double sigmaT = medium.sigmaT()[channel];
            const auto integrand = [&](const Vec3& p) {
                const double s = glm::dot(p - c.ray.o, c.ray.d);
                const double D = simpson(trilinear, c.ray, c.t0, s, 2);
                return std::exp(-sigmaT * D) * desc.sigmaA[channel] * trilinear(p) *
                       desc.emission[channel];
            };
            const double expected = simpson(integrand, c.ray, c.t0, c.t1, 2000);
            EXPECT_NEAR(L[channel], expected, 1e-4 * expected + 1e-7) << "channel " << channel;
        }
        EXPECT_EQ(L[2], 0.0f);
    }
}

}  // namespace
}  // namespace penumbra::test
