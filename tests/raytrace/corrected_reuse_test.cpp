// The hybrid's correction of a reused radiosity solution (raytrace/path_tracer.h,
// PathTracerSettings::correctionProbability) in-process in the closed furnace box, against the
// closed form L = Le / (1 - rho) (as tests/raytrace/path_tracer_furnace_test.cpp): with a
// deliberately wrong solution (none at all, or three times too bright) the corrected estimator
// still converges to L, at any continuation probability; the uncorrected one gives exactly what
// the wrong solution implies, and the correction it reports apart is the difference. Then the
// same against the path tracer in a mirror room and with plastic walls, and which part of the
// correction goes to the image's filter. Last, in participating media, where the solution holds
// none of the medium's scattered light: the furnace's closed forms with a medium in it, and the
// path tracer where specular chains follow scattering events.
#include "core/path_components.h"
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
#include <cstdio>
#include <memory>

namespace penumbra::test {
namespace {

constexpr float kLe = 2.0f;  // cd/m², emitted by every wall
constexpr float kRho = 0.5f;
// The furnace's radiance, and what every wall reflects of it (emission excluded): L - Le.
constexpr double kRadiance = kLe / (1.0 - kRho);
constexpr double kReflected = kRadiance - kLe;

std::unique_ptr<Scene> furnaceBox() {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(kRho), .emissive = Color(1.0f), .emissiveStrength = kLe});
    addClosedBox(builder, wall, wall);
    return loadBuiltScene(builder, "corrected-reuse-furnace");
}

// A radiosity solution that says every wall reflects `value`, whatever the truth.
class ConstantSolution : public ReusedSolution {
  public:
    explicit ConstantSolution(float value) : value_(value) {}
    Color reflected(const SurfaceHit&, bool) const override { return Color(value_); }
    Color indirect(const SurfaceHit&, bool) const override { return Color(value_ * kRho); }

  private:
    float value_;
};

struct Estimates {
    Estimate total, correction;           // of the green channel
    std::array<Estimate, 3> channels;     // the total's, per channel
    int pathsWithFilteredCorrection = 0;  // paths that returned a non-zero correction
};

// n independent paths along `ray` (each sample 0 of its own pixel, as in the furnace test, so the
// sample standard error is the estimator's).
Estimates tracePaths(const Scene& scene, const PathTracerSettings& settings,
                     const ReusedSolution* solution, const Ray& ray, int n) {
    const PathTracer tracer(scene, settings, solution);
    Sampler sampler(17);
    PathCounters counters;
    Estimates e;
    for (int i = 0; i < n; ++i) {
        sampler.startPixelSample(IVec2(i % 256, i / 256), 0);
        const PathRadiance L = tracer.Li(ray, sampler, nullptr, counters);
        const Color total = L.total();
        e.total.add(total.g);
        for (int c = 0; c < 3; ++c)
            e.channels[size_t(c)].add(total[c]);
        e.correction.add(L.correction().g);
        e.pathsWithFilteredCorrection += L.correction() != Color(0.0f);
    }
    return e;
}

PathTracerSettings reuse(float correctionProbability) {
    PathTracerSettings settings;
    settings.reuseRadiosity = true;
    settings.correctionProbability = correctionProbability;
    return settings;
}

const Ray kFurnaceRay{Vec3(0.0f), glm::normalize(Vec3(0.3f, -0.5f, 0.8f))};

Estimates tracePaths(const Scene& scene, float solutionValue, float correctionProbability, int n) {
    const ConstantSolution solution(solutionValue);
    return tracePaths(scene, reuse(correctionProbability), &solution, kFurnaceRay, n);
}

// As in the furnace test: 4.5 standard errors (probability 7e-6 per check for a normal mean), and
// a standard error below 0.5 % of L so that the check can see an error of 2.25 % of L.
constexpr double kStandardErrors = 4.5;
constexpr double kMaxRelativeStandardError = 0.005;

void expectMean(const Estimate& e, double exact, const char* what) {
    std::printf("%s: %.5f +- %.5f (exact %.5f)\n", what, e.mean(), e.standardError(), exact);
    EXPECT_NEAR(e.mean(), exact, kStandardErrors * e.standardError()) << what;
    EXPECT_LT(e.standardError(), kMaxRelativeStandardError * kRadiance) << what;
}

