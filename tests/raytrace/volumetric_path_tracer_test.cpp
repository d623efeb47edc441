// The path tracer in a participating medium (raytrace/path_tracer.h, core/medium.h), in-process,
// against closed forms and an independent quadrature:
// - an enclosure whose walls emit Le and reflect rho, filled with a medium that scatters and does
//   not absorb (albedo 1), has the radiance Le / (1 - rho) everywhere, whatever the medium's
//   density (even or in puffs on a grid) and phase function: the furnace of the radiative transfer
//   equation, which tests the free flights, the scattering events' next-event estimation (shadow
//   rays through the medium, weighed against phase sampling) and their bounces together;
// - an emitter seen through an absorbing slab, and a floor lit by a point light through an
//   absorbing medium, are attenuated by Beer-Lambert's exp(-sigma_a L) along each segment;
// - the light a point light scatters once into a ray that passes it (the airlight integral) is
//   a 1-D integral along the ray, which a Simpson rule in double precision computes apart
//   (Sun, Ramamoorthi, Narasimhan and Nayar 2005, "A Practical Analytic Single Scattering Model
//   for Real Time Rendering", Eq. 1), for an isotropic and a forward-scattering medium, at the
//   defaults (equiangular sampling towards the lamp with the free flights) and by free flights
//   alone, also in a haze of graded density on a grid (its optical depths exact in the
//   quadrature), and the two estimators agree on a box of smoke where light scatters many
//   times, even or in puffs;
// - light groups in one render through smoke: each group as a render lit by it alone.
#include "core/light_groups.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "raytrace/path_tracer.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/medium_scenes.h"
#include "tests/support/radiosity_scenes.h"
#include "tests/support/sample_estimate.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

