// The hierarchical radiosity solver's final gather: in a closed room where every surface reflects
// rho, the indirect share of the reflected light must be rho, and where every surface also emits
// Le, every first reflection rho Le; the cluster links alone miss both and the gather's correction
// restores them; and the gather runs by default when the solver starts from clusters.
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <string>

namespace penumbra::test {
namespace {

// The reflectance of every surface of the rooms below.
constexpr float kRho = 0.5f;

// The share of the light reflected into a closed room that is indirect: over the sides facing
// the room (the fronts of its walls, wound inwards, and of the solids in it), sum A (L - Le -
// direct) over sum A (L - Le). Every lumen they reflect lands on another of them and is reflected
// again with rho, so where every surface reflects rho the indirect flux is rho times the whole,
// whatever the geometry and however much of the sources' light the links delivered (the first
// reflection). A transfer that loses or makes light moves the share off rho. (The stats' fluxes
// count the back sides too, where the cluster model pushes some first reflection onto the walls'
// outer backs, which face nothing.)
double indirectShare(const RadiosityMesh& mesh, const RadiositySolver& solver) {
    double reflected = 0.0, indirect = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element))
            continue;
        reflected += mesh.area(element) *
                     (solver.elementDirect(element).g + solver.elementIndirect(element).g);
        indirect += mesh.area(element) * solver.elementIndirect(element).g;
    }
    return indirect / reflected;
}

// The furnace box's walls (emitting Le = 1, rho = 0.5) with three solid slabs of the same rho
// inside, emitting Le = 1 too when `slabsEmit`.
std::unique_ptr<Scene> roomWithSlabs(bool slabsEmit, const std::string& name) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(kRho), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    const int slab = slabsEmit ? wall : builder.addMaterial({.baseColor = Color(kRho)});
    for (int k = 0; k < 3; ++k) {
        const float y = -0.6f + 0.5f * static_cast<float>(k),
                    x = -0.6f + 0.3f * static_cast<float>(k);
        addSolidBox(builder, {x, y, -0.5f}, {x + 0.5f, y + 0.08f, 0.5f}, slab);
    }
    return loadBuiltScene(builder, name);
}

// Clusters forced on and a coarse epsilon, so that the cluster links err; the solve's own leaves
// (no splits after it for the shown light).
// Solves the scene so, without a final gather and then with 64 rays per leaf side, and hands
// each converged solution to `check` with the rays.
void solveWithAndWithoutFinalGather(
    const Scene& scene,
    const std::function<void(int, const RadiosityMesh&, const RadiositySolver&)>& check) {
    for (const int rays : {0, 64}) {
        RadiositySettings settings;
        settings.patchEdgeLength = 0.5f;
        settings.clusterMinPatches = 0;
        settings.epsilon = 0.05f;
        settings.finalGatherRays = rays;
        settings.directAtCorners = false;
        settings.indirectAtCorners = 0;
        RadiosityMesh mesh(scene, settings.meshing(scene));
        RadiositySolver solver(scene, mesh, settings);
        solver.solve();
        ASSERT_TRUE(solver.converged());
        check(rays, mesh, solver);
    }
}

TEST(FinalGather, KeepsTheIndirectLightOfAClosedRoom) {
    // The room with slabs (roomWithSlabs), every surface rho: the cluster links' indirect share
    // is not rho. The final gather's correction takes the loss out; what is left is the gather's
    // noise, which the patch means of 64 rays per leaf side keep small.
    const auto scene = roomWithSlabs(false, "radiosity-final-gather");
    solveWithAndWithoutFinalGather(
        *scene, [](int rays, const RadiosityMesh& mesh, const RadiositySolver& solver) {
            const double error = indirectShare(mesh, solver) / kRho - 1.0;
            std::cout << rays << " final gather rays: indirect share / rho - 1 = " << error << "\n";
            if (rays > 0)
                EXPECT_LT(std::abs(error), 0.005);
            else
                EXPECT_GT(std::abs(error), 0.02)
                    << "the links are right here: a test of the correction "
                       "needs a scene where they are not";
        });
}

