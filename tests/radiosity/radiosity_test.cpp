// The hierarchical radiosity solver against closed forms (the closed furnace box, a point light
// over a floor), against a dense full-matrix solve of the same leaves, and end to end against the
// path tracer.
#include "core/errors.h"
#include "core/gltf_loader.h"
#include "core/image_io.h"
#include "core/scene.h"
#include "radiosity/cluster_tree.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"
#include "tests/support/full_matrix_solve.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace penumbra::test {
namespace {

// --- The closed furnace box ----------------------------------------------------------------------

struct FurnaceResult {
    double maxError = 0.0;   // largest relative error of a leaf's front radiance, any channel
    double meanError = 0.0;  // relative error of the area-weighted mean
    bool allValid = true;    // no NaN, infinity or negative value on any side of any element
    bool converged = false;
    size_t leaves = 0, links = 0;
    std::vector<RadiosityIteration> iterations;
    // The indirect part (paths L D D+) against Le rho^2 / (1 - rho), relative to Le / (1 - rho),
    // per leaf and interpolated at points of the first wall; the direct part (L D) against
    // rho Le, relative to it.
    double maxIndirectError = 0.0, maxInterpolatedIndirectError = 0.0, maxDirectError = 0.0;
};

// Solves a closed enclosure whose surfaces all emit Le = 1 and reflect the same rho, and measures
// every leaf against the solution L = Le / (1 - rho).
FurnaceResult solveFurnaceScene(const Scene& scene, const RadiositySettings& settings) {
    RadiosityMesh mesh(scene, settings.meshing(scene));
    RadiositySolver solver(scene, mesh, settings);
    solver.solve();

    FurnaceResult result;
    // rho as the mesh took it from the material (a Lambertian glTF material: baseColor).
    const double rho = mesh.rho(0).g;
    const double expected = 1.0 / (1.0 - rho);
    // L = Le + rho Le + Le rho^2 / (1 - rho): emission, first reflection of the sources (every
    // element sees the whole closed box, F summing to 1), and the rest.
    const double indirect = rho * rho / (1.0 - rho);
    double weighted = 0.0, area = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        const Color front = solver.elementRadiance(element, true);
        result.allValid = result.allValid && validRadiance(front) &&
                          validRadiance(solver.elementRadiance(element, false));
        if (!mesh.isLeaf(element))
            continue;
        ++result.leaves;
        weighted += mesh.area(element) * front.g;
        area += mesh.area(element);
        const Color direct = solver.elementDirect(element, true);
        const Color rest = solver.elementIndirect(element, true);
        for (int c = 0; c < 3; ++c) {
            result.maxError = std::max(result.maxError, std::abs(front[c] / expected - 1.0));
            result.maxIndirectError =
                std::max(result.maxIndirectError, std::abs(rest[c] - indirect) / expected);
            result.maxDirectError =
                std::max(result.maxDirectError, std::abs(direct[c] / rho - 1.0));
        }
    }
    for (const uint32_t triangle : {0u, 1u}) {
        for (const Vec3 b : {Vec3(1, 0, 0), Vec3(0.5f, 0.5f, 0), Vec3(0.2f, 0.3f, 0.5f)}) {
            const Color rest = solver.indirectRadiance(0, triangle, b);
            result.maxInterpolatedIndirectError = std::max(result.maxInterpolatedIndirectError,
                                                           std::abs(rest.g - indirect) / expected);
        }
    }
    result.meanError = std::abs(weighted / area / expected - 1.0);
    result.converged = solver.converged();
    result.links = solver.linkCount();
    result.iterations = solver.iterations();
    return result;
}

// Every wall emits Le = 1 and reflects rho: the radiosity equation of a closed uniform enclosure
// has the solution L = Le / (1 - rho) everywhere.
FurnaceResult solveFurnace(float rho, const RadiositySettings& settings) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(rho), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    const auto scene = loadBuiltScene(builder, "radiosity-furnace");
    return solveFurnaceScene(*scene, settings);
}

// Three levels of elements below the 48 patches of the box (3072 leaves at most) and a threshold
// fine enough for 1 % at rho = 0.99, where every error in the form factors' row sums is
// amplified about 1 / (1 - rho) = 100 times.
RadiositySettings furnaceSettings() {
    RadiositySettings s;
    s.minElementArea = 0.5f / 64.0f;  // patch area / 4^3
    s.epsilon = 5e-4f;
    return s;
}

class ClosedFurnaceBox : public testing::TestWithParam<float> {};

TEST_P(ClosedFurnaceBox, EveryElementGivesLeOverOneMinusRho) {
    const float rho = GetParam();
    const FurnaceResult r = solveFurnace(rho, furnaceSettings());
    std::cout << "rho " << rho << ": " << r.leaves << " leaves, " << r.links << " links, "
              << r.iterations.size() << " sweeps, max element error " << r.maxError
              << ", error of the mean " << r.meanError << "; largest error of the indirect part "
              << r.maxIndirectError << " (interpolated " << r.maxInterpolatedIndirectError
              << "), of the direct part " << r.maxDirectError << "\n";
    EXPECT_TRUE(r.converged);
    EXPECT_TRUE(r.allValid);
    EXPECT_LT(r.maxError, 0.01);
    // The indirect-only solution, Le rho^2 / (1 - rho), within the same 1 % of L.
    EXPECT_LT(r.maxIndirectError, 0.01);
    EXPECT_LT(r.maxInterpolatedIndirectError, 0.01);
    EXPECT_LT(r.maxDirectError, 0.01);
    // Within a round (one set of links) the iteration is a contraction started below its fixed
    // point: every sweep changes the solution less than the one before; a divergence or a
    // stall would show here.
    for (size_t k = 1; k < r.iterations.size(); ++k) {
        if (r.iterations[k].round == r.iterations[k - 1].round) {
            EXPECT_LE(r.iterations[k].change, r.iterations[k - 1].change) << "sweep " << k;
        }
    }
    EXPECT_LE(r.iterations.back().errorBound, furnaceSettings().convergence);
}

