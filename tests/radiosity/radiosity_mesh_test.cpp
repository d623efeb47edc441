// The radiosity element mesh: patch counts and areas, vertex sharing between patches, scene
// triangles and split neighbours, the quadtree's areas and point location, continuity of the
// Gouraud interpolation across every edge (T-vertices included), material values, and the Cornell
// box meshed to about 10k elements. Each tolerance is stated where it is used.
#include "radiosity/radiosity_mesh.h"

#include "core/gltf_loader.h"
#include "core/scene.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace penumbra {
namespace {

// Float geometry (positions of midpoints rounded to float) against double references.
constexpr double kGeometryTolerance = 1e-4;

Material lambertian(const Color& baseColor) {
    Material m;
    m.baseColor = baseColor;
    m.metallic = 0.0f;
    m.specular = 0.0f;  // no specular layer: the diffuse albedo is baseColor itself
    return m;
}

Mesh makeMesh(std::vector<Vec3> positions, std::vector<glm::uvec3> triangles, int material = 0) {
    Mesh mesh;
    mesh.name = "test";
    mesh.positions = std::move(positions);
    mesh.triangles = std::move(triangles);
    mesh.material = material;
    return mesh;
}

// The square [0, side]^2 in the plane z = 0, facing +z, as two triangles sharing the diagonal
// (vertex indices 0 and 2), or with the diagonal's vertices duplicated.
Mesh square(float side, bool shareDiagonal = true) {
    std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(side, 0, 0), Vec3(side, side, 0), Vec3(0, side, 0)};
    if (shareDiagonal)
        return makeMesh(p, {{0, 1, 2}, {0, 2, 3}});
    p.push_back(p[0]);
    p.push_back(p[2]);
    return makeMesh(p, {{0, 1, 2}, {4, 5, 3}});
}

std::unique_ptr<Scene> makeScene(std::vector<Mesh> meshes,
                                 std::vector<Material> materials = {lambertian(Color(0.5f))}) {
    SceneDescription desc;
    desc.file = "test";
    desc.meshes = std::move(meshes);
    desc.materials = std::move(materials);
    return std::make_unique<Scene>(std::move(desc));
}

double triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
    return 0.5 * glm::length(glm::cross(glm::dvec3(b - a), glm::dvec3(c - a)));
}

double sceneArea(const Scene& scene) {
    double sum = 0.0;
    for (const Mesh& mesh : scene.meshes())
        for (const glm::uvec3& t : mesh.triangles)
            sum += triangleArea(mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]);
    return sum;
}

double longestEdge(const std::array<Vec3, 3>& c) {
    return std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
}

std::vector<int> leaves(const RadiosityMesh& mesh) {
    std::vector<int> result;
    for (int e = 0; e < int(mesh.elementCount()); ++e)
        if (mesh.isLeaf(e))
            result.push_back(e);
    return result;
}

// Splits `rounds` times a random half of the leaves that can be split, so that neighbours end up
// at different levels (T-vertices up to several levels deep).
void splitRandomly(RadiosityMesh& mesh, int rounds, uint32_t seed) {
    std::mt19937 rng(seed);
    for (int round = 0; round < rounds; ++round) {
        for (const int e : leaves(mesh))
            if (mesh.canSplit(e) && rng() % 2 == 0)
                mesh.split(e);
    }
}

// Barycentric weights of p with respect to triangle c (p in its plane), in double.
glm::dvec3 weightsOf(const std::array<Vec3, 3>& c, const Vec3& p) {
    const glm::dvec3 a(c[0]), e1 = glm::dvec3(c[1]) - a, e2 = glm::dvec3(c[2]) - a;
    const glm::dvec3 d = glm::dvec3(p) - a;
    const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const double d1 = glm::dot(d, e1), d2 = glm::dot(d, e2);
    const double det = d11 * d22 - d12 * d12;
    const double w1 = (d22 * d1 - d12 * d2) / det, w2 = (d11 * d2 - d12 * d1) / det;
    return {1.0 - w1 - w2, w1, w2};
}

// A smooth, non-linear field of world position, different per channel.
Color smoothField(const Vec3& p) {
    return Color(std::sin(3.0f * p.x) + p.y * p.y, std::cos(2.0f * p.y) * p.x + 1.0f,
                 0.5f + 0.25f * std::sin(p.x + 2.0f * p.y + p.z));
}

