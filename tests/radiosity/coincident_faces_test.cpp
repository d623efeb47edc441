// Coincident faces (radiosity/coincident_faces.h): which patches lie on top of others, which of
// two wins, and the gather's divergence guard that coincident faces used to trip
// (radiosity/gather_divergence.h).
#include "radiosity/coincident_faces.h"
#include "core/scene.h"
#include "radiosity/gather_divergence.h"
#include "radiosity/radiosity_mesh.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::test {
namespace {

// A 2 m x 2 m quad in the plane y = height, centred at (x, z) = (dx, 0), facing +y (or -y).
void addFloorQuad(GltfBuilder& builder, int material, float dx = 0.0f, float height = 0.0f,
                  bool up = true) {
    const Vec3 a(dx - 1.0f, height, 1.0f), b(dx + 1.0f, height, 1.0f), c(dx + 1.0f, height, -1.0f),
        d(dx - 1.0f, height, -1.0f);
    if (up)
        builder.addQuad(a, b, c, d, material);
    else
        builder.addQuad(d, c, b, a, material);
}

struct Meshed {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<RadiosityMesh> mesh;
    std::unique_ptr<CoincidentFaces> coincident;
};

Meshed mesh(const GltfBuilder& builder, const std::string& name) {
    Meshed m;
    m.scene = loadBuiltScene(builder, name);
    // Patches of a tenth of the scene's bounding radius.
    m.mesh = std::make_unique<RadiosityMesh>(
        *m.scene, MeshingSettings{0.1f * m.scene->bounds().boundingRadius()});
    m.coincident = std::make_unique<CoincidentFaces>(*m.mesh);
    return m;
}

// Whether side `front` of every patch of scene mesh `sceneMesh` is hidden at its centroid (1),
// of none (0), or of some (-1).
int centroidsHidden(const Meshed& m, uint32_t sceneMesh, bool front) {
    int hidden = 0, total = 0;
    for (int p = 0; p < static_cast<int>(m.mesh->patchCount()); ++p) {
        if (m.mesh->sceneMesh(p) != sceneMesh)
            continue;
        ++total;
        hidden += m.coincident->hidden(p, front, m.mesh->centroid(p), 1e-5f) ? 1 : 0;
    }
    return hidden == total ? 1 : hidden == 0 ? 0 : -1;
}

// The scene mesh and side that replace side `front` of the patches of scene mesh 1 at their
// centroids, if the same for all.
std::optional<std::pair<uint32_t, bool>> replacingSide(const Meshed& m, bool front) {
    std::optional<std::pair<uint32_t, bool>> result;
    for (int p = 0; p < static_cast<int>(m.mesh->patchCount()); ++p) {
        if (m.mesh->sceneMesh(p) != 1)
            continue;
        const auto side = m.coincident->replacementAt(p, front, m.mesh->centroid(p));
        if (!side)
            return std::nullopt;
        const std::pair<uint32_t, bool> s{m.mesh->sceneMesh(side->patch), side->front};
        if (result && *result != s)
            return std::nullopt;
        result = s;
    }
    return result;
}

TEST(CoincidentFaces, ADuplicateLosesBothSidesToTheEarlierMesh) {
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.5f)});
    addFloorQuad(builder, white);
    addFloorQuad(builder, white);
    const Meshed m = mesh(builder, "coincident-same");
    for (const bool front : {true, false}) {
        EXPECT_EQ(centroidsHidden(m, 1, front), 1) << "front " << front;
        EXPECT_EQ(centroidsHidden(m, 0, front), 0) << "front " << front;
        EXPECT_EQ(replacingSide(m, front), std::make_pair(0u, front)) << "front " << front;
    }
    EXPECT_NEAR(m.coincident->hiddenArea(), 4.0, 1e-4);
}

TEST(CoincidentFaces, BackToBackFacesKeepTheirFronts) {
    // Two one-sided emitters back to back: a lamp that shines both ways.
    GltfBuilder builder;
    const int light = builder.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 10.0f});
    addFloorQuad(builder, light);
    addFloorQuad(builder, light, 0.0f, 0.0f, false);
    const Meshed m = mesh(builder, "coincident-back-to-back");
    for (const uint32_t sceneMesh : {0u, 1u}) {
        EXPECT_EQ(centroidsHidden(m, sceneMesh, true), 0) << "mesh " << sceneMesh;
        EXPECT_EQ(centroidsHidden(m, sceneMesh, false), 1) << "mesh " << sceneMesh;
    }
    EXPECT_EQ(replacingSide(m, false), std::make_pair(0u, true));
    EXPECT_NEAR(m.coincident->hiddenArea(), 8.0, 1e-4);
}

