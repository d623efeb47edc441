// The path tracer in-process in the closed furnace box, against the closed form of the radiosity
// equation: every wall is Lambertian with albedo rho and emits Le, so the radiance everywhere is
// L = Le / (1 - rho), and its Neumann series Le sum_k rho^k gives what a path cut after k
// scattering events sees (maxDepth) and what each light-path component holds.
#include "core/path_components.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "raytrace/path_tracer.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"
#include "tests/support/sample_estimate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>

namespace penumbra::test {
namespace {

constexpr float kLe = 2.0f;  // cd/m², emitted by every wall

// The cube [-1, 1]^3 seen from inside, every face emitting kLe and reflecting rho (Lambertian).
std::unique_ptr<Scene> furnaceBox(float rho) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(rho), .emissive = Color(1.0f), .emissiveStrength = kLe});
    addClosedBox(builder, wall, wall);
    return loadBuiltScene(builder, "raytrace-furnace");
}

// The closed form. In an enclosure the form factors from any point sum to 1, so the radiosity
// equation L = Le + rho sum_j F_j L_j (Goral et al. 1984, "Modeling the Interaction of Light
// Between Diffuse Surfaces"; Cohen and Wallace 1993, "Radiosity and Realistic Image Synthesis",
// ch. 2) has the uniform solution L = Le / (1 - rho), whose Neumann series Le sum_k rho^k counts
// k reflections in term k: emission (k = 0), direct light (k = 1), indirect light (k >= 2).
double truncatedSeries(double rho, int depth) {
    double sum = 0.0, term = kLe;
    for (int k = 0; k <= depth; ++k, term *= rho)
        sum += term;
    return sum;
}

struct FurnaceEstimates {
    Estimate total, emission, direct, indirect, specular;
};

// n paths from the box's centre along one direction (the radiance is the same in every
// direction). Sample i is sample 0 of its own pixel: the sampler hashes (seed, pixel, dimension)
// into independent scrambles, so the paths are independent and the sample standard error is the
// estimator's (successive indices of one pixel would form a stratified net, whose error the
// sample variance overstates).
FurnaceEstimates tracePaths(const Scene& scene, const PathTracerSettings& settings, int n,
                            uint32_t seed) {
    const PathTracer tracer(scene, settings);
    const Ray ray{Vec3(0.0f), glm::normalize(Vec3(0.3f, -0.5f, 0.8f))};
    Sampler sampler(seed);
    PathCounters counters;
    FurnaceEstimates e;
    for (int i = 0; i < n; ++i) {
        sampler.startPixelSample(IVec2(i % 256, i / 256), 0);
        const PathRadiance L = tracer.Li(ray, sampler, nullptr, counters);
        // Grey scene: every channel is the same estimate; the green one is checked.
        e.total.add(L.total().g);
        e.emission.add(L[PathComponent::Emission].g);
        e.direct.add(L[PathComponent::Direct].g);
        e.indirect.add(L[PathComponent::Indirect].g);
        e.specular.add(L[PathComponent::Specular].g);
    }
    return e;
}

// The statistical check of every test here: the mean of n independent samples is within
// kStandardErrors standard errors (the sample standard deviation over sqrt(n)) of its exact
// value. For n in the thousands the mean is normal by the central limit theorem, and 4.5
// standard errors are exceeded with probability 7e-6 per check, so a seed that passes is not a
// lucky one and no seed should fail. So that a pass means something, the standard error must also
// be below 0.5 % of the radiance L of the test's set-up: the check then sees any error above
// 2.25 % of L, e.g. one reflection Le rho^k dropped among the first two at rho = 0.3 or the first
// nine at rho = 0.8 (rho^k (1 - rho) of L), a missing cos(theta) or 1 / pi (tens of per cent).
constexpr double kStandardErrors = 4.5;
constexpr double kMaxRelativeStandardError = 0.005;

void expectMean(const Estimate& e, double exact, double radiance, const char* what) {
    std::cout << what << ": " << e.mean() << " +- " << e.standardError() << " (exact " << exact
              << ")\n";
    EXPECT_NEAR(e.mean(), exact, kStandardErrors * e.standardError())
        << what << ": standard error " << e.standardError();
    EXPECT_LT(e.standardError(), kMaxRelativeStandardError * radiance)
        << what << ": too noisy to test anything";
}

class PathTracerFurnace : public ::testing::TestWithParam<float> {};

TEST_P(PathTracerFurnace, RadianceIsLeOverOneMinusRho) {
    const float rho = GetParam();
    const std::unique_ptr<Scene> scene = furnaceBox(rho);
    const FurnaceEstimates e = tracePaths(*scene, PathTracerSettings{}, 32768, 7);
    const double L = kLe / (1.0 - rho);
    expectMean(e.total, L, L, "L");
    // The camera ray sees the wall's emission itself, exactly, in every sample.
    EXPECT_EQ(e.emission.lo, kLe);
    EXPECT_EQ(e.emission.hi, kLe);
    // One reflection of the walls' emission, Le rho, is direct light; the rest of the series,
    // Le rho^2 / (1 - rho), indirect; a Lambertian box shows nothing specular.
    expectMean(e.direct, kLe * rho, L, "direct");
    expectMean(e.indirect, kLe * rho * rho / (1.0 - rho), L, "indirect");
    EXPECT_EQ(e.specular.hi, 0.0);
}

// maxDepth counts scattering events: 0 leaves the emission seen by the camera ray, 1 adds the
// first reflection (next-event estimation at the first vertex and the emission its BSDF sample
// finds), 2 the second; no Russian roulette acts before the third event.
TEST_P(PathTracerFurnace, MaxDepthTruncatesTheNeumannSeries) {
    const float rho = GetParam();
    const std::unique_ptr<Scene> scene = furnaceBox(rho);
    PathTracerSettings settings;

    settings.maxDepth = 0;
    const FurnaceEstimates none = tracePaths(*scene, settings, 64, 11);
    EXPECT_EQ(none.total.lo, kLe);
    EXPECT_EQ(none.total.hi, kLe);

    settings.maxDepth = 1;
    const FurnaceEstimates one = tracePaths(*scene, settings, 8192, 11);
    expectMean(one.total, truncatedSeries(rho, 1), truncatedSeries(rho, 1), "maxDepth 1");
    EXPECT_EQ(one.emission.lo, kLe);
    EXPECT_EQ(one.emission.hi, kLe);
    EXPECT_EQ(one.indirect.hi, 0.0);

    settings.maxDepth = 2;
    const FurnaceEstimates two = tracePaths(*scene, settings, 8192, 11);
    expectMean(two.total, truncatedSeries(rho, 2), truncatedSeries(rho, 2), "maxDepth 2");
    expectMean(two.indirect, kLe * rho * rho, truncatedSeries(rho, 2), "maxDepth 2, indirect");
}

INSTANTIATE_TEST_SUITE_P(Albedo, PathTracerFurnace, ::testing::Values(0.3f, 0.8f));

}  // namespace
}  // namespace penumbra::test