std::vector<Color> sampleField(const RadiosityMesh& mesh) {
    std::vector<Color> values(mesh.elementCount());
    for (int e = 0; e < int(mesh.elementCount()); ++e)
        values[size_t(e)] = smoothField(mesh.centroid(e));
    return values;
}

// Two triangles sharing the edge B C, one much larger than the other, so that with
// patchEdgeLength 2 the large one gets 8 x 8 patches and the small one 4 x 4: their patch
// vertices on the shared edge nest, the coarse side's being T-vertices of the fine side.
Mesh unequalNeighbours() {
    const Vec3 b(4, 0, 0), c(0, 4, 0), far(-10, 2, 0), near(3, 3, 0);
    return makeMesh({b, c, far, near}, {{0, 1, 2}, {1, 0, 3}});
}

TEST(RadiosityMesh, PatchCountsOfASquare) {
    // The 2 m square's triangles have a longest edge (the diagonal) of 2.83 m; n is the smallest
    // power of two with 2.83 / n <= patchEdgeLength, and each triangle has n^2 patches.
    const auto scene = makeScene({square(2.0f)});
    const struct {
        float length;
        size_t patches;
    } cases[] = {{10.0f, 2}, {2.9f, 2}, {2.8f, 8}, {1.5f, 8}, {1.0f, 32}, {0.5f, 128}};
    for (const auto& c : cases) {
        const RadiosityMesh mesh(*scene, {c.length, 0.0f});
        EXPECT_EQ(mesh.patchCount(), c.patches) << "patchEdgeLength " << c.length;
        EXPECT_EQ(mesh.elementCount(), c.patches);
        EXPECT_EQ(mesh.leafCount(), c.patches);
        for (int p = 0; p < int(mesh.patchCount()); ++p) {
            EXPECT_EQ(mesh.patch(p), p);
            EXPECT_EQ(mesh.parent(p), -1);
            EXPECT_LE(longestEdge(mesh.corners(p)), c.length * (1.0 + kGeometryTolerance));
        }
    }
    // 1/10 of the bounding radius (sqrt(2) m): 2.83 / 0.1414 = 20 -> n = 32.
    const RadiosityMesh tenth(*scene, {0.1f * std::sqrt(2.0f), 0.0f});
    EXPECT_EQ(tenth.patchCount(), 2u * 32u * 32u);
}

TEST(RadiosityMesh, PatchesCoverTheSceneArea) {
    // A square, a tilted sliver and the unequal pair: the patches' areas sum to the scene's area
    // within 1e-5 (float areas summed in double), and each patch's area matches its corners.
    std::vector<Mesh> meshes = {
        square(1.0f), unequalNeighbours(),
        makeMesh({Vec3(0, 0, 1), Vec3(3, 0.1f, 1.5f), Vec3(0, 0.2f, 2)}, {{0, 1, 2}})};
    const auto scene = makeScene(std::move(meshes));
    const RadiosityMesh mesh(*scene, {0.3f, 0.0f});
    double sum = 0.0;
    for (int p = 0; p < int(mesh.patchCount()); ++p) {
        sum += mesh.area(p);
        const auto c = mesh.corners(p);
        EXPECT_NEAR(triangleArea(c[0], c[1], c[2]) / mesh.area(p), 1.0, kGeometryTolerance);
    }
    EXPECT_NEAR(sum / sceneArea(*scene), 1.0, 1e-5);
}

TEST(RadiosityMesh, NeighbouringPatchesShareVertices) {
    // Two triangles of 2 x 2 patches each on a square share its diagonal: the 3 x 3 lattice has
    // 9 distinct vertices, not the 24 corners of 8 separate triangles nor the 12 of two
    // triangles that do not share the diagonal's vertex indices.
    const auto shared = makeScene({square(1.0f, true)});
    const RadiosityMesh mesh(*shared, {1.0f, 0.0f});
    ASSERT_EQ(mesh.patchCount(), 8u);
    EXPECT_EQ(mesh.vertexCount(), 9u);
    std::set<uint32_t> used;
    for (int p = 0; p < 8; ++p)
        for (const uint32_t v : mesh.vertices(p))
            used.insert(v);
    EXPECT_EQ(used.size(), 9u);

    const auto separate = makeScene({square(1.0f, false)});
    EXPECT_EQ(RadiosityMesh(*separate, {1.0f, 0.0f}).vertexCount(), 12u);
}

