// The hierarchical radiosity solver in the closed furnace box, whose every surface emits Le and
// reflects rho, against the closed form L = Le / (1 - rho) (and its direct and indirect parts):
// at several albedos, with the sweeps cut short, with either gather order, with every wall doubled,
// with clusters forced on (and perfect reflectors inside), and around a block whose foot covers the
// floor.
#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <utility>
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
    return solveFurnaceScene(*furnaceBox(rho, "radiosity-furnace"), settings);
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

// --- With clusters -------------------------------------------------------------------------------

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

// --- Covered surfaces ---------------------------------------------------------------------------

// The closed furnace box (every surface emits Le = 1 and reflects rho = 0.5 from its front, one-
// sided) with a one-sided block standing on its floor (addFloorBlock: five faces facing outward,
// no bottom). Every surface that sees the enclosure has L = Le / (1 - rho) = 2; the floor under the
// block is covered (isCovered, element_sampling.h): seen by nobody, lit by nothing but the block's
// dark inside. The floor leaves straddling the block's foot must show the light of their exposed
// part, and the covered ones must not darken their exposed neighbours' vertices: the radiance the
// renderer shows at floor points 1 mm to 3 cm off each of the block's faces, as the radiosity
// view shows it at the defaults (the direct light and the indirect light at the leaves' corners),
// must be 2. With the furnace tests' fine settings (9 cm leaves on the floor) it is within 0.4 %
// (2026-12-04). The element means alone gave 2.2 %; without the exposed fractions 22 %. The direct
// light at the corners with one visible fraction per light (a wall: four rays, all behind the
// block where 63 % of it showed) gave 7.4 %; the indirect corners with a covered corner counting
// nowhere (its leaf's mean, 16 % low, in its place) 3.1 %. The 3 % bound is what the element means
// reached plus margin; what remains is the contact line's own error (the furnace corners' 1 %).
// The furnace box with the block, solved with `settings`; the radiance shown at floor points
// 1 mm to 3 cm off each of the block's faces: the largest relative error against 2.
struct CoveredFloor {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<RadiosityMesh> mesh;
    std::unique_ptr<RadiositySolver> solver;