INSTANTIATE_TEST_SUITE_P(Albedo, ClosedFurnaceBox, testing::Values(0.5f, 0.9f, 0.99f));

TEST(ClosedFurnaceBox, DoesNotStopEarlyAtRhoNearOne) {
    // At rho = 0.99 each sweep changes the solution by only about 1 % of the remaining error, so
    // a test on the change alone would stop far from the answer. Cut the sweeps to a quarter of
    // what convergence takes: the solver must say it has not converged, and it is not there.
    const FurnaceResult full = solveFurnace(0.99f, furnaceSettings());
    RadiositySettings cut = furnaceSettings();
    cut.maxIterations = static_cast<int>(full.iterations.size() / 4);
    const FurnaceResult r = solveFurnace(0.99f, cut);
    std::cout << "after " << r.iterations.size() << " of " << full.iterations.size()
              << " sweeps: error of the mean " << r.meanError << ", last change "
              << r.iterations.back().change << ", estimated error "
              << r.iterations.back().errorBound << "\n";
    EXPECT_FALSE(r.converged);
    EXPECT_GT(r.meanError, 0.01);
    // The a posteriori estimate knows it: it is not below the convergence threshold, and it
    // is not below the true error either.
    EXPECT_GT(r.iterations.back().errorBound, cut.convergence);
    EXPECT_GT(r.iterations.back().errorBound, 0.5 * r.meanError);
}

TEST(ClosedFurnaceBox, JacobiAndGaussSeidelAgree) {
    // The two gather orders solve the same system; Gauss-Seidel needs fewer sweeps.
    RadiositySettings jacobi = furnaceSettings();
    jacobi.minElementArea = 0.5f / 16.0f;  // two levels: a quicker variant of the same box
    RadiositySettings gaussSeidel = jacobi;
    jacobi.iteration = RadiositySettings::Iteration::Jacobi;
    const FurnaceResult j = solveFurnace(0.9f, jacobi);
    const FurnaceResult g = solveFurnace(0.9f, gaussSeidel);
    std::cout << "rho 0.9: Jacobi " << j.iterations.size() << " sweeps, max error " << j.maxError
              << "; Gauss-Seidel " << g.iterations.size() << " sweeps, max error " << g.maxError
              << "\n";
    EXPECT_TRUE(j.converged);
    EXPECT_LT(j.maxError, 0.01);
    EXPECT_NEAR(j.meanError, g.meanError, 1e-3);
    EXPECT_LT(g.iterations.size(), j.iterations.size());
}

TEST(ClosedFurnaceBox, CountsCoincidentWallsOnce) {
    // Every wall twice, in the same place: the second box's quads split along the other diagonal
    // (each of its triangles lies over parts of two of the first's), or wound the other way. Seen
    // twice, rho times a receiver's form factors would sum to 2 rho = 1.8 and the gather diverge;
    // counted once (coincident_faces.h), every point inside shows Le / (1 - rho) = 10, the second
    // box's too, whose hidden sides show the first's light. With the final gather too, whose rays
    // meeting a hidden side read the side that replaces it where they meet it (leafSideSeenAt): a
    // ray that read a partly hidden side's own value there put the box 1.2 % low.
    for (const auto& [flipped, finalGatherRays] :
         {std::pair{false, 0}, std::pair{true, 0}, std::pair{false, 64}, std::pair{true, 64}}) {
        const auto scene = doubledFurnaceBox(0.9f, flipped, "radiosity-doubled-furnace");
        RadiositySettings settings;
        settings.minElementArea = 0.5f / 4.0f;  // one level below the patches: quick
        settings.finalGatherRays = finalGatherRays;
        RadiosityMesh mesh(*scene, settings.meshing(*scene));
        RadiositySolver solver(*scene, mesh, settings);
        solver.solve();
        EXPECT_TRUE(solver.converged()) << "flipped " << flipped;
        const double worst =
            worstInsideError(*scene, 10.0, [&](uint32_t m, uint32_t t, Vec3 b, bool front) {
                return solver.radiance(m, t, b, true, front);
            });
        std::string losing;
        for (const auto& [key, value] : solver.stats()) {
            if (key == "coincident_patches")
                losing = value;
        }
        std::cout << (flipped ? "wound the other way" : "split the other way") << ", final gather "
                  << finalGatherRays << " rays: largest error inside " << worst << ", " << losing
                  << " coincident patches\n";
        EXPECT_LT(worst, 0.01) << "flipped " << flipped;
        // Split the other way, the second box's patches lose both sides to the first's; wound
        // the other way, every patch has its back (on the other's front) hidden.
        EXPECT_EQ(losing, std::to_string(flipped ? mesh.patchCount() : mesh.patchCount() / 2));
    }
}

// --- Clusters
// -------------------------------------------------------------------------------------

// The closed furnace box (every wall emits Le = 1 and reflects rho), for tests that choose their
// own patch size.
std::unique_ptr<Scene> furnaceBox(float rho, const std::string& name) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(rho), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    return loadBuiltScene(builder, name);
}

