// Discontinuity meshing along shadow boundaries (radiosity/shadow_lines.h): a floor under a
// square plate lit by a point light above it or by a directional light at a slant. The oracle is
// the plate's outline projected onto the floor from the light, known in closed form: a square
// scaled about the point below the light, or the square moved along the light's direction.
#include "radiosity/shadow_lines.h"
#include "radiosity/radiosity_mesh.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"
#include "tests/support/straddling_leaves.h"

#include "core/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace penumbra {
namespace {

using test::GltfBuilder;

constexpr float kTurn = 0.5f;         // the plate's turn about +Y, radians
constexpr float kHalf = 0.2f;         // the plate's half-width
constexpr float kPlateHeight = 0.5f;  // above the floor
constexpr float kLightHeight = 2.0f;  // the point light, above the floor's centre
constexpr float kRoofHalf = 0.3f;     // the roof's half-width, 1 m above the floor
// The directional light's direction of travel (normalised in the scene).
const Vec3 kSlant(0.3f, -1.0f, 0.2f);

Vec3 turned(const Vec3& p) {
    const float c = std::cos(kTurn), s = std::sin(kTurn);
    return {c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
}

// The signed distance of a floor point from a square of half-width `half` centred on `centre`
// in the floor's plane, turned by kTurn: > 0 outside, < 0 inside.
float squareDistance(const Vec3& p, const Vec3& centre, float half) {
    const Vec3 q = turned(Vec3(p.x - centre.x, 0.0f, -(p.z - centre.z)));  // turned back
    return std::max(std::abs(q.x), std::abs(q.z)) - half;
}

// The plate's shadow outline on the floor, as a signed distance.
using Outline = std::function<float(const Vec3&)>;
// From the point light: the square scaled by h / (h - plate) about the point below the light.
float pointShadow(const Vec3& p) {
    return squareDistance(p, Vec3(0.0f), kHalf * kLightHeight / (kLightHeight - kPlateHeight));
}
// From the directional light: the square moved along it down to the floor.
float slantShadow(const Vec3& p) {
    const Vec3 d = glm::normalize(kSlant);
    return squareDistance(p, d * (kPlateHeight / -d.y), kHalf);
}

// A floor [-1, 1]^2 at y = 0 facing up (mesh 0, two triangles) and above it a double-sided
// square plate (mesh 1), turned by kTurn; with `blocker`, a one-sided square roof of half-width
// kRoofHalf 1 m above the floor, facing down, that hides the light from the plate and from the
// plate's shadow.
std::unique_ptr<Scene> floorUnderAPlate(const test::TestLight& light, bool blocker,
                                        const std::string& name) {
    GltfBuilder builder;
    const int grey = builder.addMaterial({.baseColor = Color(0.5f)});
    const int plate = builder.addMaterial({.baseColor = Color(0.5f), .doubleSided = true});
    builder.addQuad({-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, grey);
    const float y = kPlateHeight;
    builder.addQuad(turned({-kHalf, y, kHalf}), turned({kHalf, y, kHalf}),
                    turned({kHalf, y, -kHalf}), turned({-kHalf, y, -kHalf}), plate);
    if (blocker)
        builder.addQuad({-kRoofHalf, 1, -kRoofHalf}, {kRoofHalf, 1, -kRoofHalf},
                        {kRoofHalf, 1, kRoofHalf}, {-kRoofHalf, 1, kRoofHalf}, grey);
    builder.addLight(light);
    return test::loadBuiltScene(builder, name);
}

test::TestLight pointLight() {
    return {.type = "point", .intensity = 10.0f, .position = Vec3(0.0f, kLightHeight, 0.0f)};
}

// A directional light travelling along kSlant: the node's -Z turned onto it.
test::TestLight slantLight() {
    const Vec3 d = glm::normalize(kSlant);
    // The shortest arc from a to d: (a x d, 1 + a . d), normalised.
    const Vec3 a(0.0f, 0.0f, -1.0f);
    const Vec4 q = glm::normalize(Vec4(glm::cross(a, d), 1.0f + glm::dot(a, d)));
    return {.type = "directional", .intensity = 1000.0f, .rotation = q};
}

// The world-space ends of segment s on triangle t of mesh m.
std::array<Vec3, 2> ends(const Scene& scene, uint32_t m, uint32_t t, const TriangleSegment& s) {
    const Mesh& mesh = scene.meshes()[m];
    const glm::uvec3 i = mesh.triangles[t];
    std::array<Vec3, 2> world;
    for (size_t e = 0; e < 2; ++e)
        world[e] = s[e].x * mesh.positions[i[0]] + s[e].y * mesh.positions[i[1]] +
                   s[e].z * mesh.positions[i[2]];
    return world;
}

// Every segment found on the floor lies on the outline, and they cover its perimeter once.
void expectTheOutline(const Scene& scene, const Outline& outline, float perimeter) {
    const ShadowLines lines(scene, shadowSources(scene), 1e-3f, 1e-2f);
    EXPECT_EQ(lines.triangleCount(), 2u) << "the floor's two triangles, nothing else";
    float length = 0.0f;
    for (uint32_t t = 0; t < 2; ++t) {
        for (const TriangleSegment& s : lines.on(0, t)) {
            const std::array<Vec3, 2> p = ends(scene, 0, t, s);
            EXPECT_NEAR(outline(p[0]), 0.0f, 1e-4f);
            EXPECT_NEAR(outline(p[1]), 0.0f, 1e-4f);
            length += glm::distance(p[0], p[1]);
        }
    }
    EXPECT_NEAR(length, perimeter, 1e-3f);
}

TEST(ShadowLines, APointLightCutsTheFloorAlongThePlatesShadow) {
    const auto scene = floorUnderAPlate(pointLight(), false, "shadow-point");
    expectTheOutline(*scene, pointShadow,
                     8.0f * kHalf * kLightHeight / (kLightHeight - kPlateHeight));
}

TEST(ShadowLines, ADirectionalLightCutsTheFloorAlongThePlatesShadow) {
    const auto scene = floorUnderAPlate(slantLight(), false, "shadow-slant");
    expectTheOutline(*scene, slantShadow, 8.0f * kHalf);
}

TEST(ShadowLines, AnEdgeInAnotherShadowCastsNone) {
    // The roof hides the light from the plate: the plate's outline casts no boundary, the
    // roof's does, its square of half-width kRoofHalf 1 m under the light doubled on the floor.
    const auto scene = floorUnderAPlate(pointLight(), true, "shadow-hidden");
    const auto roofShadow = [](const Vec3& p) {
        return std::max(std::abs(p.x), std::abs(p.z)) - 2.0f * kRoofHalf;
    };
    expectTheOutline(*scene, roofShadow, 16.0f * kRoofHalf);
}

TEST(ShadowLines, NoLeafStraddlesTheShadowHoweverFarSplit) {
    const auto scene = floorUnderAPlate(pointLight(), false, "shadow-leaves");
    MeshingSettings settings;
    settings.patchEdgeLength = 0.6f;
    settings.minElementArea = 1e-4f;
    settings.shadowLines = true;
    RadiosityMesh cut(*scene, settings);
    settings.shadowLines = false;
    RadiosityMesh whole(*scene, settings);
    for (const int levels : {0, 1, 3}) {
        for (RadiosityMesh* mesh : {&cut, &whole}) {
            for (int level = 0; level < levels; ++level) {
                for (const int leaf : mesh->leafElements()) {
                    if (mesh->sceneMesh(leaf) == 0 && mesh->canSplit(leaf))
                        mesh->split(leaf);
                }
            }
        }
        EXPECT_EQ(test::straddlingLeaves(cut, 0, pointShadow), 0) << levels << " levels";
        if (levels > 0) {  // the check can fail: the lattice's leaves do straddle it
            EXPECT_GT(test::straddlingLeaves(whole, 0, pointShadow), 0) << levels << " levels";
        }
    }
    EXPECT_EQ(cut.stats().cutTriangles, 2u);
    // The leaves' edges marked as on a cut (across which each side keeps its own light) are the
    // outline's: both ends on it.
    int onCut = 0;
    for (const int leaf : cut.leafElements()) {
        const std::array<Vec3, 3> c = cut.corners(leaf);
        for (size_t k = 0; k < 3; ++k) {
            if (!cut.edgeOnCut(leaf, k))
                continue;
            ++onCut;
            EXPECT_NEAR(pointShadow(c[k]), 0.0f, 1e-4f) << "leaf " << leaf;
            EXPECT_NEAR(pointShadow(c[(k + 1) % 3]), 0.0f, 1e-4f) << "leaf " << leaf;
        }
    }
    EXPECT_GT(onCut, 0);
}

}  // namespace
}  // namespace penumbra
