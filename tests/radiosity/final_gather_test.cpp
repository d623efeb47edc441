// The hierarchical radiosity solver's final gather: in a closed room where every surface reflects
// rho, the indirect share of the reflected light must be rho, which the cluster links alone miss
// and the gather's correction restores; and the gather runs by default when the solver starts
// from clusters.
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <string>

namespace penumbra::test {
namespace {

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

TEST(FinalGather, KeepsTheIndirectLightOfAClosedRoom) {
    // The furnace box's walls (emitting, rho = 0.5) with three solid slabs of the same rho inside,
    // clusters forced on and a coarse epsilon, so that the cluster links err: their
    // indirect share is not rho. The final gather's correction takes the loss out; what is left
    // is the gather's noise, which the patch means of 64 rays per leaf side keep small.
    GltfBuilder builder;
    const float rho = 0.5f;
    const int wall = builder.addMaterial(
        {.baseColor = Color(rho), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    const int grey = builder.addMaterial({.baseColor = Color(rho)});
    for (int k = 0; k < 3; ++k) {
        const float y = -0.6f + 0.5f * static_cast<float>(k),
                    x = -0.6f + 0.3f * static_cast<float>(k);
        addSolidBox(builder, {x, y, -0.5f}, {x + 0.5f, y + 0.08f, 0.5f}, grey);
    }
    const auto scene = loadBuiltScene(builder, "radiosity-final-gather");
    for (const int rays : {0, 64}) {
        RadiositySettings settings;
        settings.patchEdgeLength = 0.5f;
        settings.clusterMinPatches = 0;
        settings.epsilon = 0.05f;
        settings.finalGatherRays = rays;
        RadiosityMesh mesh(*scene, settings.meshing(*scene));
        RadiositySolver solver(*scene, mesh, settings);
        solver.solve();
        ASSERT_TRUE(solver.converged());
        const double error = indirectShare(mesh, solver) / rho - 1.0;
        std::cout << rays << " final gather rays: indirect share / rho - 1 = " << error << "\n";
        if (rays > 0)
            EXPECT_LT(std::abs(error), 0.005);
        else
            EXPECT_GT(std::abs(error), 0.02)
                << "the links are right here: a test of the correction "
                   "needs a scene where they are not";
    }
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