TEST(ClusterTree, PartitionsThePatchesIntoNestedBoundedClusters) {
    const auto scene = furnaceBox(0.5f, "radiosity-cluster-tree");
    RadiositySettings settings;
    settings.patchEdgeLength = 0.25f;
    const RadiosityMesh mesh(*scene, settings.meshing(*scene));
    const ClusterTree tree(mesh);
    ASSERT_FALSE(tree.empty());
    EXPECT_NEAR(tree[0].flatness, 0.0f, 1e-5f);  // the closed box faces every way
    EXPECT_EQ(static_cast<size_t>(tree[0].count), mesh.patchCount());
    std::multiset<int> seen;
    for (const int p : tree.patches(0))
        seen.insert(p);
    ASSERT_EQ(seen.size(), mesh.patchCount());
    EXPECT_EQ(std::set<int>(seen.begin(), seen.end()).size(), mesh.patchCount());
    for (size_t c = 0; c < tree.size(); ++c) {
        const Cluster& cluster = tree[static_cast<int>(c)];
        double area = 0.0;
        for (const int p : tree.patches(static_cast<int>(c))) {
            area += 2.0 * mesh.area(p);
            for (const Vec3& corner : mesh.corners(p))
                EXPECT_LE(glm::distance(corner, cluster.center), cluster.radius * (1.0f + 1e-5f));
        }
        EXPECT_NEAR(cluster.area, area, 1e-9 * area);
        EXPECT_TRUE(cluster.emits);  // every wall emits
        // Flatness: 1 for patches of one wall, below 1 for patches of several.
        const auto patches = tree.patches(static_cast<int>(c));
        const bool oneWall = std::all_of(patches.begin(), patches.end(), [&](int p) {
            return glm::dot(mesh.normal(p), mesh.normal(patches[0])) > 0.999f;
        });
        if (oneWall)
            EXPECT_NEAR(cluster.flatness, 1.0f, 1e-5f);
        else
            EXPECT_LT(cluster.flatness, 1.0f - 1e-3f);
        if (cluster.isLeaf()) {
            EXPECT_LE(cluster.count, ClusterTree::kLeafPatches);
            continue;
        }
        const Cluster& a = tree[cluster.children[0]];
        const Cluster& b = tree[cluster.children[1]];
        EXPECT_EQ(a.first, cluster.first);
        EXPECT_EQ(b.first, a.first + a.count);
        EXPECT_EQ(a.count + b.count, cluster.count);
    }
    // Sampling by area: u on a fine regular grid lands on each patch in proportion to its area
    // (up to one grid step per patch).
    constexpr int kSteps = 100000;
    std::vector<int> hits(mesh.patchCount(), 0);
    for (int k = 0; k < kSteps; ++k) {
        float u = (static_cast<float>(k) + 0.5f) / kSteps;
        const int p = tree.samplePatch(0, u);
        ASSERT_GE(u, 0.0f);
        ASSERT_LT(u, 1.0f);
        ++hits[static_cast<size_t>(p)];
    }
    double total = 0.0;
    for (size_t p = 0; p < mesh.patchCount(); ++p)
        total += mesh.area(static_cast<int>(p));
    for (size_t p = 0; p < mesh.patchCount(); ++p)
        EXPECT_NEAR(hits[p], kSteps * mesh.area(static_cast<int>(p)) / total, 1.0) << p;
}

class ClusteredFurnaceBox : public testing::TestWithParam<float> {};

TEST_P(ClusteredFurnaceBox, EveryElementGivesLeOverOneMinusRho) {
    // The closed furnace box with clusters forced on (clusterMinPatches 0): the links between
    // clusters and elements are reciprocal (A_R K_RS = A_S K_SR) and the push gives each patch the
    // isotropic share, but the isotropic model is only right for surfaces facing every way. The
    // oracle weighs that (clusterKernel: the transfer, plus 3 times it for a flat cluster), so the
    // walls, flat clusters facing each other, are refined to links the model does not falsify.
    // Without those terms the box came out 8 % low at rho = 0.5 (19 % with a uniform push, which
    // lights the outward backs of the walls as much as their fronts); with the flat term alone,
    // 1.3 % low at rho = 0.9.
    const float rho = GetParam();
    const auto scene = furnaceBox(rho, "radiosity-clustered-furnace");
    RadiositySettings settings = furnaceSettings();
    settings.patchEdgeLength = 0.5f;
    settings.clusterMinPatches = 0;
    const FurnaceResult r = solveFurnaceScene(*scene, settings);
    std::cout << "clustered, rho " << rho << ": " << r.leaves << " leaves, " << r.links
              << " links, " << r.iterations.size() << " sweeps, max element error " << r.maxError
              << ", error of the mean " << r.meanError << ", of the indirect part "
              << r.maxIndirectError << "\n";
    EXPECT_TRUE(r.converged);
    EXPECT_TRUE(r.allValid);
    EXPECT_LT(r.maxError, 0.01);
    // The direct part goes through the cluster links too (computeDirectPart pushes it down the
    // cluster tree like the solution).
    EXPECT_LT(r.maxIndirectError, 0.01);
}

INSTANTIATE_TEST_SUITE_P(Albedo, ClusteredFurnaceBox, testing::Values(0.5f, 0.9f));

