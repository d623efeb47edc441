// The participating medium's parts (core/medium.h, core/phase_function.h) against closed forms:
// the Henyey-Greenstein phase function is normalised and has mean cosine g, and its sampling
// follows it (chi-square); a box's span along a ray is where the ray is inside it; the
// transmittance is Beer-Lambert's exp(-sigma_t L); and the free flight's weights have the
// expectations the radiative transfer equation gives them: T(d) for the light that passes, and
// the integral of T(s) sigma_s h(s) over the span for what scatters at distance s (Pharr, Jakob
// and Humphreys, "Physically Based Rendering", 4th ed., Eq. 14.3), in every channel of a
// chromatic medium, one of them clear; equiangular sampling's density is one, and its samples
// invert it.
#include "core/medium.h"
#include "core/phase_function.h"
#include "core/sampling.h"
#include "tests/support/chi2.h"
#include "tests/support/sample_estimate.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>

namespace penumbra::test {
namespace {

constexpr float kAsymmetries[] = {-0.5f, 0.0f, 0.3f, 0.85f};

// The integral over the sphere of p times 1 and times cos theta, by Simpson's rule in cos theta
// (the function depends on the angle alone): 1 and g.
TEST(HenyeyGreenstein, IsNormalisedWithMeanCosineG) {
    for (const float g : kAsymmetries) {
        const HenyeyGreenstein phase(g);
        constexpr int kIntervals = 20000;
        double integral = 0.0, meanCosine = 0.0;
        for (int i = 0; i <= kIntervals; ++i) {
            const double mu = -1.0 + 2.0 * i / kIntervals;
            const double weight = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 ? 4.0 : 2.0);
            const double value = 2.0 * kPi * phase.p(float(mu));
            integral += weight * value;
            meanCosine += weight * value * mu;
        }
        const double h = 2.0 / kIntervals / 3.0;
        EXPECT_NEAR(integral * h, 1.0, 1e-4) << "g = " << g;
        EXPECT_NEAR(meanCosine * h, g, 1e-4) << "g = " << g;
    }
}

TEST(HenyeyGreenstein, ForwardScatteringKeepsTheLightsDirection) {
    const HenyeyGreenstein haze(0.8f);
    const Vec3 wo(0.0f, 0.0f, 1.0f);
    // Light arriving from behind (wi = -wo) goes straight on: the largest value.
    EXPECT_GT(haze.p(wo, -wo), 10.0f * haze.p(wo, wo));
    EXPECT_FLOAT_EQ(haze.p(wo, -wo), haze.p(1.0f));
}

TEST(HenyeyGreenstein, SamplesFollowThePhaseFunction) {
    const Vec3 wo = glm::normalize(Vec3(0.3f, -0.5f, 0.8f));
    for (const float g : kAsymmetries) {
        const HenyeyGreenstein phase(g);
        Chi2Options options;
        options.testCount = int(std::size(kAsymmetries));
        const Chi2Result result = chi2Test(
            [&](const Vec3& u) -> std::optional<Vec3> { return phase.sample(wo, Vec2(u.x, u.y)); },
            [&](const Vec3& wi) { return phase.p(wo, wi); }, options);
        EXPECT_TRUE(result.passed) << "g = " << g << "\n" << result.report;
    }
}

// Equiangular sampling of a span towards a point 0.3 m off the ray's line (core/sampling.h): its
// density integrates to 1 over the span (Simpson's rule), and a sample at u has the fraction u
// of it below it (the sample inverts the distribution).
TEST(Equiangular, IsADensityOverTheSpanThatItsSamplesFollow) {
    const Vec3 o(0.0f), d(1.0f, 0.0f, 0.0f), lamp(2.0f, 0.3f, 0.0f);
    const std::optional<Equiangular> e = equiangularTowards(o, d, 0.5f, 6.0f, lamp);
    ASSERT_TRUE(e.has_value());
    const auto below = [&](double t) {
        constexpr int kIntervals = 20000;
        const double h = (t - 0.5) / kIntervals;
        double sum = 0.0;
        for (int i = 0; i <= kIntervals; ++i) {
            const double weight = (i == 0 || i == kIntervals) ? 1.0 : (i % 2 ? 4.0 : 2.0);
            sum += weight * e->pdf(float(0.5 + i * h));
        }
        return sum * h / 3.0;
    };
    EXPECT_NEAR(below(6.0), 1.0, 1e-4);
    for (const float u : {0.1f, 0.5f, 0.9f}) {
        const float t = e->sample(u);
        EXPECT_GT(t, 0.5f);
        EXPECT_LT(t, 6.0f);
        EXPECT_NEAR(below(t), u, 1e-4) << "u = " << u;
    }
    // Its peak is at the foot of the perpendicular from the lamp.
    EXPECT_GT(e->pdf(2.0f), 10.0f * e->pdf(5.0f));
    // No density towards a point on the ray's line.
    EXPECT_FALSE(equiangularTowards(o, d, 0.5f, 6.0f, Vec3(3.0f, 0.0f, 0.0f)).has_value());
}

const MediumDesc kChromatic{.name = "test",
                            .sigmaA = Color(0.2f, 0.0f, 0.0f),
                            .sigmaS = Color(0.3f, 1.0f, 0.0f),
                            .g = 0.0f,
                            .box = std::nullopt};
const Bounds3 kBox{Vec3(-1.0f), Vec3(1.0f)};

TEST(Medium, SpanIsWhereTheRayIsInTheBox) {
    const Medium medium(kChromatic, kBox);
    // From outside, through the box along x: in it from t = 2 to t = 4.
    auto s = medium.span(Ray{Vec3(-3.0f, 0.0f, 0.0f), Vec3(1.0f, 0.0f, 0.0f)}, INFINITY);
    ASSERT_TRUE(s.has_value());
    EXPECT_FLOAT_EQ(s->t0, 2.0f);
    EXPECT_FLOAT_EQ(s->t1, 4.0f);
    // Cut short by a surface at t = 3.
    s = medium.span(Ray{Vec3(-3.0f, 0.0f, 0.0f), Vec3(1.0f, 0.0f, 0.0f)}, 3.0f);
    ASSERT_TRUE(s.has_value());
    EXPECT_FLOAT_EQ(s->t1, 3.0f);
    // From inside: from its origin to the wall.
    s = medium.span(Ray{Vec3(0.5f, 0.0f, 0.0f), Vec3(-1.0f, 0.0f, 0.0f)}, INFINITY);
    ASSERT_TRUE(s.has_value());
    EXPECT_FLOAT_EQ(s->t0, 0.0f);
    EXPECT_FLOAT_EQ(s->t1, 1.5f);
    // Missing it, parallel to a slab outside it, stopped before it, and pointing away.
    EXPECT_FALSE(medium.span(Ray{Vec3(-3.0f, 2.0f, 0.0f), Vec3(1.0f, 0.0f, 0.0f)}, INFINITY));
    EXPECT_FALSE(medium.span(Ray{Vec3(-3.0f, 0.0f, 0.0f), Vec3(1.0f, 0.0f, 0.0f)}, 1.5f));
    EXPECT_FALSE(medium.span(Ray{Vec3(-3.0f, 0.0f, 0.0f), Vec3(-1.0f, 0.0f, 0.0f)}, INFINITY));
    EXPECT_FALSE(medium.span(Ray{Vec3(-3.0f, 0.0f, 0.0f), glm::normalize(Vec3(1.0f, 1.0f, 0.0f))},
                             INFINITY));
}

TEST(Medium, TransmittanceIsBeerLambert) {
    const Medium medium(kChromatic, kBox);
    // A diagonal through the box, from outside: inside for 2 sqrt(3) m.
    const Vec3 d = glm::normalize(Vec3(1.0f));
    const Color T = medium.transmittance(Ray{Vec3(-2.0f), d}, INFINITY);
    const float length = 2.0f * std::sqrt(3.0f);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(T[c], std::exp(-medium.sigmaT()[c] * length), 1e-5f) << "channel " << c;
}

// A glowing medium's emission along a span of length L, per channel: the integral of
// exp(-sigma_t s) sigma_a Le over [0, L], Le sigma_a / sigma_t (1 - exp(-sigma_t L)); nothing
// in the clear channel, whose sigma_a is zero.
TEST(Medium, EmissionAlongASpanIsTheTransferEquationsIntegral) {
    MediumDesc glowing = kChromatic;
    glowing.emission = Color(2.0f, 3.0f, 0.0f);
    const Medium medium(glowing, kBox);
    EXPECT_TRUE(medium.emits());
    EXPECT_FALSE(Medium(kChromatic, kBox).emits());
    const Ray ray{Vec3(-1.0f, 0.2f, 0.3f), Vec3(1.0f, 0.0f, 0.0f)};
    const Color L = medium.emitted(ray, Medium::Span{0.5f, 2.0f});
    const Color sigmaA = kChromatic.sigmaA;
    for (int c = 0; c < 2; ++c) {
        const double sigmaT = medium.sigmaT()[c];
        EXPECT_NEAR(
            L[c], glowing.emission[c] * sigmaA[c] / sigmaT * (1.0 - std::exp(-sigmaT * 1.5)), 1e-6)
            << "channel " << c;
    }
    EXPECT_EQ(L[2], 0.0f);
}

// The free flight's estimates over a span of d = 2 m, in a medium whose channels have sigma_t
// 0.5, 1 and 0 (clear): the light that passes has expectation T(d), the scattered light weighed
// by h(s) = 1 and h(s) = s the closed-form integrals of T(s) sigma_s h(s) over [0, d].
TEST(Medium, FreeFlightWeightsHaveTheTransferEquationsExpectations) {
    const Medium medium(kChromatic, kBox);
    const Ray ray{Vec3(-1.0f, 0.2f, 0.3f), Vec3(1.0f, 0.0f, 0.0f)};
    constexpr double kD = 2.0;
    constexpr int kSamples = 400000;
    std::mt19937_64 random(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::array<Estimate, 3> passed, scattered, scatteredAtS;
    for (int i = 0; i < kSamples; ++i) {
        const Medium::Flight flight =
            medium.sampleFlight(ray, *medium.span(ray, INFINITY), uniform(random), uniform(random));
        for (int c = 0; c < 3; ++c) {
            passed[c].add(flight.scattered ? 0.0 : flight.weight[c]);
            scattered[c].add(flight.scattered ? flight.weight[c] : 0.0);
            scatteredAtS[c].add(flight.scattered ? flight.weight[c] * flight.t : 0.0);
        }
    }
    for (int c = 0; c < 3; ++c) {
        SCOPED_TRACE("channel " + std::to_string(c));
        const double sigmaT = medium.sigmaT()[c], sigmaS = medium.sigmaS()[c];
        const double T = std::exp(-sigmaT * kD);
        const double once = sigmaT > 0.0 ? sigmaS / sigmaT * (1.0 - T) : 0.0;
        const double atS =
            sigmaT > 0.0 ? sigmaS / (sigmaT * sigmaT) * (1.0 - T * (1.0 + sigmaT * kD)) : 0.0;
        EXPECT_NEAR(passed[c].mean(), T, 4.5 * passed[c].standardError() + 1e-6);
        EXPECT_NEAR(scattered[c].mean(), once, 4.5 * scattered[c].standardError() + 1e-6);
        EXPECT_NEAR(scatteredAtS[c].mean(), atS, 4.5 * scatteredAtS[c].standardError() + 1e-6);
        // Tight enough to mean something: each within 1 % of its value (or exactly zero).
        EXPECT_LT(scattered[c].standardError(), 0.002 + 0.01 * once);
    }
    // A medium that only absorbs draws no event: the weight is the transmittance itself.
    MediumDesc absorbing = kChromatic;
    absorbing.sigmaS = Color(0.0f);
    const Medium absorber(absorbing, kBox);
    const Medium::Flight flight =
        absorber.sampleFlight(ray, *absorber.span(ray, INFINITY), 0.5f, 0.5f);
    EXPECT_FALSE(flight.scattered);
    EXPECT_NEAR(flight.weight[0], std::exp(-0.2 * kD), 1e-6);
    EXPECT_EQ(flight.weight[1], 1.0f);
}

}  // namespace
}  // namespace penumbra::test