TEST(RadiosityMesh, SplitNeighboursShareTheirMidpoint) {
    // One patch per triangle: patches 0 and 1 share the diagonal. Splitting the first creates its
    // three midpoints; splitting the second creates two and reuses the diagonal's.
    const auto scene = makeScene({square(1.0f)});
    RadiosityMesh mesh(*scene, {10.0f, 0.0f});
    ASSERT_EQ(mesh.patchCount(), 2u);
    ASSERT_EQ(mesh.vertexCount(), 4u);
    const int a = mesh.split(0);
    EXPECT_EQ(mesh.vertexCount(), 7u);
    const int b = mesh.split(1);
    EXPECT_EQ(mesh.vertexCount(), 9u);
    std::set<uint32_t> fromA, fromB;
    for (int c = 0; c < RadiosityMesh::kChildren; ++c) {
        for (const uint32_t v : mesh.vertices(a + c))
            fromA.insert(v);
        for (const uint32_t v : mesh.vertices(b + c))
            fromB.insert(v);
    }
    std::vector<uint32_t> common;
    std::set_intersection(fromA.begin(), fromA.end(), fromB.begin(), fromB.end(),
                          std::back_inserter(common));
    // The diagonal's two end points and its one midpoint.
    ASSERT_EQ(common.size(), 3u);
    const Vec3 centre(0.5f, 0.5f, 0.0f);
    EXPECT_TRUE(std::any_of(common.begin(), common.end(), [&](uint32_t v) {
        return glm::length(mesh.position(v) - centre) < 1e-6f;
    }));
    // Splitting again returns the same children.
    EXPECT_EQ(mesh.split(0), a);
}

TEST(RadiosityMesh, QuadtreeStructureAndAreas) {
    const auto scene = makeScene({square(1.0f), unequalNeighbours()});
    RadiosityMesh mesh(*scene, {2.0f, 0.0f});
    splitRandomly(mesh, 4, 7);
    ASSERT_GT(mesh.elementCount(), mesh.patchCount());
    // Leaf areas (each exactly a power-of-four fraction of its patch) sum to the patch area
    // within 1e-6 relative (summed in double), and match their corners' geometry.
    std::vector<double> leafSum(mesh.patchCount(), 0.0);
    size_t leafCount = 0;
    for (int e = 0; e < int(mesh.elementCount()); ++e) {
        if (mesh.isLeaf(e)) {
            ++leafCount;
            leafSum[size_t(mesh.patch(e))] += mesh.area(e);
            const auto c = mesh.corners(e);
            EXPECT_NEAR(triangleArea(c[0], c[1], c[2]) / mesh.area(e), 1.0, kGeometryTolerance);
        } else {
            const int first = mesh.firstChild(e);
            for (int c = 0; c < RadiosityMesh::kChildren; ++c) {
                EXPECT_EQ(mesh.parent(first + c), e);
                EXPECT_EQ(mesh.patch(first + c), mesh.patch(e));
                EXPECT_EQ(mesh.level(first + c), mesh.level(e) + 1);
                EXPECT_EQ(mesh.normal(first + c), mesh.normal(e));
            }
            // Child c < 3 keeps the parent's corner c.
            for (int c = 0; c < 3; ++c)
                EXPECT_EQ(mesh.vertices(first + c)[size_t(c)], mesh.vertices(e)[size_t(c)]);
        }
    }
    EXPECT_EQ(leafCount, mesh.leafCount());
    for (int p = 0; p < int(mesh.patchCount()); ++p)
        EXPECT_NEAR(leafSum[size_t(p)] / mesh.area(p), 1.0, 1e-6) << "patch " << p;
}