TEST(ClusteredFurnaceBox, SolidsInsideGetTheRoomsRadiance) {
    // The furnace box (walls emitting Le = 1, rho = 0.5) with five solid slabs inside, each a
    // closed mesh of a perfect reflector (rho = 1, no emission), with clusters forced on: in a
    // closed enclosure where every surface is at L = Le / (1 - rho), a perfect reflector that
    // emits nothing is at L too, so every outer side of every slab must show 2. The slabs' inner
    // sides face a sealed interior (sealed_interiors.h). Before they were known as such, the
    // visible fraction of a cluster of slabs counted the rays from the faces turned away from a
    // source, which leave through the slab itself, as occluded (the isotropic model already
    // gives those faces nothing): with that visible fraction the slabs' outer sides came out up to
    // 12 % low (1.0 % on their mean); now within 3.4 % (0.5 % on the mean). The rest is the
    // cluster model's, which the oracle bounds (clusterKernel).
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(0.5f), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    const int mirrorWhite = builder.addMaterial({.baseColor = Color(1.0f)});
    for (int k = 0; k < 5; ++k) {
        const float y = -0.8f + 0.35f * static_cast<float>(k),
                    x = -0.6f + 0.2f * static_cast<float>(k);
        addSolidBox(builder, {x, y, -0.5f}, {x + 0.5f, y + 0.08f, 0.5f}, mirrorWhite);
    }
    const auto scene = loadBuiltScene(builder, "radiosity-furnace-solids");
    RadiositySettings settings = furnaceSettings();
    settings.patchEdgeLength = 0.5f;
    settings.clusterMinPatches = 0;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    ASSERT_TRUE(solver.converged());
    constexpr uint32_t kFirstSlab = 6;  // after the six walls of addClosedBox
    double worst = 0.0, weighted = 0.0, area = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element) || mesh.sceneMesh(element) < kFirstSlab)
            continue;
        const double L = solver.elementRadiance(element, true).g;  // the outer side
        worst = std::max(worst, std::abs(L / 2.0 - 1.0));
        weighted += mesh.area(element) * L;
        area += mesh.area(element);
    }
    const double meanError = std::abs(weighted / area / 2.0 - 1.0);
    std::cout << "slabs' outer sides: error of the mean " << meanError << ", largest " << worst
              << "\n";
    EXPECT_LT(meanError, 0.01);
    EXPECT_LT(worst, 0.05);
}

TEST(ClusteredRoom, RefinementRoundsEnd) {
    // A link the oracle takes out for refinement must come back finer, or the rounds never end:
    // the receiver-relative criterion (exceedsThreshold) picked element links from clusters on a
    // dark floor, and the cluster pairs' own test, the absolute threshold alone, linked them
    // again unchanged, every round up to max_refinements (on the modern hall, 84 000 links per
    // round). Here a dark floor under slabs that start as clusters, and a lamp.
    GltfBuilder builder;
    const int walls = builder.addMaterial({.baseColor = Color(0.7f)});
    const int floor = builder.addMaterial({.baseColor = Color(0.02f)});
    addClosedBox(builder, walls, floor);
    addCeilingLight(builder, 0.2f, 0.99f, 10.0f);
    const int slab = builder.addMaterial({.baseColor = Color(0.8f)});
    for (int k = 0; k < 4; ++k) {
        const float x = -0.8f + 0.4f * static_cast<float>(k);
        addSolidBox(builder, {x, -0.9f, -0.5f},
                    {x + 0.2f, -0.3f + 0.1f * static_cast<float>(k), 0.5f}, slab);
    }
    const auto scene = loadBuiltScene(builder, "radiosity-clustered-room");
    RadiositySettings settings;
    settings.patchEdgeLength = 0.5f;
    settings.minElementArea = 1.0f / 256.0f;
    settings.clusterMinPatches = 0;
    settings.maxRefinements = 16;  // the churn would run them all; the oracle ends in about 7
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    int rounds = -1;
    for (const auto& [key, value] : solver.stats()) {
        if (key == "refinement_rounds")
            rounds = std::stoi(value);
    }
    std::cout << rounds << " refinement rounds of at most " << settings.maxRefinements << ", "
              << solver.linkCount() << " links\n";
    EXPECT_LT(rounds, settings.maxRefinements);
}

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

// --- Against a dense solve
// ------------------------------------------------------------------------