namespace penumbra::test {
namespace {

// Deviations of a mean from its exact value the tests accept: 4.5 standard errors are exceeded
// with probability 7e-6 for a normal mean (path_tracer_furnace_test.cpp's argument).
constexpr double kDeviations = 4.5;

// The mean and standard error of the green channel of n independent paths along `ray` (file
// coordinates), each sample 0 of its own pixel (independent scrambles).
Estimate tracePaths(const Scene& scene, const PathTracerSettings& settings, Ray ray, int n) {
    ray.o -= Vec3(scene.description().origin);
    const PathTracer tracer(scene, settings);
    Sampler sampler(5);
    PathCounters counters;
    Estimate estimate;
    for (int i = 0; i < n; ++i) {
        sampler.startPixelSample(IVec2(i % 256, i / 256), 0);
        estimate.add(tracer.Li(ray, sampler, nullptr, counters).total().g);
    }
    return estimate;
}

TEST(VolumetricPathTracer, AScatteringFurnaceHoldsItsRadiance) {
    constexpr float kRho = 0.5f;
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(kRho), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    // Even, and in puffs (the box's inside: the grid needs a box).
    struct Case {
        float g;
        const DensityField* density;
    };
    for (const Case c : {Case{0.0f, nullptr}, Case{0.7f, nullptr}, Case{0.7f, &kPuffs}}) {
        const float g = c.g;
        SCOPED_TRACE("g = " + std::to_string(g) + (c.density ? ", puffs" : ""));
        // Mean free path 0.67 m in the 2 m box (even): most paths scatter several times.
        const std::unique_ptr<Scene> scene =
            withMedium(builder, "volumetric-furnace",
                       MediumDesc{.name = "fog",
                                  .sigmaA = Color(0.0f),
                                  .sigmaS = Color(1.5f),
                                  .g = g,
                                  .box = c.density ? std::optional(Bounds3{Vec3(-1.0f), Vec3(1.0f)})
                                                   : std::nullopt},
                       c.density);
        for (const Vec3 d : {Vec3(0.3f, -0.5f, 0.8f), Vec3(0.0f, 1.0f, 0.0f)}) {
            const Estimate L =
                tracePaths(*scene, PathTracerSettings{}, Ray{Vec3(0.1f), glm::normalize(d)}, 20000);
            const double expected = 1.0 / (1.0 - kRho);
            EXPECT_NEAR(L.mean(), expected, kDeviations * L.standardError());
            EXPECT_LT(L.standardError(), 0.01 * expected);
        }
    }
}

// Thermal equilibrium (Kirchhoff's law, the radiative transfer equation's furnace with emission):
// walls that reflect rho and emit (1 - rho) Le, around a medium that absorbs, scatters and emits
// sigma_a Le per metre (core/medium.h), give the radiance Le everywhere, in every direction,
// whatever the density, the albedo and the phase function (tests/support/medium_scenes.h).
TEST(VolumetricPathTracer, AGlowingMediumInAFurnaceIsInEquilibrium) {
    const Color Le(1.0f, 2.0f, 0.5f);
    const GltfBuilder builder = equilibriumBox(0.4f, Le);
    for (const DensityField* density : {static_cast<const DensityField*>(nullptr), &kPuffs}) {
        SCOPED_TRACE(density ? "puffs" : "even");
        const std::unique_ptr<Scene> scene =
            withMedium(builder, "volumetric-equilibrium", glowingMedium(Le), density);
        const PathTracer tracer(*scene, PathTracerSettings{});
        Sampler sampler(3);
        PathCounters counters;
        for (const Vec3 d : {Vec3(0.3f, -0.5f, 0.8f), Vec3(0.0f, 1.0f, 0.0f)}) {
            Estimate L[3];
            for (int i = 0; i < 10000; ++i) {
                sampler.startPixelSample(IVec2(i % 256, i / 256), 0);
                const Ray ray{Vec3(0.1f) - Vec3(scene->description().origin), glm::normalize(d)};
                const Color radiance = tracer.Li(ray, sampler, nullptr, counters).total();
                for (int c = 0; c < 3; ++c)
                    L[c].add(radiance[c]);
            }
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(L[c].mean(), Le[c], kDeviations * L[c].standardError() + 1e-5)
                    << "channel " << c;
                EXPECT_LT(L[c].standardError(), 0.01 * Le[c]);
            }
        }
    }
}

TEST(VolumetricPathTracer, AnEmitterSeenThroughAnAbsorbingSlab) {
    const Color sigmaA(0.1f, 0.4f, 1.0f);
    const std::unique_ptr<Scene> scene =
        withMedium(panelAtFiveMetres(), "volumetric-slab", slabBetween(sigmaA));
    const PathTracer tracer(*scene, PathTracerSettings{});
    Sampler sampler(1);
    PathCounters counters;
    // Straight on, and slanted: the path in the slab is 1.5 m over the cosine.
    for (const Vec3 target : {Vec3(0, 0, -5), Vec3(0.8f, 0.5f, -5)}) {
        const Vec3 d = glm::normalize(target);
        const float length = 1.5f / -d.z;
        sampler.startPixelSample(IVec2(0), 0);
        const Color L =
            tracer.Li(Ray{-Vec3(scene->description().origin), d}, sampler, nullptr, counters)
                .total();
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(L[c], kPanelRadiance * std::exp(-sigmaA[c] * length), 1e-5f)
                << "channel " << c;
    }
}

TEST(VolumetricPathTracer, AFloorLitThroughAnAbsorbingMedium) {
    GltfBuilder builder;
    const int floor = builder.addMaterial({.baseColor = Color(0.6f)});
    builder.addQuad({-4, 0, 4}, {4, 0, 4}, {4, 0, -4}, {-4, 0, -4}, floor);
    const Vec3 lamp(0.5f, 2.0f, -0.5f);
    builder.addLight({.type = "point", .intensity = 30.0f, .position = lamp});
    constexpr float kSigmaA = 0.3f;
    const std::unique_ptr<Scene> scene =
        withMedium(builder, "volumetric-floor",
                   MediumDesc{.name = "smoke",
                              .sigmaA = Color(kSigmaA),
                              .sigmaS = Color(0.0f),
                              .g = 0.0f,
                              .box = Bounds3{Vec3(-5, -1, -5), Vec3(5, 5, 5)}});
    // The direct light alone (one scattering event): exact for a point light, one sample.
    PathTracerSettings direct;
    direct.maxDepth = 1;
    const Vec3 eye(-1.0f, 3.0f, 2.0f), point(1.0f, 0.0f, 0.5f);
    const Estimate L = tracePaths(*scene, direct, Ray{eye, glm::normalize(point - eye)}, 4);
    const Vec3 toLamp = lamp - point;
    const float r = glm::length(toLamp);
    const float E = 30.0f * (toLamp.y / r) / (r * r) * std::exp(-kSigmaA * r);
    const float expected = 0.6f / kPi * E * std::exp(-kSigmaA * glm::length(point - eye));
    EXPECT_NEAR(L.mean(), expected, 1e-5 * expected);
    EXPECT_EQ(L.lo, L.hi);
}

// The light scattered once into `ray` (maxDepth 1), at the defaults (equiangular sampling with
// the free flights) and by free flights alone, each against `expected`; their standard errors.
std::array<double, 2> expectSingleScattering(const Scene& scene, const Ray& ray, double expected) {
    std::array<double, 2> standardErrors{};
    for (const bool equiangular : {true, false}) {
        SCOPED_TRACE(equiangular ? "equiangular" : "free flights alone");
        PathTracerSettings single;
        single.maxDepth = 1;
        single.equiangular = equiangular;
        const Estimate L = tracePaths(scene, single, ray, 40000);
        EXPECT_NEAR(L.mean(), expected, kDeviations * L.standardError());
        EXPECT_LT(L.standardError(), 0.02 * expected);
        standardErrors[equiangular ? 0 : 1] = L.standardError();
    }
    return standardErrors;
}

TEST(VolumetricPathTracer, SingleScatteringOfAPointLightIsTheAirlightIntegral) {
    const GltfBuilder builder = lampAtTheOrigin();
    constexpr float kSigmaS = 0.2f, kSigmaA = 0.1f;
    // The ray passes h = 1 m or 0.1 m from the lamp and leaves the box [-5, 5]^3 at x = 5, t = 9.
    // Equiangular sampling's standard error over that of free flights alone, measured with these
    // seeds: 0.32 (isotropic, 1 m), 0.84 (forward, 1 m: the phase function's peak, which neither
    // strategy follows, takes much of the variance) and 0.37 (forward, 0.1 m); the bounds leave a
    // margin for another sampler, not for a loss of the gain.
    struct Case {
        float g, h, maxRatio;
    };
    const Vec3 d(1.0f, 0.0f, 0.0f);
    for (const Case& c : {Case{0.0f, 1.0f, 0.5f}, Case{0.6f, 1.0f, 1.0f}, Case{0.6f, 0.1f, 0.5f}}) {
        const float g = c.g;
        SCOPED_TRACE("g = " + std::to_string(g) + ", h = " + std::to_string(c.h));
        const Vec3 o(-4.0f, c.h, 0.0f);
        const std::unique_ptr<Scene> scene =
            withMedium(builder, "volumetric-airlight",
                       MediumDesc{.name = "haze",
                                  .sigmaA = Color(kSigmaA),
                                  .sigmaS = Color(kSigmaS),
                                  .g = g,
                                  .box = Bounds3{Vec3(-5.0f), Vec3(5.0f)}});
        const double expected =
            airlight(o, d, 9.0, kLampIntensity, kSigmaS, kSigmaA + kSigmaS, HenyeyGreenstein(g));
        const std::array<double, 2> standardErrors =
            expectSingleScattering(*scene, Ray{o, d}, expected);
        // Drawn towards the lamp, the events pass its 1 / r^2 peak: less noise.
        EXPECT_LT(standardErrors[0], c.maxRatio * standardErrors[1]);
    }
}

// The same in a haze whose density grows along x and y (from 0.2 to 1.8 per unit of sigma):
// the density grid's exact optical depths and free flights, and equiangular sampling weighed
// against them, in a heterogeneous medium.
TEST(VolumetricPathTracer, SingleScatteringInAGradedHazeIsTheAirlightIntegral) {
    constexpr float kSigmaS = 0.3f, kSigmaA = 0.1f;
    const AffineDensity graded = [](const glm::dvec3& p) { return 1.0 + 0.12 * p.x + 0.04 * p.y; };
    const DensityField field{[&](const Vec3& p) { return graded(glm::dvec3(p)); }, {11, 6, 4}};
    const std::unique_ptr<Scene> scene =
        withMedium(lampAtTheOrigin(), "volumetric-graded",
                   MediumDesc{.name = "graded haze",
                              .sigmaA = Color(kSigmaA),
                              .sigmaS = Color(kSigmaS),
                              .g = 0.3f,
                              .box = Bounds3{Vec3(-5.0f), Vec3(5.0f)}},
                   &field);
    const Vec3 o(-4.0f, 0.5f, 0.3f), d = glm::normalize(Vec3(1.0f, 0.1f, 0.0f));
    // The ray leaves the box at x = 5.
    const double tEnd = 9.0 / d.x;
    const double expected = airlight(o, d, tEnd, kLampIntensity, kSigmaS, kSigmaA + kSigmaS,
                                     HenyeyGreenstein(0.3f), graded);
    expectSingleScattering(*scene, Ray{o, d}, expected);
}

// Multiple scattering of a point light in smoke between grey walls (smokyRoom(), kLowSmoke, even
// and in puffs): equiangular sampling and free flights alone are two estimators of the same
// radiance (every event after the first too).

TEST(VolumetricPathTracer, EquiangularSamplingAgreesWithFreeFlightsAlone) {
    for (const DensityField* density : {static_cast<const DensityField*>(nullptr), &kPuffs}) {
        SCOPED_TRACE(density ? "puffs" : "even smoke");
        const std::unique_ptr<Scene> scene =
            withMedium(smokyRoom(), "volumetric-smoke", kLowSmoke, density);
        Estimate estimates[2];
        for (const bool equiangular : {true, false}) {
            PathTracerSettings settings;
            settings.equiangular = equiangular;
            estimates[equiangular ? 0 : 1] = tracePaths(*scene, settings, kIntoTheSmoke, 40000);
        }
        const double error = std::hypot(estimates[0].standardError(), estimates[1].standardError());
        EXPECT_NEAR(estimates[0].mean(), estimates[1].mean(), kDeviations * error);
        EXPECT_LT(error, 0.01 * estimates[1].mean());
    }
}

// Light groups in one render through the medium (core/light_groups.h): the smoky room, lit by
// its lamp, by an emissive panel under the ceiling and by the smoke's own glow. Each sample's
// groups sum to its radiance, and each group's mean is that of a render lit by the group alone, so
// the scattering events' light samples, equiangular and free-flight alike, are drawn and weighted
// within each group.
TEST(VolumetricPathTracer, LightGroupsSplitTheMediumsLight) {
    GltfBuilder builder = smokyRoom();
    const int panel = builder.addMaterial({.baseColor = Color(0.0f),
                                           .emissive = Color(1.0f, 0.8f, 0.6f),
                                           .emissiveStrength = 2.0f,
                                           .name = "Panel"});
    // Facing down: counter-clockwise seen from below.
    builder.addQuad({-0.8f, 0.95f, -0.8f}, {-0.4f, 0.95f, -0.8f}, {-0.4f, 0.95f, -0.4f},
                    {-0.8f, 0.95f, -0.4f}, panel);
    // The smoke glows too: its emission is a group of its own.
    MediumDesc glowing = kLowSmoke;
    glowing.emission = Color(0.6f, 0.4f, 0.2f);
    const std::unique_ptr<Scene> smoky = withMedium(builder, "volumetric-groups", glowing);
    const SceneDescription& description = smoky->description();
    const LightGroupSplit split(*smoky);
    ASSERT_EQ(split.groups().size(), 3u);
    EXPECT_EQ(split.groups()[2].name, "medium");
    const PathTracer tracer(*smoky, PathTracerSettings{}, nullptr, nullptr, &split);
    Ray ray = kIntoTheSmoke;
    ray.o -= Vec3(description.origin);
    constexpr int kSamples = 20000;
    std::vector<Estimate> splitMeans(split.groups().size());
    Sampler sampler(9);
    PathCounters counters;
    for (int i = 0; i < kSamples; ++i) {
        sampler.startPixelSample(IVec2(i % 256, i / 256), 0);
        const PathRadiance L = tracer.Li(ray, sampler, nullptr, counters);
        Color sum(0.0f);
        for (size_t g = 0; g < split.groups().size(); ++g) {
            sum += L.groups[g];
            splitMeans[g].add(L.groups[g].g);
        }
        ASSERT_NEAR(sum.g, L.total().g, 1e-5f * L.total().g + 1e-9f) << "sample " << i;
    }
    for (size_t g = 0; g < split.groups().size(); ++g) {
        SCOPED_TRACE(split.groups()[g].name);
        const Scene alone(litOnlyBy(description, split.groups()[g]));
        const PathTracer plain(alone, PathTracerSettings{});
        Estimate aloneMean;
        Sampler aloneSampler(21);
        for (int i = 0; i < kSamples; ++i) {
            aloneSampler.startPixelSample(IVec2(i % 256, i / 256), 0);
            aloneMean.add(plain.Li(ray, aloneSampler, nullptr, counters).total().g);
        }
        const double error = std::hypot(splitMeans[g].standardError(), aloneMean.standardError());
        EXPECT_NEAR(splitMeans[g].mean(), aloneMean.mean(), kDeviations * error);
        EXPECT_LT(error, 0.02 * aloneMean.mean());
    }
}

}  // namespace
}  // namespace penumbra::test