    explicit CoveredFloor(const RadiositySettings& settings, const std::string& name) {
        GltfBuilder builder;
        const int material = builder.addMaterial(
            {.baseColor = Color(0.5f), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
        addClosedBox(builder, material, material);
        addFloorBlock(builder, material);  // x in [-0.6, 0.2], z in [-0.2, 0.6]
        scene = loadBuiltScene(builder, name);
        mesh = std::make_unique<RadiosityMesh>(*scene, settings.meshing(*scene));
        solver = std::make_unique<RadiositySolver>(*scene, *mesh, settings);
        solver->solve();
        solver->showIndirectAtCorners();
    }
    static bool underBlock(const Vec3& p) {
        return p.x > -0.6f && p.x < 0.2f && p.z > -0.2f && p.z < 0.6f;
    }
    double worstAroundTheBlock() const {
        double worst = 0.0, lowest = 2.0;
        for (const float d : {1e-3f, 1e-2f, 3e-2f}) {
            for (int k = 0; k <= 16; ++k) {
                const float x = -0.6f + 0.05f * k, z = -0.2f + 0.05f * k;
                for (const Vec2 p : {Vec2(x, -0.2f - d), Vec2(x, 0.6f + d), Vec2(-0.6f - d, z),
                                     Vec2(0.2f + d, z)}) {
                    // The floor point under p, found as a ray straight down finds it.
                    const auto hit = scene->intersect(Ray{Vec3(p.x, -0.9f, p.y), Vec3(0, -1, 0)});
                    EXPECT_TRUE(hit);
                    if (!hit)
                        continue;
                    const Color L =
                        solver->radiance(hit->mesh, hit->triangle, hit->barycentric, true);
                    for (int c = 0; c < 3; ++c) {
                        worst = std::max(worst, std::abs(L[c] / 2.0 - 1.0));
                        lowest = std::min(lowest, static_cast<double>(L[c]));
                    }
                }
            }
        }
        std::cout << "floor around the block: largest relative error " << worst
                  << ", lowest radiance " << lowest << " (exact 2)\n";
        return worst;
    }
};

// The closed furnace box (every surface emits Le = 1 and reflects rho = 0.5 from its front, one-
// sided) with a one-sided block standing on its floor (addFloorBlock: five faces facing outward,
// no bottom). Every surface that sees the enclosure has L = Le / (1 - rho) = 2; the floor under the
// block is covered (isCovered, element_sampling.h): seen by nobody, lit by nothing but the block's
// dark inside. The floor leaves straddling the block's foot must show the light of their exposed
// part, and the covered ones must not darken their exposed neighbours' vertices: the radiance the
// renderer shows at floor points 1 mm to 3 cm off each of the block's faces, as the radiosity
// view shows it at the defaults (the direct light and the indirect light at the leaves' corners),
// must be 2. With the furnace tests' fine settings (9 cm leaves on the floor) it is within 0.4 %
// (2026-12-04). The element means alone gave 2.2 %; without the exposed fractions 22 %. The direct
// light at the corners with one visible fraction per light (a wall: four rays, all behind the
// block where 63 % of it showed) gave 7.4 %; the indirect corners with a covered corner counting
// nowhere (its leaf's mean, 16 % low, in its place) 3.1 %. The 3 % bound is what the element means
// reached plus margin; what remains is the contact line's own error (the furnace corners' 1 %).
TEST(HierarchicalRadiosity, CoveredFloorDoesNotDarkenTheFloorAroundABlock) {
    const CoveredFloor floor(furnaceSettings(), "radiosity-covered-floor");
    const RadiosityMesh& mesh = *floor.mesh;
    // Every floor leaf that lies a quarter to three quarters under the block (counted on a grid of
    // its points) is partly covered: each element samples its own cover (element_exposure.h).
    // When a child took its parent's "wholly exposed" on trust, one of the 34 (61 % under the
    // block) was taken as wholly exposed (2026-12-04).
    int astride = 0;
    for (const int e : mesh.leafElements()) {
        if (mesh.normal(e).y < 0.99f || mesh.centroid(e).y > -0.99f)
            continue;  // the floor's leaves only
        const std::array<Vec3, 3> c = mesh.corners(e);
        constexpr int kGrid = 32;
        int under = 0, points = 0;
        for (int a = 0; a < kGrid; ++a) {
            for (int b = 0; a + b < kGrid; ++b, ++points) {
                const float u = (a + 1.0f / 3.0f) / kGrid, v = (b + 1.0f / 3.0f) / kGrid;
                under +=
                    CoveredFloor::underBlock(c[0] + u * (c[1] - c[0]) + v * (c[2] - c[0])) ? 1 : 0;
            }
        }
        const double covered = double(under) / points;
        if (covered < 0.25 || covered > 0.75)
            continue;
        ++astride;
        const float exposed = floor.solver->exposedFraction(e, true);
        EXPECT_TRUE(exposed > 0.0f && exposed < 1.0f)
            << "leaf " << e << ", " << covered << " under the block, exposed fraction " << exposed;
    }
    std::cout << astride << " floor leaves astride the block's edges\n";
    EXPECT_GT(astride, 0);
    EXPECT_LT(floor.worstAroundTheBlock(), 0.03);
}

// The same with the floor cut along the block's foot (contact_lines): no leaf straddles it, and
// the pieces under the block are whole patches that nobody sees. Their stand-in values must
// neither anchor the corners on their edges nor count in the vertex values: before both were
// kept out, the floor showed 1.42 at 1 mm from the block (29 % low), 1.2 with the element means.
TEST(HierarchicalRadiosity, CoveredPiecesCutAlongTheFootDoNotDarkenTheFloor) {
    RadiositySettings settings = furnaceSettings();
    settings.contactLines = true;
    const CoveredFloor floor(settings, "radiosity-covered-floor-cut");
    EXPECT_GT(floor.mesh->stats().cutTriangles, 0u);
    EXPECT_LT(floor.worstAroundTheBlock(), 0.03);
    settings.directAtCorners = false;
    settings.indirectAtCorners = 0;
    const CoveredFloor means(settings, "radiosity-covered-floor-cut-means");
    EXPECT_LT(means.worstAroundTheBlock(), 0.03);
}

}  // namespace
}  // namespace penumbra::test
