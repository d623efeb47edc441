// Hierarchical radiosity on degenerate and extreme input (the item 13): slivers, tiny and
// huge faces, coplanar touching faces, a scene far from the origin. Each case is built inside a
// closed furnace: when every surface emits the same Le and reflects the same rho on every side
// that can see another, the radiosity equation has the solution Le / (1 - rho) everywhere,
// whatever the geometry inside the enclosure. So each case has an exact answer, and a solver that
// mishandles a degenerate element shows it as a departure from that answer, a NaN or a negative.
#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

namespace penumbra::test {
namespace {

constexpr float kRho = 0.5f;
constexpr double kExact = 1.0 / (1.0 - kRho);  // Le = 1

struct FurnaceCheck {
    double maxError = 0.0;  // largest relative error of a leaf side that sees the enclosure
    bool allValid = true;   // no NaN, infinity or negative on any side of any element
    size_t leaves = 0;
};

// Every leaf side that has something in front of it must carry Le / (1 - rho). The walls' outer
// sides see nothing (they are one-sided and face outwards): their radiance is their reflected
// nothing, 0, which is checked only for validity.
FurnaceCheck checkFurnace(const Scene& scene, const RadiositySettings& settings) {
    RadiosityMesh mesh(scene, settings.meshing(scene));
    RadiositySolver solver(scene, mesh, settings);
    solver.solve();
    FurnaceCheck check;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        for (const bool front : {true, false}) {
            const Color L = solver.elementRadiance(element, front);
            check.allValid = check.allValid && validRadiance(L);
            if (!mesh.isLeaf(element) || (!front && !mesh.twoSided(element)))
                continue;
            ++check.leaves;
            for (int c = 0; c < 3; ++c)
                check.maxError = std::max(check.maxError, std::abs(L[c] / kExact - 1.0));
        }
    }
    return check;
}

// Settings fine enough for 1 % in the furnace (those of the furnace tests in
// tests/radiosity/radiosity_furnace_test.cpp: at the defaults, elements in the corners of the box
// reach 3.5 %).
RadiositySettings fineSettings() {
    RadiositySettings s;
    s.minElementArea = 0.5f / 64.0f;
    s.epsilon = 5e-4f;
    return s;
}

TestMaterial furnaceMaterial(bool doubleSided) {
    return {.baseColor = Color(kRho),
            .emissive = Color(1.0f),
            .emissiveStrength = 1.0f,
            .doubleSided = doubleSided};
}

// The furnace walls, and a material for objects inside it (emitting and reflecting on both
// sides, like the walls' inner sides).
struct Furnace {
    GltfBuilder scene;
    int object = -1;

    explicit Furnace(float h = 1.0f) {
        const int walls = scene.addMaterial(furnaceMaterial(false));
        object = scene.addMaterial(furnaceMaterial(true));
        addClosedBox(scene, walls, walls, h);
    }
};

TEST(RadiosityRobustness, SliversAndTinyTrianglesInAFurnace) {
    Furnace furnace;
    // A sliver 1 m long and 1e-4 m wide (aspect ratio 1e4), standing in the room.
    furnace.scene.addMesh({{-0.5f, -0.2f, 0.0f}, {0.5f, -0.2f, 0.0f}, {0.5f, -0.2f + 1e-4f, 0.0f}},
                          {0, 1, 2}, furnace.object);
    // A triangle of 1e-6 m² (edges near 1.4 mm).
    furnace.scene.addMesh({{0.2f, 0.3f, 0.2f}, {0.2014f, 0.3f, 0.2f}, {0.2f, 0.3014f, 0.2f}},
                          {0, 1, 2}, furnace.object);
    // A needle: three nearly collinear vertices (height 1e-6 m over a 0.5 m base).
    furnace.scene.addMesh({{-0.3f, 0.5f, -0.3f}, {0.2f, 0.5f, -0.3f}, {-0.05f, 0.500001f, -0.3f}},
                          {0, 1, 2}, furnace.object);
    const auto scene = loadBuiltScene(furnace.scene, "radiosity-slivers");
    const FurnaceCheck check = checkFurnace(*scene, fineSettings());
    std::cout << check.leaves << " leaf sides, largest error " << check.maxError << "\n";
    EXPECT_TRUE(check.allValid);
    EXPECT_LT(check.maxError, 0.01);
}

TEST(RadiosityRobustness, CoplanarTouchingTilesActAsOneFloor) {
    // The floor of the box is replaced by four coplanar tiles, separate meshes that touch along
    // their edges without sharing vertices (a tiled floor as modellers export it): they must not
    // see each other (coplanar) nor leak at the seams.
    GltfBuilder tiled;
    const int material = tiled.addMaterial(furnaceMaterial(false));
    const float h = 1.0f;
    const Vec3 c[8] = {{-h, -h, -h}, {h, -h, -h}, {h, h, -h}, {-h, h, -h},
                       {-h, -h, h},  {h, -h, h},  {h, h, h},  {-h, h, h}};
    // The walls and ceiling of addClosedBox(), without its floor.
    tiled.addQuad(c[0], c[1], c[2], c[3], material);
    tiled.addQuad(c[5], c[4], c[7], c[6], material);
    tiled.addQuad(c[4], c[0], c[3], c[7], material);
    tiled.addQuad(c[1], c[5], c[6], c[2], material);
    tiled.addQuad(c[3], c[2], c[6], c[7], material);
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            const float x0 = -h + i * h, z0 = -h + j * h;
            // Facing +y: counter-clockwise seen from above.
            tiled.addQuad({x0, -h, z0 + h}, {x0 + h, -h, z0 + h}, {x0 + h, -h, z0}, {x0, -h, z0},
                          material);
        }
    }
    const auto loaded = loadBuiltScene(tiled, "radiosity-tiles");
    const FurnaceCheck check = checkFurnace(*loaded, fineSettings());
    std::cout << check.leaves << " leaf sides, largest error " << check.maxError << "\n";
    EXPECT_TRUE(check.allValid);
    EXPECT_LT(check.maxError, 0.01);
}