TEST(RadiosityMesh, InterpolationIsContinuousAcrossEveryEdge) {
    // The square (one patch per triangle) and the unequal neighbours (8 x 8 and 4 x 4 patches,
    // nesting on their shared edge), split at random to different levels, with per-element
    // values sampled from a smooth non-linear field.
    const auto scene = makeScene({square(1.0f), unequalNeighbours()});
    RadiosityMesh mesh(*scene, {2.0f, 0.0f});
    splitRandomly(mesh, 5, 11);
    mesh.setElementValues(sampleField(mesh));
    ASSERT_GT(mesh.stats().tVertices, 0u);

    // The Gouraud field is linear on each leaf. It is continuous if every leaf's linear function,
    // evaluated at each vertex on the leaf's boundary (corners and T-vertices), equals that
    // vertex's value: two leaves sharing a boundary segment then agree at its ends, so along it.
    // Tolerance 1e-6: the weights of a vertex in the leaf come from float positions (relative
    // error ~1e-7) and multiply value differences of order 1.
    constexpr double kContinuity = 1e-6;
    int checked = 0;
    for (const int e : leaves(mesh)) {
        const auto c = mesh.corners(e);
        const auto& v = mesh.vertices(e);
        for (const uint32_t b : mesh.leafBoundary(e)) {
            const glm::dvec3 w = weightsOf(c, mesh.position(b));
            const glm::dvec3 inLeaf = w.x * glm::dvec3(mesh.vertexValue(v[0])) +
                                      w.y * glm::dvec3(mesh.vertexValue(v[1])) +
                                      w.z * glm::dvec3(mesh.vertexValue(v[2]));
            const glm::dvec3 atVertex(mesh.vertexValue(b));
            for (int ch = 0; ch < 3; ++ch)
                ASSERT_NEAR(inLeaf[ch], atVertex[ch], kContinuity)
                    << "leaf " << e << ", vertex " << b << ", channel " << ch;
            ++checked;
        }
    }
    EXPECT_GT(checked, 3 * int(mesh.leafCount()));  // T-vertices were among them

    // Through interpolate(), from both scene triangles of the unequal pair along their shared
    // edge B C (vertices 0 and 1 of mesh 1): triangle 0 is (B, C, far), triangle 1 is (C, B,
    // near). Same tolerance. The edge parameters t are dyadic, so that t and 1 - t are exact in
    // float and both sides are asked about the very same point.
    for (int i = 0; i < 1024; ++i) {
        const float t = (float(i) + 0.5f) / 1024.0f;  // from B towards C
        const Color first = mesh.interpolate(1, 0, Vec3(1.0f - t, t, 0.0f));
        const Color second = mesh.interpolate(1, 1, Vec3(t, 1.0f - t, 0.0f));
        for (int ch = 0; ch < 3; ++ch)
            EXPECT_NEAR(first[ch], second[ch], kContinuity) << "t = " << t;
    }
}

TEST(RadiosityMesh, ConstantFieldIsReproducedExactly) {
    const auto scene = makeScene({square(1.0f), unequalNeighbours()});
    RadiosityMesh mesh(*scene, {2.0f, 0.0f});
    splitRandomly(mesh, 4, 3);
    const Color constant(0.3f, 0.7f, 0.11f);
    mesh.setElementValues(std::vector<Color>(mesh.elementCount(), constant));
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v)
        ASSERT_EQ(mesh.vertexValue(v), constant) << "vertex " << v;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int i = 0; i < 2000; ++i) {
        float b1 = u(rng), b2 = u(rng);
        if (b1 + b2 > 1.0f)
            b1 = 1.0f - b1, b2 = 1.0f - b2;
        const Vec3 b(1.0f - b1 - b2, b1, b2);
        EXPECT_EQ(mesh.interpolate(0, uint32_t(i % 2), b), constant);
        EXPECT_EQ(mesh.interpolate(1, uint32_t(i % 2), b), constant);
        EXPECT_EQ(mesh.elementValue(1, uint32_t(i % 2), b), constant);
    }
}

TEST(RadiosityMesh, LocateFindsTheLeafContainingAPoint) {
    // Round trip: a point given by weights w in a leaf, mapped to the scene triangle's
    // barycentrics, is located in that leaf with the same weights. The barycentrics are floats
    // (rounding ~6e-8) and the leaf's weights scale them by its size ratio to the triangle (n
    // 2^level, up to 256 here), so the tolerance is 1e-6 times that ratio. Weights >= 0.05 keep the
    // point away from the leaf's edges.
    const auto scene = makeScene({square(1.0f), unequalNeighbours()});
    RadiosityMesh mesh(*scene, {2.0f, 0.0f});
    splitRandomly(mesh, 5, 13);
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(0.05f, 0.9f);
    for (const int e : leaves(mesh)) {
        Vec3 w(u(rng), u(rng), u(rng));
        w /= w.x + w.y + w.z;
        if (glm::min(w.x, glm::min(w.y, w.z)) < 0.05f)
            continue;
        const auto& corners = mesh.barycentrics(e);
        const Vec3 b = w.x * corners[0] + w.y * corners[1] + w.z * corners[2];
        const ElementPoint found = mesh.locate(mesh.sceneMesh(e), mesh.sceneTriangle(e), b);
        ASSERT_EQ(found.element, e);
        const Vec3 side =
            glm::max(glm::abs(corners[1] - corners[0]), glm::abs(corners[2] - corners[0]));
        const double ratio = 1.0 / double(glm::max(side.x, glm::max(side.y, side.z)));
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(found.weights[i], w[i], 1e-6 * ratio) << "element " << e;
    }
}

