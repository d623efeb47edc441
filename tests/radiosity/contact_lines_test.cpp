// Discontinuity meshing along contact lines (radiosity/contact_lines.h, triangle_pieces.h): a
// floor with a box standing on it, turned so that its footprint crosses the floor's diagonal
// and the patches' lattice at odd angles. The oracle is the footprint itself, known in closed
// form: no leaf of the floor may straddle it, however far the leaves are split.
#include "radiosity/contact_lines.h"
#include "radiosity/radiosity_mesh.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"
#include "tests/support/straddling_leaves.h"

#include "core/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace penumbra {
namespace {

using test::GltfBuilder;

constexpr float kTurn = 0.5f;   // radians about +Y
constexpr float kHalf = 0.25f;  // the box's half-width

Vec3 turned(const Vec3& p) {
    const float c = std::cos(kTurn), s = std::sin(kTurn);
    return {c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
}

// A floor [-1, 1]^2 at y = 0 facing up (two triangles) and a box of half-width kHalf from
// y = bottom to y = top, turned by kTurn about its vertical axis.
std::unique_ptr<Scene> floorAndBox(float bottom, float top, const std::string& name) {
    GltfBuilder builder;
    const int grey = builder.addMaterial({.baseColor = Color(0.5f)});
    builder.addQuad({-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, grey);
    test::TriangleMesh box = test::solidBox({-kHalf, bottom, -kHalf}, {kHalf, top, kHalf});
    for (Vec3& p : box.positions)
        p = turned(p);
    builder.addMesh(box.positions, box.indices, grey);
    return test::loadBuiltScene(builder, name);
}

MeshingSettings contactSettings(bool contactLines) {
    MeshingSettings settings;
    settings.patchEdgeLength = 0.6f;
    settings.minElementArea = 1e-4f;
    settings.contactLines = contactLines;
    return settings;
}

// Where a floor point lies against the footprint: > 0 outside, < 0 inside (the largest of the
// four signed distances to its sides).
float footprintDistance(const Vec3& p) {
    const Vec3 q = turned(Vec3(p.x, 0.0f, -p.z));  // turned back: the inverse rotation
    const Vec3 local(q.x, 0.0f, -q.z);
    return std::max(std::abs(local.x), std::abs(local.z)) - kHalf;
}

bool isFloor(const RadiosityMesh& mesh, int element) {
    return mesh.sceneMesh(element) == 0;
}

// Splits every floor leaf `levels` times.
void splitFloor(RadiosityMesh& mesh, int levels) {
    for (int level = 0; level < levels; ++level) {
        for (const int leaf : mesh.leafElements()) {
            if (isFloor(mesh, leaf) && mesh.canSplit(leaf))
                mesh.split(leaf);
        }
    }
}

TEST(ContactLines, ABoxStandingOnAFloorCutsItAlongItsFootprint) {
    const auto scene = floorAndBox(0.0f, 0.5f, "contact-standing");
    const ContactLines lines(*scene, 1e-3f, 1e-2f);
    // Both floor triangles: the footprint crosses the diagonal; the box's own faces meet only
    // at their edges, so none of them is cut.
    EXPECT_EQ(lines.triangleCount(), 2u);
    float length = 0.0f;
    for (uint32_t t = 0; t < 2; ++t) {
        const Mesh& floor = scene->meshes()[0];
        const glm::uvec3 i = floor.triangles[t];
        for (const TriangleSegment& s : lines.on(0, t)) {
            std::array<Vec3, 2> ends;
            for (int e = 0; e < 2; ++e) {
                ends[size_t(e)] = s[size_t(e)].x * floor.positions[i[0]] +
                                  s[size_t(e)].y * floor.positions[i[1]] +
                                  s[size_t(e)].z * floor.positions[i[2]];
                EXPECT_NEAR(footprintDistance(ends[size_t(e)]), 0.0f, 1e-5f);
            }
            length += glm::distance(ends[0], ends[1]);
        }
    }
    EXPECT_NEAR(length, 8.0f * kHalf, 1e-4f);  // the footprint's perimeter, once
}

TEST(ContactLines, ABoxThroughAFloorCutsItWhereItPassesThrough) {
    const auto scene = floorAndBox(-0.2f, 0.5f, "contact-through");
    RadiosityMesh mesh(*scene, contactSettings(true));
    splitFloor(mesh, 2);
    EXPECT_EQ(test::straddlingLeaves(mesh, 0, footprintDistance), 0);
    // The floor's two triangles, and the eight of the box's sides, which the floor cuts in turn.
    EXPECT_EQ(mesh.stats().cutTriangles, 10u);
}

TEST(ContactLines, ABoxUnderAOneSidedFloorLeavesItWhole) {
    // The floor faces up; a box below it touching it from behind cannot be seen from its front.
    const auto scene = floorAndBox(-0.5f, 0.0f, "contact-behind");
    const ContactLines lines(*scene, 1e-3f, 1e-2f);
    EXPECT_TRUE(lines.on(0, 0).empty());
    EXPECT_TRUE(lines.on(0, 1).empty());
}

TEST(ContactLines, NoLeafStraddlesTheFootprintHoweverFarSplit) {
    const auto scene = floorAndBox(0.0f, 0.5f, "contact-leaves");
    RadiosityMesh cut(*scene, contactSettings(true));
    RadiosityMesh whole(*scene, contactSettings(false));
    for (const int levels : {0, 1, 3}) {
        splitFloor(cut, levels);
        splitFloor(whole, levels);
        EXPECT_EQ(test::straddlingLeaves(cut, 0, footprintDistance), 0) << levels << " levels";
        if (levels > 0) {  // the check can fail: the lattice's leaves do straddle it
            EXPECT_GT(test::straddlingLeaves(whole, 0, footprintDistance), 0)
                << levels << " levels";
        }
    }
    EXPECT_EQ(cut.stats().cutTriangles, 2u);
    EXPECT_GT(cut.stats().pieces, 8u);
}

TEST(ContactLines, ThePiecesCoverEachTriangleAndLocateFindsEveryPoint) {
    const auto scene = floorAndBox(0.0f, 0.5f, "contact-locate");
    RadiosityMesh mesh(*scene, contactSettings(true));
    splitFloor(mesh, 2);
    // The patches of each floor triangle sum to its area (2 m²): no gap, no overlap.
    double area[2] = {0.0, 0.0};
    for (size_t p = 0; p < mesh.patchCount(); ++p) {
        if (isFloor(mesh, int(p)))
            area[mesh.sceneTriangle(int(p))] += mesh.area(int(p));
    }
    EXPECT_NEAR(area[0], 2.0, 1e-5);
    EXPECT_NEAR(area[1], 2.0, 1e-5);
    // A point's barycentrics come back from the leaf locate() finds and the weights in it, and
    // the leaf is the one under the point (its corners' hull holds the point).
    std::mt19937 random(7);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) {
        float b1 = uniform(random), b2 = uniform(random);
        if (b1 + b2 > 1.0f) {
            b1 = 1.0f - b1;
            b2 = 1.0f - b2;
        }
        const Vec3 b(1.0f - b1 - b2, b1, b2);
        const uint32_t triangle = uint32_t(i % 2);
        const ElementPoint p = mesh.locate(0, triangle, b);
        ASSERT_GE(p.element, 0);
        EXPECT_EQ(mesh.sceneTriangle(p.element), triangle);
        EXPECT_TRUE(mesh.isLeaf(p.element));
        EXPECT_GE(std::min({p.weights.x, p.weights.y, p.weights.z}), -1e-4f);
        const std::array<Vec3, 3>& corners = mesh.barycentrics(p.element);
        const Vec3 back =
            p.weights.x * corners[0] + p.weights.y * corners[1] + p.weights.z * corners[2];
        EXPECT_NEAR(back.y, b.y, 1e-5f);
        EXPECT_NEAR(back.z, b.z, 1e-5f);
    }
}

}  // namespace
}  // namespace penumbra
