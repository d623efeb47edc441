// Which sides of the scene's triangles face a sealed interior (radiosity/sealed_interiors.h):
// closed solids without a light inside, from the topology alone.
#include "radiosity/sealed_interiors.h"
#include "core/scene.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

namespace penumbra::test {
namespace {

// Counts, over every triangle of scene mesh m, the sides facing a sealed interior.
struct SideCounts {
    int front = 0, back = 0, triangles = 0;
};
SideCounts count(const Scene& scene, const SealedInteriors& sealed, uint32_t m) {
    SideCounts c;
    for (uint32_t t = 0; t < scene.meshes()[m].triangles.size(); ++t) {
        c.front += sealed.faces(m, t, true) ? 1 : 0;
        c.back += sealed.faces(m, t, false) ? 1 : 0;
        ++c.triangles;
    }
    return c;
}

TEST(SealedInteriors, TheInsideOfASolidBoxInALitRoom) {
    // A room of six separate quads (no closed mesh) lit by a point light, a solid box in it with
    // a double-sided material (the flag must not matter), and the same box wound inward.
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.5f)});
    const int solid = builder.addMaterial({.baseColor = Color(0.5f), .doubleSided = true});
    addClosedBox(builder, white, white, 2.0f);                                    // meshes 0-5
    addSolidBox(builder, {-1.0f, -2.0f, -1.0f}, {0.0f, -1.9f, 0.5f}, solid);      // mesh 6
    addSolidBox(builder, {0.5f, -1.0f, 0.5f}, {1.0f, -0.5f, 1.0f}, solid, true);  // mesh 7
    builder.addLight({.type = "point", .intensity = 10.0f, .position = {0.0f, 1.5f, 0.0f}});
    const auto scene = loadBuiltScene(builder, "sealed-solid-box");
    const SealedInteriors sealed(*scene);

    EXPECT_EQ(sealed.count(), 2u);
    for (uint32_t wall = 0; wall < 6; ++wall) {
        const SideCounts c = count(*scene, sealed, wall);
        EXPECT_EQ(c.front + c.back, 0) << "room quad " << wall;
    }
    const SideCounts outward = count(*scene, sealed, 6);
    EXPECT_EQ(outward.triangles, 12);
    EXPECT_EQ(outward.back, 12);
    EXPECT_EQ(outward.front, 0);
    const SideCounts inward = count(*scene, sealed, 7);
    EXPECT_EQ(inward.front, 12);
    EXPECT_EQ(inward.back, 0);
}

TEST(SealedInteriors, AClosedRoomWithItsLightInsideIsNotSealed) {
    // The room as one closed mesh wound inward (its inside is where its triangles face): with a
    // point light inside, or an emissive panel inside, light reaches its inner sides; with only
    // the sun (from outside everything), nothing does.
    const auto room = [](GltfBuilder& builder) {
        const int white = builder.addMaterial({.baseColor = Color(0.5f)});
        addSolidBox(builder, Vec3(-2.0f), Vec3(2.0f), white, true);
    };
    {
        GltfBuilder builder;
        room(builder);
        builder.addLight({.type = "point", .intensity = 10.0f, .position = {0.3f, 1.0f, 0.2f}});
        const auto scene = loadBuiltScene(builder, "sealed-room-point-light");
        EXPECT_EQ(SealedInteriors(*scene).count(), 0u);
    }
    {
        GltfBuilder builder;
        room(builder);
        addCeilingLight(builder, 0.3f, 1.9f, 10.0f);
        const auto scene = loadBuiltScene(builder, "sealed-room-panel");
        EXPECT_EQ(SealedInteriors(*scene).count(), 0u);
    }
    {
        GltfBuilder builder;
        room(builder);
        builder.addLight({.type = "directional", .intensity = 100.0f});
        const auto scene = loadBuiltScene(builder, "sealed-room-sun");
        const SealedInteriors sealed(*scene);
        EXPECT_EQ(sealed.count(), 1u);
        EXPECT_EQ(count(*scene, sealed, 0).front, 12);
    }
}

TEST(SealedInteriors, OpenNonManifoldFlatAndEmissiveSurfacesAreNot) {
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.5f)});
    const int lamp = builder.addMaterial(
        {.baseColor = Color(0.5f), .emissive = Color(1.0f), .emissiveStrength = 5.0f});
    addSolidBox(builder, {0.0f, 0.0f, 0.0f}, {0.5f, 0.5f, 0.5f}, white, false, 5);  // open
    // A box whose top quad is there twice in the mesh (a third triangle on each of its edges).
    TriangleMesh doubled = solidBox({1.0f, 0.0f, 1.0f}, {1.5f, 0.5f, 1.5f});
    for (size_t i = 24; i < 30; ++i)  // the top, quad 4
        doubled.indices.push_back(doubled.indices[i]);
    builder.addMesh(doubled.positions, doubled.indices, white);
    // A quad and its reverse in one mesh: closed and consistently wound, but enclosing nothing.
    builder.addMesh(
        {{2.0f, 0.0f, 2.0f}, {2.5f, 0.0f, 2.0f}, {2.5f, 0.5f, 2.0f}, {2.0f, 0.5f, 2.0f}},
        {0, 1, 2, 0, 2, 3, 0, 2, 1, 0, 3, 2}, white);
    addSolidBox(builder, {-1.5f, 0.0f, -1.5f}, {-1.0f, 0.5f, -1.0f}, lamp);  // emits
    builder.addLight({.type = "directional", .intensity = 100.0f});
    const auto scene = loadBuiltScene(builder, "sealed-not");
    EXPECT_EQ(SealedInteriors(*scene).count(), 0u);
}

}  // namespace
}  // namespace penumbra::test