TEST(CoincidentFaces, APartialOverlapHidesOnlyTheOverlap) {
    // The second quad shifted by 1 m along x: half of it lies over the first.
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.5f)});
    addFloorQuad(builder, white);
    addFloorQuad(builder, white, 1.0f);
    const Meshed m = mesh(builder, "coincident-partial");
    // The first quad's far edge, in the scene's coordinates.
    float edge = -INFINITY;
    for (int p = 0; p < static_cast<int>(m.mesh->patchCount()); ++p) {
        if (m.mesh->sceneMesh(p) == 0) {
            for (const Vec3& c : m.mesh->corners(p))
                edge = glm::max(edge, c.x);
        }
    }
    int hidden = 0, open = 0;
    for (int p = 0; p < static_cast<int>(m.mesh->patchCount()); ++p) {
        if (m.mesh->sceneMesh(p) != 1)
            continue;
        const Vec3 x = m.mesh->centroid(p);
        const bool over = x.x < edge;
        for (const bool front : {true, false}) {
            EXPECT_EQ(m.coincident->hidden(p, front, x, 1e-5f), over)
                << "patch " << p << " at x " << x.x;
        }
        (over ? hidden : open) += 1;
    }
    EXPECT_GT(hidden, 0);
    EXPECT_EQ(hidden, open);
    EXPECT_EQ(centroidsHidden(m, 0, true), 0);
    EXPECT_EQ(centroidsHidden(m, 0, false), 0);
}

TEST(CoincidentFaces, AnEmitterWinsOverTheSurfaceItLiesOn) {
    // A light panel modelled in the plane of a ceiling that comes first, both facing down.
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.5f)});
    const int light = builder.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 10.0f});
    addFloorQuad(builder, white, 0.0f, 0.0f, false);
    addFloorQuad(builder, light, 0.0f, 0.0f, false);
    const Meshed m = mesh(builder, "coincident-emitter");
    for (const bool front : {true, false}) {
        EXPECT_EQ(centroidsHidden(m, 0, front), 1) << "front " << front;
        EXPECT_EQ(centroidsHidden(m, 1, front), 0) << "front " << front;
    }
}

TEST(CoincidentFaces, NeighboursOffsetAndTiltedFacesAreNotCoincident) {
    // A neighbour sharing an edge in the same plane, a copy 1 mm above (the covering probes see
    // it), and a copy tilted by one degree about its centre line.
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.5f)});
    addFloorQuad(builder, white);
    addFloorQuad(builder, white, 2.0f);
    addFloorQuad(builder, white, 0.0f, 1e-3f);
    const float t = std::tan(1.0f * 3.14159265f / 180.0f);
    builder.addQuad({-1.0f, -t, 1.0f}, {1.0f, t, 1.0f}, {1.0f, t, -1.0f}, {-1.0f, -t, -1.0f},
                    white);
    const Meshed m = mesh(builder, "coincident-none");
    EXPECT_EQ(m.coincident->hiddenPatches(), 0u);
}

TEST(GatherDivergence, OnlyASustainedGrowthDiverges) {
    std::vector<double> growing{1.0}, converging{1.0}, slow{1.0}, bump{1.0};
    for (int k = 0; k < 30; ++k) {
        growing.push_back(growing.back() * 1.1);
        converging.push_back(converging.back() * 0.9);
        slow.push_back(slow.back() * 1.02);  // 20 growing sweeps, but only 1.49-fold
        bump.push_back(bump.back() * (k == 25 ? 0.99 : 1.1));
    }
    EXPECT_TRUE(gatherDiverges(growing));
    EXPECT_FALSE(gatherDiverges(converging));
    EXPECT_FALSE(gatherDiverges(slow));
    EXPECT_FALSE(gatherDiverges(bump));  // one smaller change among the last 20
    EXPECT_FALSE(gatherDiverges(std::vector<double>(growing.begin(), growing.begin() + 20)));
}

}  // namespace
}  // namespace penumbra::test