TEST(HierarchicalRadiosity, AgreesWithFullMatrixSolve) {
    // A room with a ceiling light, and a red block casting shadows: the hierarchical solution
    // against Gauss-Seidel on the full matrix over the same leaves (every pair of leaf sides linked
    // directly, with the same form factors and the same visibility sampling).
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.7f)});
    addClosedBox(builder, white, white);
    const int red = builder.addMaterial({.baseColor = Color(0.7f, 0.2f, 0.1f)});
    addFloorBlock(builder, red);  // 0.8 x 0.6 x 0.8, faces outward, no bottom
    addCeilingLight(builder, 0.3f, 0.99f, 20.0f);
    const auto scene = loadBuiltScene(builder, "radiosity-full-matrix");

    RadiositySettings settings;
    settings.minElementArea = 0.01f;  // about 1000 leaves: the dense solve stays fast
    settings.epsilon = 1e-3f;
    // The links' solution against the dense solve of the same kernel: the final gather replaces
    // the links' transfer by the rays' (with it, the means agree within 0.2 %, one patch side
    // within 5 %).
    settings.finalGatherRays = 0;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    ASSERT_TRUE(solver.converged());
    const std::vector<Color> full = solveFullMatrix(solver, mesh);

    // The reflected light (emission is the same in both by construction), in luminance, per leaf
    // side and summed per patch side.
    struct Sums {
        double hierarchical = 0.0, full = 0.0, area = 0.0;
    };
    Sums total;
    std::vector<Sums> patches(2 * mesh.patchCount());
    std::vector<std::pair<double, double>> leaves;  // (hierarchical, full) per leaf side
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element))
            continue;
        for (const bool front : {true, false}) {
            const Color Le = front ? mesh.Le(element) : Color(0.0f);
            const Color h = solver.elementRadiance(element, front) - Le;
            const Color f = full[2 * e + (front ? 0 : 1)] - Le;
            ASSERT_TRUE(validRadiance(h));
            ASSERT_TRUE(validRadiance(f));
            const double area = mesh.area(element);
            for (Sums* s : {&total, &patches[2 * mesh.patch(element) + (front ? 0 : 1)]}) {
                s->hierarchical += area * luminance(h);
                s->full += area * luminance(f);
                s->area += area;
            }
            leaves.emplace_back(luminance(h), luminance(f));
        }
    }
    const double mean = total.full / total.area;
    double worstPatch = 0.0, worstLeaf = 0.0, meanLeaf = 0.0;
    for (const Sums& p : patches) {
        // Patch sides that receive light at all (not the backs of walls and block faces).
        if (p.full > 0.1 * mean * p.area)
            worstPatch = std::max(worstPatch, std::abs(p.hierarchical / p.full - 1.0));
    }
    for (const auto& [h, f] : leaves) {
        worstLeaf = std::max(worstLeaf, std::abs(h - f) / mean);
        meanLeaf += std::abs(h - f) / mean / static_cast<double>(leaves.size());
    }
    std::cout << leaves.size() / 2 << " leaves, " << solver.linkCount()
              << " links; reflected radiance: mean " << total.hierarchical / total.area
              << " (full matrix " << mean << "); largest relative difference of a lit patch side "
              << worstPatch << "; difference of a leaf side, in units of the mean: average "
              << meanLeaf << ", largest " << worstLeaf << "\n";
    EXPECT_NEAR(total.hierarchical / total.full, 1.0, 0.01);
    EXPECT_LT(worstPatch, 0.01);
    EXPECT_LT(meanLeaf, 0.01);
    // A single leaf side differs more where a coarse link in a penumbra estimates its visible
    // fraction with 16 rays for the whole pair, the dense solve with 16 per leaf pair; and most
    // (measured up to 0.095, under 0.06 elsewhere) at the ceiling leaves straddling the foot of
    // the lamp, which hangs 1 cm under it (one-sided: the ceiling over it is covered, isCovered in
    // element_sampling.h): their value is that of their exposed strip beside the lamp, which the
    // hierarchical solution lights through links at their parents, shared one level down by the
    // children's own visible fractions (setReceiverWeights), the dense solve through each leaf's
    // own links. Hence 0.1.
    EXPECT_LT(worstLeaf, 0.1);
}

// --- Covered surfaces ---------------------------------------------------------------------------

// The closed furnace box (every surface emits Le = 1 and reflects rho = 0.5 from its front, one-
// sided) with a one-sided block standing on its floor (addFloorBlock: five faces facing outward,
// no bottom). Every surface that sees the enclosure has L = Le / (1 - rho) = 2; the floor under the
// block is covered (isCovered, element_sampling.h): seen by nobody, lit by nothing but the block's
// dark inside. The floor leaves straddling the block's foot must show the light of their exposed
// part, and the covered ones must not darken their exposed neighbours' vertices: the radiance the
// renderer shows (interpolated) at floor points 1 mm to 3 cm off each of the block's faces must be
// 2. With the furnace tests' fine settings (9 cm leaves on the floor) it is within 2.2 % (lowest
// 1.956); without the exposed fractions it was down to 1.56 (22 %), and with them but the block
// faces' form factors over the whole straddling leaf (exposedFormFactor) to 1.785. The 3 % bound
// is the measured 2.2 % plus margin; what remains is the contact line's own error (the furnace
// corners' 1 %).
TEST(HierarchicalRadiosity, CoveredFloorDoesNotDarkenTheFloorAroundABlock) {
    GltfBuilder builder;
    const int material = builder.addMaterial(
        {.baseColor = Color(0.5f), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, material, material);
    addFloorBlock(builder, material);  // x in [-0.6, 0.2], z in [-0.2, 0.6]
    const auto scene = loadBuiltScene(builder, "radiosity-covered-floor");
    const RadiositySettings settings = furnaceSettings();
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    double worst = 0.0, lowest = 2.0;
    for (const float d : {1e-3f, 1e-2f, 3e-2f}) {
        for (int k = 0; k <= 16; ++k) {
            const float x = -0.6f + 0.05f * k, z = -0.2f + 0.05f * k;
            for (const Vec2 p :
                 {Vec2(x, -0.2f - d), Vec2(x, 0.6f + d), Vec2(-0.6f - d, z), Vec2(0.2f + d, z)}) {
                // The floor point under p, found as a ray straight down finds it.
                const auto hit = scene->intersect(Ray{Vec3(p.x, -0.9f, p.y), Vec3(0, -1, 0)});
                ASSERT_TRUE(hit);
                const Color L = solver.radiance(hit->mesh, hit->triangle, hit->barycentric, true);
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, std::abs(L[c] / 2.0 - 1.0));
                    lowest = std::min(lowest, static_cast<double>(L[c]));
                }
            }
        }
    }
    std::cout << "floor around the block: largest relative error " << worst << ", lowest radiance "
              << lowest << " (exact 2)\n";
    EXPECT_LT(worst, 0.03);
}

// --- Punctual lights
// ------------------------------------------------------------------------------