// Without a correction the path sees the wall's emission, the first vertex's direct light (one
// reflection of Le, by next-event estimation and the emission its bounce finds) and, at the
// second vertex, the solution reflected once more: Le + rho Le + rho S, exactly.
TEST(CorrectedReuse, UncorrectedReuseGivesWhatTheSolutionImplies) {
    const std::unique_ptr<Scene> scene = furnaceBox();
    for (const float solution : {0.0f, float(kReflected), float(3.0 * kReflected)}) {
        const Estimates e = tracePaths(*scene, solution, 0.0f, 16384);
        expectMean(e.total, kLe + kRho * kLe + kRho * solution, "uncorrected");
        EXPECT_EQ(e.correction.sum, 0.0);
    }
}

struct Case {
    const char* name;
    float solution;     // in units of the true reflected radiance
    float probability;  // the correction's continuation probability
};

class CorrectedReuse : public ::testing::TestWithParam<Case> {};

TEST_P(CorrectedReuse, ConvergesToTheClosedFormWhateverTheSolution) {
    const std::unique_ptr<Scene> scene = furnaceBox();
    const Case c = GetParam();
    const float solution = c.solution * float(kReflected);
    const Estimates e = tracePaths(*scene, solution, c.probability, 65536);
    expectMean(e.total, kRadiance, "corrected");
    // The correction reported apart is what the solution missed at the second vertex: rho (the
    // true reflected radiance - S).
    expectMean(e.correction, kRho * (kReflected - solution), "correction");
}

INSTANTIATE_TEST_SUITE_P(Furnace, CorrectedReuse,
                         ::testing::Values(Case{"NoSolution", 0.0f, 0.5f},
                                           Case{"ThreeTimesTooBright", 3.0f, 0.5f},
                                           Case{"RightSolution", 1.0f, 0.5f},
                                           Case{"NoSolutionRarelyCorrected", 0.0f, 0.1f},
                                           Case{"TooBrightAlwaysCorrected", 3.0f, 1.0f}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                             return std::string(info.param.name);
                         });

// A closed room lit mostly through a mirror (addMirrorRoom, as tests/passes/
// indirect_caustics_test.cpp): most of the room's light has passed the mirror, which a solution
// treats as black. Against the path
// tracer, whatever the solution says: the correction must bring back what it lacks, through the
// mirror or not.
TEST(CorrectedReuse, MatchesThePathTracerInAMirrorRoom) {
    GltfBuilder builder;
    addMirrorRoom(builder);
    const std::unique_ptr<Scene> scene = loadBuiltScene(builder, "corrected-reuse-mirror-room");

    // Towards the floor, which the mirror lights; caustics left out as in the hybrid (its
    // caustic pass counts them).
    constexpr int n = 1 << 20;
    const Ray ray{Vec3(0.0f, -0.2f, 0.5f), glm::normalize(Vec3(0.0f, -1.0f, 0.2f))};
    PathTracerSettings plain;
    plain.excludeCaustics = true;
    const Estimates pathTracer = tracePaths(*scene, plain, nullptr, ray, n);
    // No solution at all: every reflection after the first diffuse vertex is the correction's.
    const ConstantSolution none(0.0f);
    PathTracerSettings settings = reuse(0.5f);
    settings.excludeCaustics = true;
    const Estimates corrected = tracePaths(*scene, settings, &none, ray, n);
    const double difference = corrected.total.mean() - pathTracer.total.mean();
    const double error =
        std::hypot(corrected.total.standardError(), pathTracer.total.standardError());
    std::printf("corrected %.5f +- %.5f, path tracer %.5f +- %.5f\n", corrected.total.mean(),
                corrected.total.standardError(), pathTracer.total.mean(),
                pathTracer.total.standardError());
    EXPECT_NEAR(difference, 0.0, kStandardErrors * error);
    // Most of this light takes rare paths (through the small mirror image of the lamp): the
    // check sees a bias above 4.5 x 2 % of the radiance, e.g. the light of a mirror bounce (most
    // of it) lost or counted twice. Measured: 1.6 % (seed 17).
    EXPECT_LT(error, 0.02 * pathTracer.total.mean());
}

// The furnace box with plastic walls (a Lambertian base under a dielectric coat, smooth or
// rough): the reuse vertex then splits into the Lambertian layer the solution stands for, and a
// delta or rough glossy lobe the path follows. With no solution at all the corrected reuse must
// still be the path tracer's estimate.
class CorrectedReuseOnPlastic : public ::testing::TestWithParam<float> {};