// A block standing on the floor, emitting and reflecting on both sides: the floor runs under it,
// so floor elements straddle its faces, and its faces meet the floor along contact lines where the
// form factor between the two peaks. At the default settings the block's inner sides along the
// contact lines were 18.6 % off (its outer sides 9 %), and more with finer settings: the oracle
// sampled the kernel exactly on the contact line, where it is 0 (kernelSamples in
// radiosity/link_transfer.cpp), so links stayed at coarse receivers whose elements along the line
// gathered a third too little. Fixed, the largest error over all leaf sides, inner ones included,
// is 8.7 % (fixed seeds: the same on every run; 9.1 % since the children of partly occluded links
// are weighed by their own visibility from 8 rays each, radiosity/link_hierarchy.cpp,
// setReceiverWeights),
// and the 10 % bound is that plus margin. What remains is
// visibility at coarse receivers: the 16 shadow rays of a floor patch can all miss its part under
// the block, so its links to the walls look wholly visible (the leaves under the block gather walls
// they cannot see) or wholly hidden and dropped (its leaves outside the block miss them).
TEST(RadiosityRobustness, BlockInAFurnace) {
    Furnace furnace;
    addFloorBlock(furnace.scene, furnace.object);
    const auto scene = loadBuiltScene(furnace.scene, "radiosity-furnace-block");
    const FurnaceCheck check = checkFurnace(*scene, RadiositySettings{});
    std::cout << check.leaves << " leaf sides, largest error " << check.maxError << "\n";
    EXPECT_TRUE(check.allValid);
    EXPECT_LT(check.maxError, 0.10);
}

// A lit room (a ceiling light, a block on the floor: occlusion, refinement along its shadow) at
// other scales and far from the origin: radiance does not depend on the unit of length or on where
// the scene is, so the area-weighted mean radiance of every scene mesh must match the untransformed
// room's. The two solves make their refinement decisions independently, so rounding of the
// positions could flip one and move a mean by a fraction of the oracle's epsilon (here 5 %); none
// did when this was written (largest relative difference 3e-6), and 0.1 % leaves room for one.
struct Placement {
    std::string name;
    Vec3 translation;
    float scale;
};

std::vector<Color> meanRadiancePerMesh(const Placement& placement) {
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.7f)});
    addClosedBox(builder, white, white);
    addFloorBlock(builder, white);
    addCeilingLight(builder, 0.3f, 0.99f, 20.0f);
    builder.setRootTransform(placement.translation, placement.scale);
    const auto scene = loadBuiltScene(builder, "radiosity-" + placement.name);
    RadiositySettings settings;
    settings.epsilon = 0.05f;  // coarse: the test compares solutions, it does not judge them
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    // In double: the leaves' areas at the huge scale are 1e8 times the unit room's, and a float
    // sum over the thousands of leaves the direct light's refinement makes drifts by 0.15 %.
    std::vector<glm::dvec3> sum(scene->meshes().size(), glm::dvec3(0.0));
    std::vector<double> area(scene->meshes().size(), 0.0);
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        const Color L = solver.elementRadiance(element, true);
        EXPECT_TRUE(validRadiance(L) && validRadiance(solver.elementRadiance(element, false)));
        if (!mesh.isLeaf(element))
            continue;
        sum[mesh.sceneMesh(element)] += double(mesh.area(element)) * glm::dvec3(L);
        area[mesh.sceneMesh(element)] += mesh.area(element);
    }
    std::vector<Color> mean(sum.size());
    for (size_t m = 0; m < sum.size(); ++m)
        mean[m] = Color(sum[m] / area[m]);
    return mean;
}

class RadiosityPlacement : public testing::TestWithParam<Placement> {};

TEST_P(RadiosityPlacement, MeanRadiancePerSurfaceIsThatOfTheUntransformedRoom) {
    const std::vector<Color> expected = meanRadiancePerMesh({"unit", Vec3(0.0f), 1.0f});
    const std::vector<Color> placed = meanRadiancePerMesh(GetParam());
    ASSERT_EQ(placed.size(), expected.size());
    for (size_t m = 0; m < expected.size(); ++m) {
        std::cout << "mesh " << m << ": " << placed[m].g << " (untransformed " << expected[m].g
                  << ")\n";
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(placed[m][c], expected[m][c], 1e-3f * expected[m][c] + 1e-6f)
                << "mesh " << m << " channel " << c;
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, RadiosityPlacement,
                         testing::Values(Placement{"far", Vec3(1e5f, 3e4f, -1e5f), 1.0f},
                                         Placement{"huge", Vec3(0.0f), 1e4f},    // walls of 2e4 m
                                         Placement{"tiny", Vec3(0.0f), 1e-3f}),  // walls of 2 mm
                         [](const testing::TestParamInfo<Placement>& info) {
                             return info.param.name;
                         });

}  // namespace
}  // namespace penumbra::test