TEST(HierarchicalRadiosity, PointLightShootsIntoTheFloor) {
    // A point light of I candela at height h over a 4 x 4 m floor, nothing else: the floor's
    // reflected radiance integrates to rho I Omega / pi, Omega the solid angle of the floor seen
    // from the light, and directly below the light L = rho I / (pi h^2).
    const PointLightOverFloor setup;  // I = 10 cd at 1 m over 4 x 4 m, rho 0.5
    GltfBuilder builder;
    setup.build(builder);
    const auto scene = loadBuiltScene(builder, "radiosity-point-light");
    RadiositySettings settings;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();

    double power = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (mesh.isLeaf(element)) {
            power += mesh.area(element) * solver.elementRadiance(element, true).g;
            EXPECT_EQ(solver.elementRadiance(element, false), Color(0.0f));
            // One plane and a point light: all of its light is the light's first reflection.
            EXPECT_EQ(solver.elementIndirect(element, true), Color(0.0f));
            EXPECT_EQ(solver.elementDirect(element, true), solver.elementRadiance(element, true));
        }
    }
    const double expectedPower = setup.reflectedPower();
    EXPECT_NEAR(power, expectedPower, 0.01 * expectedPower);
    const double below = setup.rho * setup.intensity / (kPi * setup.height * setup.height);
    const Color centre = solver.radiance(0, 0, Vec3(0.5f, 0.0f, 0.5f), true);
    std::cout << "floor: " << mesh.leafCount() << " leaves; reflected power " << power << " (exact "
              << expectedPower << "), below the light " << centre.g << " (exact " << below << ")\n";
    // The interpolated value under the peak of the cos^3 falloff is an average over the
    // elements around it, so slightly low: 3 %.
    EXPECT_NEAR(centre.g, below, 0.03 * below);
}

// --- The indirect-only solution ------------------------------------------------------------------

TEST(HierarchicalRadiosity, AllMinusIndirectIsTheDirectLightOfTheSources) {
    // A closed box whose floor alone emits: the ceiling's direct light, rho Le F(x -> floor), is
    // in closed form (EmittingFloorBox). What the solution holds beyond its indirect part,
    // All - Indirect, must be that light: per ceiling leaf (against F averaged over the leaf by
    // the seven-point rule of degree 3) and at points of the ceiling (the Gouraud-interpolated
    // values against the point value). Over the whole box, the direct light reflected is rho
    // times the floor's emitted flux, sum_i A_i direct_i = rho Le A_floor (the floor's form factors
    // to the rest of the closed box sum to 1), and the floor, which sees none of itself, has none.
    const EmittingFloorBox box;
    const auto scene = box.load("radiosity-emitting-floor");
    RadiositySettings settings;
    settings.minElementArea = 0.5f / 64.0f;
    settings.epsilon = 1e-3f;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    ASSERT_TRUE(solver.converged());

    double worstLeaf = 0.0, directFlux = 0.0, floorDirect = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element))
            continue;
        const Color all = solver.elementRadiance(element, true) - mesh.Le(element);
        const Color direct = all - solver.elementIndirect(element, true);
        directFlux += mesh.area(element) * direct.g;
        if (mesh.centroid(element).y < -0.99f)
            floorDirect = std::max(floorDirect, static_cast<double>(maxComponent(direct)));
        if (mesh.centroid(element).y < 0.99f)
            continue;
        const auto c = mesh.corners(element);
        const auto at = [&](const Vec3& p) { return box.ceilingDirect(p.x, p.z); };
        const double expected =
            (at(c[0]) + at(c[1]) + at(c[2])) / 20.0 +
            (at(0.5f * (c[0] + c[1])) + at(0.5f * (c[1] + c[2])) + at(0.5f * (c[2] + c[0]))) *
                (2.0 / 15.0) +
            at(mesh.centroid(element)) * (9.0 / 20.0);
        worstLeaf = std::max(worstLeaf, std::abs(direct.g / expected - 1.0));
    }
    // All - Indirect, interpolated, at points of the ceiling.
    const double worstPoint = box.worstCeilingPoint(*scene, [&](uint32_t m, uint32_t t, Vec3 b) {
        return solver.radiance(m, t, b, false) - solver.indirectRadiance(m, t, b);
    });
    const double expectedFlux = box.rho * box.Le * 4.0 * box.h * box.h;
    std::cout << mesh.leafCount() << " leaves; direct part on the ceiling: largest relative error "
              << worstLeaf << " per leaf, " << worstPoint << " interpolated; direct flux / pi "
              << directFlux << " (exact " << expectedFlux << "); on the floor at most "
              << floorDirect << "\n";
    EXPECT_LT(worstLeaf, 0.01);
    EXPECT_LT(worstPoint, 0.02);
    EXPECT_NEAR(directFlux, expectedFlux, 0.01 * expectedFlux);
    EXPECT_LT(floorDirect, 1e-6);
}

// The area of the floor leaf (y = -1, facing up) whose projection holds the point (x, z).
float floorLeafArea(const RadiosityMesh& mesh, float x, float z) {
    const auto side = [](Vec2 p, Vec2 a, Vec2 b) {
        return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    };
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element) || mesh.normal(element).y < 0.9f ||
            mesh.centroid(element).y > -0.99f)
            continue;
        const auto c = mesh.corners(element);
        const Vec2 p(x, z), a(c[0].x, c[0].z), b(c[1].x, c[1].z), d(c[2].x, c[2].z);
        const float s0 = side(p, a, b), s1 = side(p, b, d), s2 = side(p, d, a);
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0))
            return mesh.area(element);
    }
    return 0.0f;
}