TEST(RadiosityMesh, MaterialValues) {
    // Lambertian (no specular layer): rho is baseColor exactly. Emissive, through the glTF
    // loader: Le is emissiveFactor x emissiveStrength exactly (0.5 x 4 = 2, ...) on the front.
    test::GltfBuilder builder;
    test::TestMaterial wall;
    wall.baseColor = Color(0.2f, 0.5f, 0.8f);
    test::TestMaterial lamp;
    lamp.baseColor = Color(0.0f);
    lamp.emissive = Color(0.5f, 0.25f, 1.0f);
    lamp.emissiveStrength = 4.0f;
    lamp.doubleSided = true;
    const int wallIndex = builder.addMaterial(wall);
    const int lampIndex = builder.addMaterial(lamp);
    builder.addQuad(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), wallIndex);
    builder.addQuad(Vec3(0, 0, 1), Vec3(0, 1, 1), Vec3(1, 1, 1), Vec3(1, 0, 1), lampIndex);
    const test::TempDir dir("radiosity_mesh_materials");
    builder.write(dir.file("scene.gltf"));
    const Scene scene(loadGltf(dir.file("scene.gltf")));

    RadiosityMesh mesh(scene, {0.5f, 0.0f});
    splitRandomly(mesh, 2, 1);
    int walls = 0, lamps = 0;
    for (int e = 0; e < int(mesh.elementCount()); ++e) {
        const bool isLamp = scene.meshes()[mesh.sceneMesh(e)].material == lampIndex;
        if (isLamp) {
            ++lamps;
            EXPECT_EQ(mesh.Le(e), Color(2.0f, 1.0f, 4.0f));
            EXPECT_EQ(mesh.rho(e), Color(0.0f));
            EXPECT_TRUE(mesh.twoSided(e));
            EXPECT_NEAR(mesh.normal(e).z, -1.0f, 1e-6f);  // the lamp faces down
        } else {
            ++walls;
            EXPECT_EQ(mesh.rho(e), wall.baseColor);
            EXPECT_EQ(mesh.Le(e), Color(0.0f));
            EXPECT_FALSE(mesh.twoSided(e));
            EXPECT_NEAR(mesh.normal(e).z, 1.0f, 1e-6f);
        }
    }
    EXPECT_GT(walls, 0);
    EXPECT_GT(lamps, 0);
}

TEST(RadiosityMesh, TransmissiveAndDegenerateInput) {
    // A transmissive pane is not meshed (locate answers -1, interpolate 0). A third triangle on
    // an edge and a neighbour with the opposite winding make the polygon mesh non-manifold: they
    // get vertices of their own and are meshed all the same.
    Material glass = lambertian(Color(1.0f));
    glass.transmission = 1.0f;
    std::vector<Mesh> meshes = {
        makeMesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 2}}, 1),
        makeMesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0), Vec3(0, 0, 1),
                  Vec3(0.5f, -1, 0)},
                 {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {0, 1, 5}}, 0)};
    const auto scene = makeScene(std::move(meshes), {lambertian(Color(0.5f)), glass});
    RadiosityMesh mesh(*scene, {0.25f, 0.0f});
    EXPECT_EQ(mesh.locate(0, 0, Vec3(1.0f / 3.0f)).element, -1);
    double area = 0.0;
    for (int p = 0; p < int(mesh.patchCount()); ++p) {
        EXPECT_EQ(mesh.sceneMesh(p), 1u);
        area += mesh.area(p);
    }
    EXPECT_NEAR(area, 0.5 + 0.5 + 0.5 + 0.5, 1e-5);
    splitRandomly(mesh, 3, 2);
    mesh.setElementValues(sampleField(mesh));
    EXPECT_EQ(mesh.interpolate(0, 0, Vec3(1.0f / 3.0f)), Color(0.0f));
    EXPECT_TRUE(isFinite(mesh.interpolate(1, 3, Vec3(1.0f / 3.0f))));
}