TEST_P(CorrectedReuseOnPlastic, MatchesThePathTracer) {
    GltfBuilder builder;
    const int wall = builder.addMaterial({.baseColor = Color(0.6f),
                                          .emissive = Color(1.0f),
                                          .emissiveStrength = kLe,
                                          .lambertian = false,
                                          .roughness = GetParam()});
    addClosedBox(builder, wall, wall);
    const std::unique_ptr<Scene> scene = loadBuiltScene(builder, "corrected-reuse-plastic");
    constexpr int n = 65536;
    const Estimates pathTracer = tracePaths(*scene, PathTracerSettings{}, nullptr, kFurnaceRay, n);
    const ConstantSolution none(0.0f);
    const Estimates corrected = tracePaths(*scene, reuse(0.5f), &none, kFurnaceRay, n);
    std::printf("roughness %.1f: corrected %.5f +- %.5f, path tracer %.5f +- %.5f\n", GetParam(),
                corrected.total.mean(), corrected.total.standardError(), pathTracer.total.mean(),
                pathTracer.total.standardError());
    const double error =
        std::hypot(corrected.total.standardError(), pathTracer.total.standardError());
    EXPECT_NEAR(corrected.total.mean(), pathTracer.total.mean(), kStandardErrors * error);
    EXPECT_LT(error, kMaxRelativeStandardError * pathTracer.total.mean());
}

INSTANTIATE_TEST_SUITE_P(Coat, CorrectedReuseOnPlastic, ::testing::Values(0.0f, 0.3f));

// The correction PathRadiance::corrections returns is what the image's filter averages over
// neighbouring pixels, whichever lobe the eye's first non-delta vertex was left through: a rough
// metal floor (glossy lobes only) hands its correction to the filter as a Lambertian floor does
// (the filter's width per pixel keeps a sharp reflection sharp: correction_filter.h), and the
// path's estimate is still the path tracer's.
TEST(CorrectedReuse, EveryFirstVertexHandsItsCorrectionToTheFilter) {
    const auto box = [](bool metalFloor) {
        GltfBuilder builder;
        const int wall = builder.addMaterial(
            {.baseColor = Color(kRho), .emissive = Color(1.0f), .emissiveStrength = kLe});
        const int floor = metalFloor ? builder.addMaterial({.baseColor = Color(0.8f),
                                                            .lambertian = false,
                                                            .metallic = 1.0f,
                                                            .roughness = 0.3f})
                                     : wall;
        addClosedBox(builder, wall, floor);
        return loadBuiltScene(
            builder, metalFloor ? "corrected-reuse-metal-floor" : "corrected-reuse-matte-floor");
    };
    const Ray towardsTheFloor{Vec3(0.0f), glm::normalize(Vec3(0.2f, -1.0f, 0.1f))};
    constexpr int n = 65536;
    const ConstantSolution none(0.0f);

    const std::unique_ptr<Scene> metal = box(true);
    const Estimates pathTracer =
        tracePaths(*metal, PathTracerSettings{}, nullptr, towardsTheFloor, n);
    const Estimates corrected = tracePaths(*metal, reuse(0.5f), &none, towardsTheFloor, n);
    std::printf("metal floor: corrected %.5f +- %.5f, path tracer %.5f +- %.5f\n",
                corrected.total.mean(), corrected.total.standardError(), pathTracer.total.mean(),
                pathTracer.total.standardError());
    EXPECT_GT(corrected.pathsWithFilteredCorrection, n / 3);  // q = 0.5
    const double error =
        std::hypot(corrected.total.standardError(), pathTracer.total.standardError());
    EXPECT_NEAR(corrected.total.mean(), pathTracer.total.mean(), kStandardErrors * error);
    EXPECT_LT(error, kMaxRelativeStandardError * pathTracer.total.mean());

    // On the Lambertian floor as well.
    const std::unique_ptr<Scene> matte = box(false);
    const Estimates filtered = tracePaths(*matte, reuse(0.5f), &none, towardsTheFloor, n);
    EXPECT_GT(filtered.pathsWithFilteredCorrection, n / 3);
}