TEST(HierarchicalRadiosity, SubdivisionRefinesAHardShadowBoundary) {
    // A small bright ceiling light (0.1 m square) over the block of AgreesWithFullMatrixSolve: the
    // block's top edge at x = -0.6 casts a hard shadow boundary on the floor at
    // x = -0.6 * 1.99 / 1.39 = -0.859 (from the light's centre at y = 0.99). The oracle is made
    // coarse (epsilon 0.5, no refinement rounds: every floor leaf stays a 0.5 m² patch), so that
    // what refines the floor is subdivision alone. With subdivision_threshold 0.2 the leaf on the
    // boundary must end up finer than without, and finer than the leaf at the mirror point
    // x = +0.859, lit without occlusion, where only the smooth falloff of the light varies
    // (measured: 0.5 m² -> 0.002 m², the smallest element, on the boundary; 0.008 m² in the light).
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.7f)});
    addClosedBox(builder, white, white);
    addFloorBlock(builder, white);
    addCeilingLight(builder, 0.05f, 0.99f, 500.0f);
    const auto scene = loadBuiltScene(builder, "radiosity-subdivision");
    const auto solveWith = [&](float threshold, float& boundary, float& lit) {
        RadiositySettings settings;
        settings.epsilon = 0.5f;  // a coarse oracle, to leave the boundary to subdivision
        settings.subdivisionThreshold = threshold;
        settings.maxRefinements = 0;
        RadiosityMesh mesh(*scene, settings.meshing(*scene));
        RadiositySolver solver(*scene, mesh, settings);
        solver.solve();
        EXPECT_TRUE(solver.converged());
        boundary = floorLeafArea(mesh, -0.859f, 0.2f);
        lit = floorLeafArea(mesh, 0.859f, 0.2f);
        return mesh.leafCount();
    };
    float offBoundary = 0, offLit = 0, onBoundary = 0, onLit = 0;
    const size_t offLeaves = solveWith(0.0f, offBoundary, offLit);
    const size_t onLeaves = solveWith(0.2f, onBoundary, onLit);
    std::cout << "leaves " << offLeaves << " -> " << onLeaves << "; leaf area on the boundary "
              << offBoundary << " -> " << onBoundary << ", in the light " << offLit << " -> "
              << onLit << "\n";
    ASSERT_GT(onBoundary, 0.0f);
    ASSERT_GT(onLit, 0.0f);
    EXPECT_GT(onLeaves, offLeaves);
    EXPECT_LT(onBoundary, offBoundary);
    EXPECT_LT(onBoundary, onLit);
}

TEST(HierarchicalRadiosity, StatsReportPeakMemoryPerStage) {
    // getrusage's ru_maxrss after each stage: a running maximum, so it never falls from one stage
    // to the next, and the process holds at least the solver's own estimate of its arrays.
    const auto scene = furnaceBox(0.5f, "radiosity-stats");
    RadiositySettings settings;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    std::map<std::string, double> stats;
    for (const auto& [key, value] : solver.stats()) {
        if (key != "converged")  // "yes" or "no"; every other figure is a number
            stats[key] = std::stod(value);
    }
    const std::vector<std::string> stages = {"direct", "linking", "refine", "solve"};
    double previous = 0.0;
    for (const std::string& stage : stages) {
        const std::string key = "peak_memory_mib_" + stage;
        ASSERT_TRUE(stats.count(key)) << key;
        EXPECT_GE(stats[key], previous) << key;
        previous = stats[key];
    }
    EXPECT_GE(stats["peak_memory_mib_solve"], stats["memory_mib"]);
    EXPECT_EQ(stats["clusters"], 0.0);  // 48 patches: under clusterMinPatches
}

TEST(HierarchicalRadiosity, ReportsItsStagesToTheProgressSink) {
    // A closed room with a ceiling light and a point light: every stage is reported, in order,
    // each ended with its figures; the stages of known length are advanced by exactly their
    // total (the bar reaches 100 %), and the gathers, which converge, reach theirs too.
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.6f)});
    addClosedBox(builder, white, white);
    addCeilingLight(builder, 0.3f, 0.99f, 20.0f);
    builder.addLight({.type = "point", .intensity = 1.0f, .position = {0.5f, 0.5f, 0.0f}});
    const auto scene = loadBuiltScene(builder, "radiosity-progress");
    RadiositySettings settings;
    settings.minElementArea = 0.5f / 16.0f;
    settings.finalGatherRays = 16;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    RecordedProgress progress;
    solver.solve(&progress);
    ASSERT_TRUE(solver.converged());

    std::vector<std::string> expected = {"direct light of the punctual lights",
                                         "linking: refinement oracle",
                                         "linking: form factors and visibility", "gather"};
    ASSERT_GE(progress.stages.size(), expected.size() + 2);
    for (size_t i = 0; i < expected.size(); ++i)
        EXPECT_EQ(progress.stages[i].name, expected[i]);
    // Then the final gather's passes, two stages each (its rays, then the sweeps).
    int passes = -1;
    for (const auto& [key, value] : solver.stats()) {
        if (key == "final_gather_passes")
            passes = std::stoi(value);
    }
    ASSERT_GE(passes, 1);
    const size_t last = progress.stages.size() - 1 - 2 * static_cast<size_t>(passes);
    EXPECT_EQ(progress.stages[last - 1].name, "gather to convergence");
    EXPECT_EQ(progress.stages[last].name, "push-pull of the direct part, vertex values");
    for (int pass = 1; pass <= passes; ++pass) {
        const std::string name = "final gather " + std::to_string(pass);
        EXPECT_EQ(progress.stages[last + 2 * pass - 1].name, name + ": rays");
        EXPECT_EQ(progress.stages[last + 2 * pass].name, name + ": gather");
    }
    int gathers = 0;
    for (const RecordedProgress::Stage& stage : progress.stages) {
        std::cout << stage.name << ": " << stage.done << " of " << stage.total << ", "
                  << stage.summary << "\n";
        EXPECT_TRUE(stage.ended) << stage.name;
        EXPECT_FALSE(stage.summary.empty()) << stage.name;
        if (stage.total > 0) {
            EXPECT_EQ(stage.done, stage.total) << stage.name;
        }
        gathers += stage.name.rfind("gather", 0) == 0;
    }
    // A gather after the first links, one per refinement round, and the last.
    int rounds = -1;
    for (const auto& [key, value] : solver.stats()) {
        if (key == "refinement_rounds")
            rounds = std::stoi(value);
    }
    EXPECT_EQ(gathers, 2 + rounds);
    // The oracle's stages count the pairs they examine; the direct light the first leaves, the
    // patches.
    EXPECT_GT(progress.find("linking: refinement oracle")->done, 0u);
    EXPECT_EQ(progress.find("direct light")->total, mesh.patchCount());
}