TEST(FinalGather, GivesEveryElementTheEmittersFirstReflection) {
    // The room with slabs (roomWithSlabs) whose every surface facing into it emits Le = 1, the
    // slabs too: each point of those sides sees emitting sides over its whole hemisphere, so its
    // irradiance is pi Le and its first reflection of the sources rho Le exactly, whatever the
    // geometry. The cluster links carry the emission wrong; the final gather's estimate of it
    // replaces theirs, patch side by patch side.
    const auto scene = roomWithSlabs(true, "radiosity-final-gather-first-reflection");
    solveWithAndWithoutFinalGather(
        *scene, [](int rays, const RadiosityMesh& mesh, const RadiositySolver& solver) {
            // Over the leaves' fronts (the sides facing the room): the area-weighted mean error and
            // the largest on a whole patch (the correction's unit).
            double area = 0.0, sum = 0.0;
            std::map<int, std::pair<double, double>> patches;  // patch: area, area-weighted value
            for (size_t e = 0; e < mesh.elementCount(); ++e) {
                const int element = static_cast<int>(e);
                if (!mesh.isLeaf(element))
                    continue;
                const double a = mesh.area(element), value = solver.elementDirect(element).g;
                area += a;
                sum += a * value;
                patches[mesh.patch(element)].first += a;
                patches[mesh.patch(element)].second += a * value;
            }
            double worst = 0.0, squares = 0.0;
            for (const auto& [patch, values] : patches) {
                const double error = values.second / values.first / kRho - 1.0;
                worst = std::max(worst, std::abs(error));
                squares += error * error;
            }
            const double rms = std::sqrt(squares / static_cast<double>(patches.size()));
            const double meanError = sum / area / kRho - 1.0;
            std::cout << rays << " final gather rays: first reflection / (rho Le) - 1: mean "
                      << meanError << ", over the patches RMS " << rms << " and largest " << worst
                      << "\n";
            if (rays > 0) {
                // What is left is the noise of 64 samples per leaf side, a patch's mean over its
                // leaves: about 1.3 % RMS, 6 % at worst over the room's patches.
                EXPECT_LT(std::abs(meanError), 0.005);
                EXPECT_LT(rms, 0.03);
                EXPECT_LT(worst, 0.1);
            } else {
                EXPECT_GT(worst, 0.1) << "the links are right here: a test of the correction needs "
                                         "a scene where they are not";
            }
        });
}

TEST(FinalGather, RunsByDefaultWhenTheSolverStartsFromClusters) {
    // final_gather = auto: 64 rays per leaf side with clusters, whose transfer the gather
    // corrects (above), none without (radiosity_solver.h, "Final gather", says why).
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.5f)});
    addClosedBox(builder, white, white);
    addCeilingLight(builder, 0.3f, 0.99f, 1.0f);
    const auto scene = loadBuiltScene(builder, "radiosity-final-gather-auto");
    for (const bool clustered : {false, true}) {
        RadiositySettings settings;
        settings.patchEdgeLength = 1.0f;
        settings.minElementArea = 0.05f;
        settings.epsilon = 0.05f;
        settings.clusterMinPatches = clustered ? 0 : 1000;
        RadiosityMesh mesh(*scene, settings.meshing(*scene));
        RadiositySolver solver(*scene, mesh, settings);
        solver.solve();
        std::map<std::string, std::string> stats;
        for (const auto& [key, value] : solver.stats())
            stats[key] = value;
        EXPECT_EQ(stats["clusters"] != "0", clustered);
        EXPECT_EQ(stats["final_gather_rays_per_side"], clustered ? "64" : "0");
        EXPECT_EQ(stats["final_gather_passes"] != "0", clustered);
    }
}

}  // namespace
}  // namespace penumbra::test
