// The bake's expected error (passes/solution_check.h) against closed forms: on a floor alone with
// its light, the light a floor point reflects is known exactly (rho E / pi), so the path tracer's
// estimate at each checked point, and the errors the check reports, can be compared with the
// solution's true error at the same points.
#include "passes/solution_check.h"
#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>

namespace penumbra::test {
namespace {

struct TrueErrors {
    double bias = 0.0, rms = 0.0;  // relative to the mean exact value, as SolutionCheck's
    double naiveRms = 0.0;         // the traced values' RMS difference, their noise left in
};

// The solution's errors at the checked points against `exact` there.
TrueErrors trueErrors(const SolutionCheck& check, const std::function<double(Vec3)>& exact) {
    double mean = 0.0, error = 0.0, squared = 0.0, naive = 0.0;
    for (const CheckedPoint& p : check.points) {
        const double e = exact(p.p);
        mean += e;
        error += p.solution - e;
        squared += (p.solution - e) * (p.solution - e);
        naive += (p.solution - p.traced) * (p.solution - p.traced);
    }
    const double n = double(check.points.size());
    mean /= n;
    return {error / n / mean, std::sqrt(squared / n) / mean, std::sqrt(naive / n) / mean};
}

// A point light over a floor, solved coarsely (element means, elements of 0.05 m² and more), so
// that the solution is measurably wrong under the light. The path tracer's direct light from a
// point light has no noise, so each traced value is the closed form, and the reported errors are
// the true ones.
TEST(SolutionCheck, UnderAPointLightItReportsTheTrueError) {
    const PointLightOverFloor setup;
    GltfBuilder builder;
    setup.build(builder);
    const std::unique_ptr<Scene> scene = loadBuiltScene(builder, "solution-check-point");
    RadiositySettings settings;
    settings.directAtCorners = false;
    settings.minElementArea = 0.05f;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();

    const SolutionCheck check = checkSolution(*scene, mesh, solver, {.points = 64, .samples = 16});
    ASSERT_EQ(check.points.size(), 64u);
    const auto exact = [&](Vec3 p) {
        const double h = setup.height, r2 = double(p.x) * p.x + double(p.z) * p.z;
        return setup.rho * setup.intensity * h / std::pow(h * h + r2, 1.5) / kPi;
    };
    for (const CheckedPoint& p : check.points) {
        EXPECT_NEAR(p.p.y, 0.0f, 1e-5f);
        EXPECT_NEAR(p.traced, exact(p.p), 1e-3 * exact(p.p)) << p.p.x << ", " << p.p.z;
    }
    const TrueErrors truth = trueErrors(check, exact);
    std::cout << "point light: reported bias " << check.bias << " rms " << check.rmsError
              << "; true bias " << truth.bias << " rms " << truth.rms << "\n";
    EXPECT_GT(truth.rms, 0.02) << "the coarse solution should be measurably wrong";
    EXPECT_NEAR(check.bias, truth.bias, 2e-3);
    EXPECT_NEAR(check.rmsError, truth.rms, 0.02 * truth.rms);
}

// A floor under a uniform sky of 1 cd/m²: E = pi at every point of its upper side, the floor's
// light rho. The path tracer's sky samples are noisy, about as much as the solution is wrong, and
// the check takes their variance out of the RMS error: it must land nearer the true error than
// the plain RMS difference does.
TEST(SolutionCheck, UnderAUniformSkyItTakesTheTracersNoiseOut) {
    constexpr float kRho = 0.5f, kHalf = 2.0f;
    GltfBuilder builder;
    const int floor = builder.addMaterial({.baseColor = Color(kRho)});
    builder.addQuad({-kHalf, 0, -kHalf}, {-kHalf, 0, kHalf}, {kHalf, 0, kHalf}, {kHalf, 0, -kHalf},
                    floor);
    SceneDescription description = loadBuiltScene(builder, "solution-check-sky")->description();
    EnvironmentDesc sky;
    sky.file = "uniform";
    sky.radiance = Image(4, 2, {"R", "G", "B"});
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 3; ++c)
                sky.radiance.at(x, y, c) = 1.0f;
    description.environment = sky;
    const Scene scene(std::move(description));
    const RadiositySettings settings;
    RadiosityMesh mesh(scene, settings.meshing(scene));
    RadiositySolver solver(scene, mesh, settings);
    solver.solve();

    const SolutionCheck check = checkSolution(scene, mesh, solver, {.points = 512, .samples = 64});
    const TrueErrors truth = trueErrors(check, [](Vec3) { return double(kRho); });
    std::cout << "uniform sky: reported bias " << check.bias << " +- " << check.biasStandardError
              << " rms " << check.rmsError << " noise " << check.noise << "; true bias "
              << truth.bias << " rms " << truth.rms << ", plain rms " << truth.naiveRms << "\n";
    EXPECT_GT(check.noise, 0.01) << "the sky's samples should be noisy";
    EXPECT_LT(std::abs(check.rmsError - truth.rms), 0.5 * std::abs(truth.naiveRms - truth.rms));
    EXPECT_LT(std::abs(check.bias - truth.bias), 3.0 * check.biasStandardError + 1e-3);
    EXPECT_NEAR(check.meanTraced, kRho, 4.0 * check.biasStandardError + 1e-3);
}

}  // namespace
}  // namespace penumbra::test