TEST(ConsoleSolveProgress, PrintsALinePerStageInALogAndNothingWhenQuiet) {
    // Not a terminal (a temporary file): one line per stage, its name, figures and time; with
    // quiet, nothing at all.
    for (const bool quiet : {false, true}) {
        std::FILE* log = std::tmpfile();
        ASSERT_NE(log, nullptr);
        {
            ConsoleSolveProgress progress("radiosity", quiet, log);
            progress.beginStage("linking", 100);
            progress.advance(60);
            progress.advance(40);
            progress.endStage("12 links");
            progress.beginStage("oracle", 0);
            progress.advance(5);
            progress.beginStage("gather", 1000);  // ends "oracle" without figures
        }                                         // the destructor ends "gather"
        std::rewind(log);
        std::string text;
        for (int c = std::fgetc(log); c != EOF; c = std::fgetc(log))
            text.push_back(static_cast<char>(c));
        std::fclose(log);
        if (quiet) {
            EXPECT_EQ(text, "");
            continue;
        }
        std::vector<std::string> lines;
        for (size_t start = 0, end; (end = text.find('\n', start)) != std::string::npos;
             start = end + 1)
            lines.push_back(text.substr(start, end - start));
        ASSERT_EQ(lines.size(), 3u) << text;
        EXPECT_EQ(lines[0].rfind("radiosity: linking: 12 links, ", 0), 0u) << lines[0];
        EXPECT_EQ(lines[1].rfind("radiosity: oracle: ", 0), 0u) << lines[1];
        EXPECT_EQ(lines[2].rfind("radiosity: gather: ", 0), 0u) << lines[2];
        for (const std::string& line : lines)
            EXPECT_EQ(line.substr(line.size() - 2), " s") << line;
    }
}

TEST(HierarchicalRadiosity, RefusesBadSettings) {
    RadiositySettings s;
    s.epsilon = 0.0f;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.solver = "progressive";
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.visibilitySamples = 0;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.clusterMinPatches = -1;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.subdivisionThreshold = -0.1f;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
}

// --- End to end, against the path tracer
// ----------------------------------------------------------

Image render(const TempDir& dir, const std::string& name, const std::string& options) {
    const std::string out = dir.file(name + ".exr");
    const CliResult result =
        runPenumbra("render " + dir.file("scene.gltf") + " -o " + out + " --quiet " + options);
    EXPECT_EQ(result.status, 0) << result.output;
    return readImage(out);
}

TEST(RadiosityPipeline, FloorAgreesWithReferencePathTracer) {
    // A closed Lambertian room lit by a square ceiling light; an orthographic camera below the
    // light looks straight down and sees only the floor. Radiosity and the path tracer solve the
    // same equation here (every surface Lambertian), so the floor's mean must agree.
    GltfBuilder scene;
    const int walls = scene.addMaterial({.baseColor = Color(0.6f)});
    const int floor = scene.addMaterial({.baseColor = Color(0.5f, 0.4f, 0.3f)});
    addClosedBox(scene, walls, floor);
    addCeilingLight(scene, 0.25f, 0.99f, 20.0f);
    // Looking down (-Y): rotation of -90 degrees about +X.
    scene.setOrthographicCamera({0, 0.9f, 0}, {-std::sqrt(0.5f), 0.0f, 0.0f, std::sqrt(0.5f)},
                                0.95f, 0.95f);
    TempDir dir("radiosity-pipeline");
    scene.write(dir.file("scene.gltf"));
    const Image radiosity = render(dir, "radiosity",
                                   "--pipeline radiosity --width 48 "
                                   "--height 48 --spp 4");
    const Image reference = render(dir, "reference",
                                   "--pipeline reference --width 48 "
                                   "--height 48 --spp 256");
    const double r = luminanceMean(radiosity), p = luminanceMean(reference);
    std::cout << "floor mean: radiosity " << r << ", path tracer " << p << " (ratio " << r / p
              << ")\n";
    // The path tracer's mean over 590k paths has a relative standard error near 0.2 %; 2 % is
    // the bound.
    EXPECT_NEAR(r / p, 1.0, 0.02);
}

}  // namespace
}  // namespace penumbra::test
