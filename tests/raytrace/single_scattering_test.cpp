// Whitted's preview of a participating medium (raytrace/single_scattering.h through the specular
// chain of raytrace/distribution_tracer.h), in-process, against oracles it does not share:
// - the light a point light scatters once into a ray (the airlight integral by Simpson's rule,
//   tests/support/medium_scenes.h), in an even haze and in one graded on a grid;
// - an emitter behind an absorbing slab, attenuated by exp(-sigma_a L), and a glowing slab;
// - in a closed room with puffs of chromatic smoke (tests/support/medium_scenes.h), the path tracer
// limited to one scattering
//   vertex (maxDepth 1: L E, L D E, L V E, the paths Whitted's pass counts there with no
//   ambient term), a different estimator (free flights and equiangular sampling against ray
//   marching).
#include "core/sampler.h"
#include "core/scene.h"
#include "raytrace/distribution_tracer.h"
#include "raytrace/path_tracer.h"
#include "tests/support/medium_scenes.h"
#include "tests/support/sample_estimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace penumbra::test {
namespace {

// 4.5 standard errors (path_tracer_furnace_test.cpp's argument).
constexpr double kDeviations = 4.5;

// The mean and standard error of channel `c` of n estimates along `ray` (file coordinates) by
// `Li`, each sample 0 of its own pixel.
template <typename Tracer>
Estimate traceMean(const Scene& scene, const Tracer& tracer, Ray ray, int n, int c = 1) {
    ray.o -= Vec3(scene.description().origin);
    Sampler sampler(11);
    PathCounters counters;
    Estimate estimate;
    for (int i = 0; i < n; ++i) {
        sampler.startPixelSample(IVec2(i % 256, i / 256), 0);
        estimate.add(tracer.Li(ray, sampler, nullptr, counters).total()[c]);
    }
    return estimate;
}

TEST(WhittedPreview, SingleScatteringIsTheAirlightIntegral) {
    constexpr float kSigmaS = 0.3f, kSigmaA = 0.1f, kG = 0.4f;
    const AffineDensity even = [](const glm::dvec3&) { return 1.0; };
    const AffineDensity graded = [](const glm::dvec3& p) { return 1.0 + 0.12 * p.x + 0.04 * p.y; };
    const DensityField field{[&](const Vec3& p) { return graded(glm::dvec3(p)); }, {11, 6, 4}};
    for (const bool onGrid : {false, true}) {
        SCOPED_TRACE(onGrid ? "graded, on a grid" : "even");
        const std::unique_ptr<Scene> scene =
            withMedium(lampAtTheOrigin(), "whitted-airlight",
                       MediumDesc{.name = "haze",
                                  .sigmaA = Color(kSigmaA),
                                  .sigmaS = Color(kSigmaS),
                                  .g = kG,
                                  .box = Bounds3{Vec3(-5.0f), Vec3(5.0f)}},
                       onGrid ? &field : nullptr);
        const DistributionTracer whitted(*scene, DistributionSettings{}, nullptr);
        const Vec3 o(-4.0f, 0.5f, 0.3f), d = glm::normalize(Vec3(1.0f, 0.1f, 0.0f));
        const double expected =
            airlight(o, d, 9.0 / d.x, kLampIntensity, kSigmaS, kSigmaA + kSigmaS,
                     HenyeyGreenstein(kG), onGrid ? graded : even);
        const Estimate L = traceMean(*scene, whitted, Ray{o, d}, 20000);
        EXPECT_NEAR(L.mean(), expected, kDeviations * L.standardError());
        EXPECT_LT(L.standardError(), 0.01 * expected);
    }
}

TEST(WhittedPreview, AnEmitterBehindAnAbsorbingSlabAndAGlowingOne) {
    const Color sigmaA(0.1f, 0.4f, 1.0f), Le(1.0f, 2.0f, 0.5f);
    for (const bool glowing : {false, true}) {
        SCOPED_TRACE(glowing ? "glowing" : "absorbing");
        const std::unique_ptr<Scene> scene = withMedium(
            panelAtFiveMetres(), "whitted-slab", slabBetween(sigmaA, glowing ? Le : Color(0.0f)));
        const DistributionTracer whitted(*scene, DistributionSettings{}, nullptr);
        const Vec3 d = glm::normalize(Vec3(0.3f, 0.2f, -5.0f));
        const float length = 1.5f / -d.z;
        for (int c = 0; c < 3; ++c) {
            const double T = std::exp(-sigmaA[c] * length);
            const Estimate L = traceMean(*scene, whitted, Ray{Vec3(0.0f), d}, 4, c);
            EXPECT_NEAR(L.mean(), kPanelRadiance * T + (glowing ? Le[c] * (1.0 - T) : 0.0), 1e-5)
                << "channel " << c;
        }
    }
}

TEST(WhittedPreview, AgreesWithThePathTracerAtOneScatteringVertex) {
    const std::unique_ptr<Scene> scene =
        withMedium(smokyRoom(), "whitted-room", kLowSmoke, &kPuffs);
    const DistributionTracer whitted(*scene, DistributionSettings{}, nullptr);
    PathTracerSettings oneVertex;
    oneVertex.maxDepth = 1;
    const PathTracer pathTracer(*scene, oneVertex);
    const Estimate preview = traceMean(*scene, whitted, kIntoTheSmoke, 20000);
    const Estimate traced = traceMean(*scene, pathTracer, kIntoTheSmoke, 40000);
    const double error = std::hypot(preview.standardError(), traced.standardError());
    EXPECT_NEAR(preview.mean(), traced.mean(), kDeviations * error);
    EXPECT_LT(error, 0.01 * traced.mean());
}

}  // namespace
}  // namespace penumbra::test