// Participating media: no solution holds a medium's scattered light, so the correction traces it
// (raytrace/path_tracer.h). A closed box of walls that emit Le and reflect rho, filled with a
// medium of albedo 1, has the radiance Le / (1 - rho) everywhere (the furnace with a medium, as
// in tests/raytrace/volumetric_path_tracer_test.cpp); reused with no solution or one three times
// too bright, the corrected estimate keeps it, in an even medium and in puffs of smoke.
TEST(CorrectedReuseInMedia, TheScatteringFurnaceHoldsItsRadianceWhateverTheSolution) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(kRho), .emissive = Color(1.0f), .emissiveStrength = kLe});
    addClosedBox(builder, wall, wall);
    for (const DensityField* density : {static_cast<const DensityField*>(nullptr), &kPuffs}) {
        const std::unique_ptr<Scene> scene =
            withMedium(builder, "corrected-reuse-scattering-furnace",
                       MediumDesc{.name = "fog",
                                  .sigmaA = Color(0.0f),
                                  .sigmaS = Color(1.5f),
                                  .g = 0.7f,
                                  .box = Bounds3{Vec3(-1.0f), Vec3(1.0f)}},
                       density);
        for (const float solution : {0.0f, float(3.0 * kReflected)}) {
            SCOPED_TRACE(std::string(density ? "puffs" : "even") + ", solution " +
                         std::to_string(solution));
            const ConstantSolution wrong(solution);
            const Estimates e = tracePaths(*scene, reuse(0.5f), &wrong, kFurnaceRay, 65536);
            expectMean(e.total, kRadiance, "corrected in a medium");
        }
    }
}

// Thermal equilibrium: walls that reflect rho and emit (1 - rho) Le around a medium that absorbs,
// scatters and emits with Le give the radiance Le in every channel (Kirchhoff's law:
// tests/support/medium_scenes.h), whatever the solution says of the walls.
TEST(CorrectedReuseInMedia, AGlowingMediumStaysInEquilibriumWhateverTheSolution) {
    const Color Le(1.0f, 2.0f, 0.5f);
    const std::unique_ptr<Scene> scene =
        withMedium(equilibriumBox(kRho, Le), "corrected-reuse-equilibrium", glowingMedium(Le));
    for (const float solution : {0.0f, 3.0f}) {
        const ConstantSolution wrong(solution);
        const Estimates e = tracePaths(*scene, reuse(0.5f), &wrong, kFurnaceRay, 32768);
        for (int c = 0; c < 3; ++c) {
            const Estimate& L = e.channels[size_t(c)];
            std::printf("solution %.1f, channel %d: %.5f +- %.5f (exact %.5f)\n", solution, c,
                        L.mean(), L.standardError(), Le[c]);
            EXPECT_NEAR(L.mean(), Le[c], kStandardErrors * L.standardError()) << "channel " << c;
            EXPECT_LT(L.standardError(), 0.01 * Le[c]) << "channel " << c;
        }
    }
}

// Against the path tracer, with no solution at all: the smoky room (a point light above
// chromatic smoke, where light scatters many times), and a room with a mirror ceiling in a haze,
// where paths scatter in the haze and then meet the mirror (the base counts the light the mirror
// brings them, the correction what comes before: neither twice).
TEST(CorrectedReuseInMedia, MatchesThePathTracer) {
    struct Case {
        const char* name;
        std::unique_ptr<Scene> scene;
        Ray ray;
    };
    GltfBuilder mirrorRoom;
    addMirrorCeilingRoom(mirrorRoom);
    Case cases[] = {
        {"smoky room", withMedium(smokyRoom(), "corrected-reuse-smoky-room", kLowSmoke),
         kIntoTheSmoke},
        {"mirror ceiling in haze",
         withMedium(mirrorRoom, "corrected-reuse-hazy-mirror-ceiling",
                    MediumDesc{.name = "haze",
                               .sigmaA = Color(0.05f, 0.1f, 0.2f),
                               .sigmaS = Color(0.4f),
                               .g = 0.3f,
                               .box = std::nullopt}),
         Ray{Vec3(0.0f, -0.2f, 0.5f), glm::normalize(Vec3(0.0f, -1.0f, 0.2f))}},
    };
    const ConstantSolution none(0.0f);
    for (const Case& c : cases) {
        constexpr int n = 1 << 18;
        const Estimates pathTracer = tracePaths(*c.scene, PathTracerSettings{}, nullptr, c.ray, n);
        const Estimates corrected = tracePaths(*c.scene, reuse(0.5f), &none, c.ray, n);
        for (size_t k = 0; k < 3; ++k) {
            const Estimate &a = corrected.channels[k], &b = pathTracer.channels[k];
            std::printf("%s, channel %zu: corrected %.5f +- %.5f, path tracer %.5f +- %.5f\n",
                        c.name, k, a.mean(), a.standardError(), b.mean(), b.standardError());
            const double error = std::hypot(a.standardError(), b.standardError());
            EXPECT_NEAR(a.mean(), b.mean(), kStandardErrors * error) << c.name << " " << k;
            EXPECT_LT(error, 0.01 * b.mean()) << c.name << " " << k;
        }
    }
}

}  // namespace
}  // namespace penumbra::test