TEST(RadiosityMesh, RefusesMisuse) {
    const auto scene = makeScene({square(1.0f)});
    EXPECT_THROW(RadiosityMesh(*scene, {-1.0f, 0.0f}), std::invalid_argument);
    // No automatic length: the solvers resolve their own "auto" before they mesh.
    EXPECT_THROW(RadiosityMesh(*scene, {}), std::invalid_argument);
    EXPECT_THROW(RadiosityMesh(*scene, {1.0f, std::nanf("")}), std::invalid_argument);
    EXPECT_THROW(RadiosityMesh(*scene, {1e-6f, 0.0f}), std::invalid_argument);  // 2^42 patches

    // Children below minElementArea: the 0.5 m² patches may be split once with 0.1 m².
    RadiosityMesh mesh(*scene, {10.0f, 0.1f});
    EXPECT_TRUE(mesh.canSplit(0));
    const int first = mesh.split(0);
    EXPECT_FALSE(mesh.canSplit(first));
    EXPECT_THROW(mesh.split(first), std::logic_error);
    EXPECT_THROW(mesh.split(99), std::out_of_range);

    EXPECT_THROW(mesh.setElementValues(std::vector<Color>(3)), std::invalid_argument);
    mesh.setElementValues(std::vector<Color>(mesh.elementCount(), Color(1.0f)));
    mesh.split(1);
    EXPECT_THROW(mesh.interpolate(0, 0, Vec3(1.0f / 3.0f)), std::logic_error);
    EXPECT_THROW(mesh.leafBoundary(0), std::logic_error);
}

TEST(RadiosityMesh, CornellBoxAtTenThousandElements) {
    // The Cornell box with 0.2 m patches, refined uniformly (every leaf that may be split, level
    // by level) until it has about 10k elements; the last level stops part way, which leaves
    // T-vertices. No element may be degenerate: positive
    // finite area matching its corners (1e-4), a unit normal, three distinct corners.
    const Scene scene(
        loadGltf(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.gltf"));
    using Clock = std::chrono::steady_clock;
    const auto start = Clock::now();
    RadiosityMesh mesh(scene, {0.2f, 0.0f});
    const double patchSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    const auto refineStart = Clock::now();
    while (mesh.elementCount() < 10000) {
        const std::vector<int> current = leaves(mesh);
        for (const int e : current) {
            if (mesh.elementCount() >= 10000)
                break;
            if (mesh.canSplit(e))
                mesh.split(e);
        }
    }
    const double refineSeconds = std::chrono::duration<double>(Clock::now() - refineStart).count();
    const auto valuesStart = Clock::now();
    mesh.setElementValues(sampleField(mesh));
    const double valuesSeconds = std::chrono::duration<double>(Clock::now() - valuesStart).count();

    const RadiosityMeshStats s = mesh.stats();
    std::printf(
        "Cornell box: patch edge %.4f m, %zu patches (%.2f ms), refined to %zu elements, %zu "
        "leaves, %zu vertices, %zu T-vertices (%.2f ms), Gouraud values %.2f ms, ~%.2f MiB\n",
        mesh.patchEdgeLength(), s.patches, 1e3 * patchSeconds, s.elements, s.leaves, s.vertices,
        s.tVertices, 1e3 * refineSeconds, 1e3 * valuesSeconds,
        double(s.memoryBytes) / (1024.0 * 1024.0));
    EXPECT_GE(s.elements, 10000u);
    // Generous bound against a pathological slowdown, not a benchmark.
    EXPECT_LT(patchSeconds + refineSeconds + valuesSeconds, 2.0);

    for (int e = 0; e < int(mesh.elementCount()); ++e) {
        const auto c = mesh.corners(e);
        const auto& v = mesh.vertices(e);
        ASSERT_TRUE(v[0] != v[1] && v[1] != v[2] && v[0] != v[2]) << "element " << e;
        ASSERT_TRUE(mesh.area(e) > 0.0f && std::isfinite(mesh.area(e))) << "element " << e;
        ASSERT_NEAR(triangleArea(c[0], c[1], c[2]) / mesh.area(e), 1.0, kGeometryTolerance)
            << "element " << e;
        ASSERT_NEAR(glm::length(mesh.normal(e)), 1.0f, 1e-6f) << "element " << e;
        ASSERT_TRUE(isFinite(mesh.rho(e)) && isFinite(mesh.Le(e))) << "element " << e;
    }
}

}  // namespace
}  // namespace penumbra
