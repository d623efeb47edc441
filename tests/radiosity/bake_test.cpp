// `penumbra bake`: the radiosity solution baked into an unlit, vertex-coloured glTF model. The
// written file is read back with tinygltf (as a viewer would) and with penumbra's own loader
// (which validates it), and compared with the solver: every vertex colour against the solver's
// radiance at that point, positions against the input scene placed far from the origin, the
// leaves' area, T-junctions, the automatic exposure's quantile; then the command line.
#include "radiosity/bake.h"
#include "core/errors.h"
#include "core/gltf_loader.h"
#include "core/gltf_writer.h"
#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace penumbra::test {
namespace {

namespace fs = std::filesystem;

using DVec3 = glm::dvec3;

// Where the test scene sits in its file: far enough from the origin that float positions would
// lose millimetres (float spacing at 45 km is 4 mm), exactly representable so the input is exact.
const DVec3 kOffset{3000.5, -1200.25, 45000.75};

// The scene in its own coordinates (before kOffset).
struct Quad {
    Vec3 p[4];
    int material;
};

// A floor, a double-sided red back wall, a table top casting a shadow, an emissive ceiling panel
// and a point light: emitters, shadows (refinement, hence T-vertices) and both kinds of sides.
std::vector<Quad> testQuads(GltfBuilder& builder) {
    const int white = builder.addMaterial({.baseColor = Color(0.6f)});
    const int red =
        builder.addMaterial({.baseColor = Color(0.7f, 0.2f, 0.1f), .doubleSided = true});
    const int light = builder.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 5.0f});
    return {{{{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}}, white},  // floor, up
            {{{-1, 0, -1}, {1, 0, -1}, {1, 2, -1}, {-1, 2, -1}}, red},  // wall, +z
            {{{-0.3f, 0.4f, -0.3f}, {-0.3f, 0.4f, 0.3f}, {0.3f, 0.4f, 0.3f}, {0.3f, 0.4f, -0.3f}},
             white},  // table, up
            {{{-0.25f, 1.5f, -0.25f},
              {0.25f, 1.5f, -0.25f},
              {0.25f, 1.5f, 0.25f},
              {-0.25f, 1.5f, 0.25f}},
             light}};  // panel, down
}

// The input triangles in the file's frame, per quad (two triangles each, as addQuad writes them).
struct FileTriangle {
    DVec3 a, b, c;
};

// Barycentric coordinates of p in triangle (a, b, c), and its distance from the triangle's plane.
DVec3 barycentric(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c,
                  double* planeDistance = nullptr) {
    const DVec3 e1 = b - a, e2 = c - a, d = p - a;
    const DVec3 n = glm::cross(e1, e2);
    if (planeDistance)
        *planeDistance = std::abs(glm::dot(d, n)) / glm::length(n);
    const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const double dp1 = glm::dot(d, e1), dp2 = glm::dot(d, e2);
    const double det = d11 * d22 - d12 * d12;
    const double v = (d22 * dp1 - d12 * dp2) / det, w = (d11 * dp2 - d12 * dp1) / det;
    return {1.0 - v - w, v, w};
}

// The triangle of `triangles` containing p (largest smallest barycentric among those whose plane
// passes within `tolerance`), or -1.
int containingTriangle(const DVec3& p, const std::vector<FileTriangle>& triangles,
                       double tolerance) {
    int best = -1;
    double bestInside = -1e-6;
    for (size_t t = 0; t < triangles.size(); ++t) {
        double distance = 0.0;
        const DVec3 b = barycentric(p, triangles[t].a, triangles[t].b, triangles[t].c, &distance);
        const double inside = std::min({b.x, b.y, b.z});
        if (distance <= tolerance && inside > bestInside) {
            best = int(t);
            bestInside = inside;
        }
    }
    return best;
}

// One primitive of the written file, read as a viewer reads it.
struct ReadMesh {
    std::string name;
    int material = -1;
    std::vector<Vec3> positions;
    std::vector<Vec3> colors;
    std::vector<Vec3> radiance;  // kRadianceAttribute
    std::vector<uint32_t> indices;
};

// The data of a tightly packed accessor, checking what the glTF specification requires of it:
// component type, element type, alignment (section 3.6.2.4) and bounds (3.6.2.2).
template <typename T>
std::vector<T> readAccessor(const tinygltf::Model& model, int index, int componentType, int type) {
    const tinygltf::Accessor& accessor = model.accessors.at(size_t(index));
    EXPECT_EQ(accessor.componentType, componentType);
    EXPECT_EQ(accessor.type, type);
    const tinygltf::BufferView& view = model.bufferViews.at(size_t(accessor.bufferView));
    const tinygltf::Buffer& buffer = model.buffers.at(size_t(view.buffer));
    const size_t offset = view.byteOffset + accessor.byteOffset;
    EXPECT_EQ(offset % 4, 0u) << "accessor " << index << " is not 4-byte aligned";
    EXPECT_TRUE(view.byteStride == 0 || view.byteStride == sizeof(T));
    EXPECT_EQ(view.byteLength, accessor.count * sizeof(T)) << "accessor " << index;
    std::vector<T> data(accessor.count);
    if (offset + accessor.count * sizeof(T) > buffer.data.size()) {
        ADD_FAILURE() << "accessor " << index << " runs past its buffer";
        return {};
    }
    std::memcpy(data.data(), buffer.data.data() + offset, accessor.count * sizeof(T));
    return data;
}

struct ReadModel {
    tinygltf::Model model;
    std::vector<ReadMesh> meshes;
    DVec3 rootTranslation{0.0};
};

ReadModel readGlb(const std::string& path) {
    ReadModel read;
    tinygltf::TinyGLTF loader;
    std::string error, warning;
    EXPECT_TRUE(loader.LoadBinaryFromFile(&read.model, &error, &warning, path)) << error;
    EXPECT_EQ(error, "");
    EXPECT_EQ(warning, "");
    const tinygltf::Model& model = read.model;
    const tinygltf::Node& root = model.nodes.at(size_t(model.scenes.at(0).nodes.at(0)));
    if (root.translation.size() == 3)
        read.rootTranslation = {root.translation[0], root.translation[1], root.translation[2]};
    for (const int child : root.children) {
        const tinygltf::Node& node = model.nodes.at(size_t(child));
        EXPECT_TRUE(node.translation.empty() && node.rotation.empty() && node.scale.empty());
        const tinygltf::Mesh& mesh = model.meshes.at(size_t(node.mesh));
        EXPECT_EQ(mesh.primitives.size(), 1u);
        const tinygltf::Primitive& primitive = mesh.primitives.at(0);
        EXPECT_EQ(primitive.mode, TINYGLTF_MODE_TRIANGLES);
        ReadMesh m;
        m.name = mesh.name;
        m.material = primitive.material;
        m.positions = readAccessor<Vec3>(model, primitive.attributes.at("POSITION"),
                                         TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
        m.colors = readAccessor<Vec3>(model, primitive.attributes.at("COLOR_0"),
                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
        m.indices = readAccessor<uint32_t>(
            model, primitive.indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR);
        m.radiance = readAccessor<Vec3>(model, primitive.attributes.at(kRadianceAttribute),
                                        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
        EXPECT_EQ(m.colors.size(), m.positions.size());
        EXPECT_EQ(m.radiance.size(), m.positions.size());
        // The specification's range of a float COLOR_0 (the Khronos validator's
        // ACCESSOR_NON_CLAMPED).
        for (const Vec3& c : m.colors)
            EXPECT_TRUE(glm::all(glm::greaterThanEqual(c, Vec3(0.0f))) &&
                        glm::all(glm::lessThanEqual(c, Vec3(1.0f))));
        // POSITION's min and max are required and must be the data's bounds.
        const tinygltf::Accessor& p =
            model.accessors.at(size_t(primitive.attributes.at("POSITION")));
        for (int k = 0; k < 3; ++k) {
            float lo = INFINITY, hi = -INFINITY;
            for (const Vec3& v : m.positions) {
                lo = std::min(lo, v[k]);
                hi = std::max(hi, v[k]);
            }
            EXPECT_EQ(p.minValues.at(size_t(k)), double(lo));
            EXPECT_EQ(p.maxValues.at(size_t(k)), double(hi));
        }
        read.meshes.push_back(std::move(m));
    }
    return read;
}

// Radiosity settings that refine around the table's shadow in about a second, with the cuts
// along the shadow lines of the point light, as `penumbra bake` has it by default.
RadiositySettings testSettings() {
    RadiositySettings s;
    s.patchEdgeLength = 1.0f;
    s.minElementArea = 2e-3f;
    s.epsilon = 0.02f;
    return s;
}

// The scene built, loaded and solved once for all tests of the suite.
class Bake : public testing::Test {
  protected:
    static void SetUpTestSuite() {
        GltfBuilder builder;
        const std::vector<Quad> quads = testQuads(builder);
        for (const Quad& q : quads) {
            builder.addQuad(q.p[0], q.p[1], q.p[2], q.p[3], q.material);
            // addQuad writes (p0, p1, p2) and (p0, p2, p3).
            const auto file = [](const Vec3& p) { return DVec3(p) + kOffset; };
            fileTriangles_.push_back({file(q.p[0]), file(q.p[1]), file(q.p[2])});
            fileTriangles_.push_back({file(q.p[0]), file(q.p[2]), file(q.p[3])});
        }
        builder.addLight({.intensity = 2.0f, .position = {0.5f, 1.0f, 0.5f}});
        builder.setRootTransform(Vec3(kOffset), 1.0f);
        dir_ = new TempDir("bake");
        builder.write(dir_->file("scene.gltf"));
        scene_ = new Scene(loadGltf(dir_->file("scene.gltf")));
        mesh_ = new RadiosityMesh(*scene_, testSettings().meshing(*scene_));
        solver_ = new RadiositySolver(*scene_, *mesh_, testSettings());
        solver_->solve();
        solver_->showIndirectAtCorners();
    }
    // The bake of the solved mesh, with the solver's values at the leaves' corners.
    static BakeResult bake(std::optional<float> exposure) {
        return bakeRadiosity(
            *scene_, *mesh_,
            [](int leaf, size_t corner) { return solver_->cornerRadiance(leaf, corner, true); },
            exposure);
    }

    static void TearDownTestSuite() {
        delete solver_;
        delete mesh_;
        delete scene_;
        delete dir_;
    }

    static TempDir* dir_;
    static Scene* scene_;
    static RadiosityMesh* mesh_;
    static RadiositySolver* solver_;
    static std::vector<FileTriangle> fileTriangles_;
};

TempDir* Bake::dir_ = nullptr;
Scene* Bake::scene_ = nullptr;
RadiosityMesh* Bake::mesh_ = nullptr;
RadiositySolver* Bake::solver_ = nullptr;
std::vector<FileTriangle> Bake::fileTriangles_;

// The scene mesh a written mesh came from (they keep its name).
uint32_t sceneMeshNamed(const Scene& scene, const std::string& name) {
    for (size_t m = 0; m < scene.meshes().size(); ++m) {
        if (scene.meshes()[m].name == name)
            return uint32_t(m);
    }
    ADD_FAILURE() << "no scene mesh named " << name;
    return 0;
}

// What the bake writes at a vertex of a triangle is the solver's view (RadiositySolver::
// radiance(), emission included) at that corner of the leaf the triangle lies on, in radiance
// and, times the exposure and clamped, in colour. The view is linear over a leaf, so it is read
// a ten-thousandth of the way from the corner to the triangle's centroid, inside the triangle
// and so inside its leaf (a vertex on a shadow line's cut belongs to the leaves of both sides,
// which show different values): the field changes there by at most 1e-4 of the largest value
// at the triangle's corners. A vertex that two leaves share holds the first one's value when the
// other's is within kSameBakedRadiance (a thousandth) of it; float rounding adds a few ulps. A
// wrong exposure, vertex, side or leaf shows as several per cent.
TEST_F(Bake, VertexColoursAreTheSolversViewTimesTheExposure) {
    constexpr float kExposure = 1.5f;
    const BakeResult result = bake(kExposure);
    EXPECT_FALSE(result.automaticExposure);
    const std::string path = dir_->file("lit.glb");
    const size_t bytes = writeGltf(path, result.model);
    EXPECT_EQ(bytes, fs::file_size(path));
    const ReadModel read = readGlb(path);
    ASSERT_EQ(read.meshes.size(), scene_->meshes().size());  // every mesh here is opaque

    const float scale = std::exp2(kExposure);
    double worst = 0.0;
    size_t checked = 0, clamped = 0;
    for (const ReadMesh& m : read.meshes) {
        const uint32_t s = sceneMeshNamed(*scene_, m.name);
        const Mesh& source = scene_->meshes()[s];
        std::vector<FileTriangle> triangles;  // the source's, in penumbra's frame
        for (const glm::uvec3& t : source.triangles) {
            triangles.push_back(
                {source.positions[t[0]], source.positions[t[1]], source.positions[t[2]]});
        }
        for (size_t i = 0; i < m.indices.size(); i += 3) {
            // The scene triangle holding this one (its centroid is inside exactly one).
            const DVec3 p[3] = {m.positions[m.indices[i]], m.positions[m.indices[i + 1]],
                                m.positions[m.indices[i + 2]]};
            const DVec3 centroid = (p[0] + p[1] + p[2]) / 3.0;
            const int t = containingTriangle(centroid, triangles, 1e-6);
            ASSERT_GE(t, 0) << m.name << " triangle " << i / 3 << " lies on no input triangle";
            float largest = 0.0f;
            for (int k = 0; k < 3; ++k)
                largest = std::max(largest, maxComponent(m.radiance[m.indices[i + size_t(k)]]));
            for (int k = 0; k < 3; ++k) {
                const uint32_t v = m.indices[i + size_t(k)];
                const Color L = m.radiance[v];
                EXPECT_LE(maxComponent(glm::abs(m.colors[v] - glm::clamp(scale * L, 0.0f, 1.0f))),
                          1e-6f);
                const DVec3 b = barycentric(p[k] + 1e-4 * (centroid - p[k]), triangles[size_t(t)].a,
                                            triangles[size_t(t)].b, triangles[size_t(t)].c);
                const Color view = solver_->radiance(s, uint32_t(t), Vec3(b), true, true);
                const double difference = maxComponent(glm::abs(L - view));
                worst = std::max(worst, difference / std::max(largest, 1e-6f));
                ASSERT_LE(difference,
                          2e-4 * largest + 1.01 * kSameBakedRadiance * maxComponent(view) + 1e-6)
                    << m.name << " vertex " << v << ": radiance (" << L.r << ", " << L.g << ", "
                    << L.b << "), the view's (" << view.r << ", " << view.g << ", " << view.b
                    << ")";
                ++checked;
                clamped += maxComponent(scale * L) > 1.0f ? 1 : 0;
            }
        }
    }
    std::cout << checked << " triangle corners (" << clamped << " clamped), " << result.vertices
              << " vertices: largest difference from the view " << worst
              << " of the triangle's largest value\n";
    EXPECT_GT(clamped, 0u);  // the emitter, at least: the clamp was tested
}

TEST_F(Bake, PositionsLineUpWithTheInputFarFromTheOrigin) {
    const BakeResult result = bake(0.0f);
    const std::string path = dir_->file("positions.glb");
    writeGltf(path, result.model);
    const ReadModel read = readGlb(path);
    // The root's translation is the scene's origin, to double precision.
    EXPECT_EQ(read.rootTranslation, scene_->description().origin);
    double worst = 0.0;
    for (const ReadMesh& m : read.meshes) {
        for (const Vec3& local : m.positions) {
            const DVec3 p = read.rootTranslation + DVec3(local);
            const int t = containingTriangle(p, fileTriangles_, 1e-5);
            ASSERT_GE(t, 0) << m.name << ": vertex at (" << p.x << ", " << p.y << ", " << p.z
                            << ") is on no input triangle";
            const FileTriangle& f = fileTriangles_[size_t(t)];
            double distance = 0.0;
            const DVec3 b = barycentric(p, f.a, f.b, f.c, &distance);
            worst = std::max({worst, distance, -std::min({b.x, b.y, b.z})});
        }
    }
    std::cout << "largest distance of a vertex from the input surface: " << worst << " m\n";
    // A float at 45 km is only good to 4 mm: this holds only if the offset stays in double.
    EXPECT_LT(worst, 1e-5);

    // penumbra's own loader accepts the file (it validates what the specification requires) and
    // puts it at the same place; no triangle of a centroid fan is degenerate.
    const SceneDescription again = loadGltf(path);
    EXPECT_EQ(again.report.degenerateTriangles, 0u);
    EXPECT_EQ(again.meshes.size(), read.meshes.size());
    const std::vector<std::string>& ignored = again.report.extensionsIgnored;
    EXPECT_NE(std::find(ignored.begin(), ignored.end(), "KHR_materials_unlit"), ignored.end());
    for (size_t m = 0; m < again.meshes.size(); ++m) {
        ASSERT_EQ(again.meshes[m].positions.size(), read.meshes[m].positions.size());
        for (size_t v = 0; v < again.meshes[m].positions.size(); ++v) {
            const DVec3 loaded = again.origin + DVec3(again.meshes[m].positions[v]);
            const DVec3 written = read.rootTranslation + DVec3(read.meshes[m].positions[v]);
            ASSERT_LT(glm::length(loaded - written), 1e-5) << "mesh " << m << " vertex " << v;
        }
    }
}

TEST_F(Bake, LeavesCoverTheSurfaceWithoutTJunctions) {
    const BakeResult result = bake(0.0f);
    const std::string path = dir_->file("topology.glb");
    writeGltf(path, result.model);
    const ReadModel read = readGlb(path);

    // The test means something only if refinement left T-vertices (centroid fans) and the
    // shadow lines cut triangles, whose cuts end on edges the triangles beside do not cut. One
    // triangle per leaf, or one per boundary vertex for a centroid fan, and more where a leaf
    // takes the vertices of the triangle beside on its edges.
    size_t tLeaves = 0, triangles = 0;
    for (size_t e = 0; e < mesh_->elementCount(); ++e) {
        if (!mesh_->isLeaf(int(e)))
            continue;
        const size_t n = mesh_->leafBoundary(int(e)).size();
        tLeaves += n > 3 ? 1 : 0;
        triangles += n > 3 ? n : 1;
    }
    std::cout << result.leaves << " leaves, " << tLeaves << " with T-vertices, " << result.triangles
              << " triangles, " << mesh_->stats().cutTriangles << " scene triangles cut\n";
    ASSERT_GT(tLeaves, 0u);
    ASSERT_GT(mesh_->stats().cutTriangles, 0u);
    EXPECT_GE(result.triangles, triangles);

    for (const ReadMesh& m : read.meshes) {
        // The triangles cover the source mesh exactly once: equal areas (every triangle lies on
        // the source, as the other tests check).
        double area = 0.0, sourceArea = 0.0;
        for (size_t i = 0; i < m.indices.size(); i += 3) {
            const DVec3 a = m.positions[m.indices[i]], b = m.positions[m.indices[i + 1]],
                        c = m.positions[m.indices[i + 2]];
            area += 0.5 * glm::length(glm::cross(b - a, c - a));
        }
        const Mesh& source = scene_->meshes()[sceneMeshNamed(*scene_, m.name)];
        for (const glm::uvec3& t : source.triangles) {
            const DVec3 a = source.positions[t[0]], b = source.positions[t[1]],
                        c = source.positions[t[2]];
            sourceArea += 0.5 * glm::length(glm::cross(b - a, c - a));
        }
        EXPECT_NEAR(area / sourceArea, 1.0, 1e-5) << m.name;

        // No vertex lies inside another triangle's edge: a vertex there (a midpoint of a finer
        // neighbour) must be a corner of the triangles on both sides.
        size_t junctions = 0;
        for (size_t i = 0; i < m.indices.size(); ++i) {
            const uint32_t i0 = m.indices[i];
            const uint32_t i1 = m.indices[i % 3 == 2 ? i - 2 : i + 1];
            const DVec3 a = m.positions[i0], b = m.positions[i1];
            const double length2 = glm::dot(b - a, b - a);
            for (uint32_t v = 0; v < m.positions.size(); ++v) {
                const DVec3 p = m.positions[v];
                if (v == i0 || v == i1 || p == a || p == b)
                    continue;
                const double t = glm::dot(p - a, b - a) / length2;
                if (t > 1e-6 && t < 1.0 - 1e-6 &&
                    glm::length(p - (a + t * (b - a))) < 1e-6 * std::sqrt(length2))
                    ++junctions;
            }
        }
        EXPECT_EQ(junctions, 0u) << m.name;
    }
}

// The table's hard shadow keeps its step: the point light's shadow lines cut the floor where the
// table's edges cast them, x = 1/6 from z = -5/6 to 1/6 (the table's edge x = 0.3 at y = 0.4 seen
// from the light at (0.5, 1, 0.5)), and the vertices on that line are written twice, the lit
// side's value and the shadowed side's, each the view's a millimetre to its side. Without the
// cut a vertex there holds one value, and the step is spread over the leaves beside.
TEST_F(Bake, HardShadowsKeepTheirStep) {
    const BakeResult result = bake(0.0f);
    const std::string path = dir_->file("shadow.glb");
    writeGltf(path, result.model);
    const ReadModel read = readGlb(path);
    const uint32_t floor = sceneMeshNamed(*scene_, read.meshes[0].name);
    ASSERT_EQ(floor, 0u);
    const ReadMesh& m = read.meshes[0];
    constexpr double kEdgeX = 1.0 / 6.0;
    // From penumbra's frame (rebased on the scene's origin) to the scene's own (before kOffset).
    const DVec3 toOwn = scene_->description().origin - kOffset;
    // The values written at each point of the line, by its z.
    std::map<double, std::vector<Color>> onLine;
    for (size_t v = 0; v < m.positions.size(); ++v) {
        const DVec3 p = DVec3(m.positions[v]) + toOwn;
        if (std::abs(p.x - kEdgeX) < 1e-5 && p.z > -0.8 && p.z < 0.15)
            onLine[p.z].push_back(m.radiance[v]);
    }
    const Mesh& source = scene_->meshes()[floor];
    const auto view = [&](double x, double z) {
        const DVec3 p = DVec3(x, 0.0, z);
        for (uint32_t t = 0; t < source.triangles.size(); ++t) {
            const glm::uvec3& i = source.triangles[t];
            const DVec3 b = barycentric(p, DVec3(source.positions[i[0]]) + toOwn,
                                        DVec3(source.positions[i[1]]) + toOwn,
                                        DVec3(source.positions[i[2]]) + toOwn);
            if (std::min({b.x, b.y, b.z}) >= 0.0)
                return solver_->radiance(floor, t, Vec3(b), true, true);
        }
        ADD_FAILURE() << "no floor triangle at " << x << ", " << z;
        return Color(0.0f);
    };
    size_t stepped = 0;
    for (const auto& [z, values] : onLine) {
        if (values.size() < 2)
            continue;
        const auto [dark, lit] = std::ranges::minmax(values, {}, luminance);
        const Color litView = view(kEdgeX + 1e-3, z), darkView = view(kEdgeX - 1e-3, z);
        // A millimetre is a thousandth of the leaves there: the views change by about as much.
        EXPECT_NEAR(luminance(lit), luminance(litView), 0.01 * luminance(litView)) << z;
        EXPECT_NEAR(luminance(dark), luminance(darkView), 0.01 * luminance(litView)) << z;
        stepped += luminance(lit) > 1.5f * luminance(dark) ? 1 : 0;
    }
    std::cout << onLine.size() << " points on the line, " << stepped << " with a step\n";
    EXPECT_GE(stepped, 3u);
}

TEST_F(Bake, MaterialsAreUnlitAndKeepTheirSides) {
    const BakeResult result = bake(0.0f);
    const std::string path = dir_->file("materials.glb");
    writeGltf(path, result.model);
    const ReadModel read = readGlb(path);
    const auto& used = read.model.extensionsUsed;
    EXPECT_NE(std::find(used.begin(), used.end(), "KHR_materials_unlit"), used.end());
    // Not required: a viewer without it shows the colours on a dull non-metal.
    EXPECT_TRUE(read.model.extensionsRequired.empty());
    size_t doubleSided = 0;
    for (const ReadMesh& m : read.meshes) {
        const tinygltf::Material& material = read.model.materials.at(size_t(m.material));
        EXPECT_EQ(material.extensions.count("KHR_materials_unlit"), 1u);
        EXPECT_EQ(material.pbrMetallicRoughness.baseColorFactor,
                  std::vector<double>({1.0, 1.0, 1.0, 1.0}));
        const Mesh& source = scene_->meshes()[sceneMeshNamed(*scene_, m.name)];
        const bool sourceDoubleSided = scene_->materials()[size_t(source.material)].doubleSided;
        EXPECT_EQ(material.doubleSided, sourceDoubleSided) << m.name;
        doubleSided += sourceDoubleSided ? 1 : 0;
    }
    EXPECT_EQ(doubleSided, 1u);  // the red wall
}

TEST_F(Bake, AutomaticExposureMapsTheLitQuantileToOne) {
    const BakeResult result = bake(std::nullopt);
    ASSERT_TRUE(result.automaticExposure);
    EXPECT_GT(result.exposureRadiance, 0.0f);
    EXPECT_NEAR(result.exposure, -std::log2(result.exposureRadiance), 1e-6);
    const std::string path = dir_->file("auto.glb");
    writeGltf(path, result.model);
    const ReadModel read = readGlb(path);
    // From the file: the area share of the non-emissive surfaces (a third of each triangle's area
    // to each corner) whose exposed radiance exceeds 1 is at most 1 - kAutoExposureQuantile, and
    // the share of at least 1 is at least that.
    double total = 0.0, above = 0.0, atLeast = 0.0;
    for (const ReadMesh& m : read.meshes) {
        const Mesh& source = scene_->meshes()[sceneMeshNamed(*scene_, m.name)];
        if (scene_->materials()[size_t(source.material)].isEmissive())
            continue;
        for (size_t i = 0; i < m.indices.size(); i += 3) {
            const DVec3 a = m.positions[m.indices[i]], b = m.positions[m.indices[i + 1]],
                        c = m.positions[m.indices[i + 2]];
            const double third = glm::length(glm::cross(b - a, c - a)) / 6.0;
            for (size_t k = 0; k < 3; ++k) {
                const float value =
                    maxComponent(m.radiance[m.indices[i + k]]) * std::exp2(result.exposure);
                total += third;
                above += value > 1.0f + 1e-5f ? third : 0.0;
                atLeast += value >= 1.0f - 1e-5f ? third : 0.0;
            }
        }
    }
    std::cout << "automatic exposure " << result.exposure << " EV (" << result.exposureRadiance
              << " cd/m^2 -> 1): " << 100.0 * above / total << " % of the lit area above 1\n";
    EXPECT_LE(above / total, 1.0 - kAutoExposureQuantile);
    EXPECT_GE(atLeast / total, 1.0 - kAutoExposureQuantile);
}

// --- The writer alone -------------------------------------------------------------------------

TEST(GltfWriter, RgbaColoursAndTextGltfRoundTrip) {
    TempDir dir("gltf-writer");
    GltfModelData model;
    model.origin = {1.0e6, 0.25, -2.0e6};
    GltfMeshData mesh;
    mesh.name = "triangle";
    mesh.material = "paint";
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.colors = {0.5f, 0.2f, 0.0f, 1.0f, 0.0f, 0.25f, 0.8f, 0.5f, 1e-3f, 0.0f, 1.0f, 0.75f};
    mesh.customAttributes = {{"_HEAT", 1, {1e5f, -2.0f, 0.0f}}};
    mesh.colorComponents = 4;
    mesh.indices = {0, 1, 2};
    model.meshes = {mesh, mesh};  // two meshes, one shared material
    model.meshes[1].name = "again";
    const std::string path = dir.file("model.GLTF");  // the extension is case-insensitive
    writeGltf(path, model);

    tinygltf::Model read;
    tinygltf::TinyGLTF loader;
    std::string error, warning;
    ASSERT_TRUE(loader.LoadASCIIFromFile(&read, &error, &warning, path)) << error;
    ASSERT_EQ(read.meshes.size(), 2u);
    EXPECT_EQ(read.materials.size(), 1u);
    const std::vector<Vec4> colors =
        readAccessor<Vec4>(read, read.meshes[0].primitives[0].attributes.at("COLOR_0"),
                           TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4);
    ASSERT_EQ(colors.size(), 3u);
    for (size_t v = 0; v < 3; ++v) {
        for (int c = 0; c < 4; ++c)
            EXPECT_EQ(colors[v][c], mesh.colors[4 * v + size_t(c)]) << "vertex " << v;
    }
    const std::vector<float> heat =
        readAccessor<float>(read, read.meshes[1].primitives[0].attributes.at("_HEAT"),
                            TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR);
    EXPECT_EQ(heat, mesh.customAttributes[0].values);
    // The root node carries the origin exactly (JSON numbers are doubles).
    const tinygltf::Node& root = read.nodes.at(size_t(read.scenes.at(0).nodes.at(0)));
    EXPECT_EQ(root.translation, std::vector<double>({1.0e6, 0.25, -2.0e6}));
    // The self-contained .gltf: one buffer, embedded.
    ASSERT_EQ(read.buffers.size(), 1u);
    EXPECT_EQ(read.buffers[0].uri.rfind("data:", 0), 0u);
    // Only the file itself, no temporary or external buffer next to it.
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.file("")), fs::directory_iterator()), 1);
}

TEST(GltfWriter, RefusesBadPathsAndLeavesNothing) {
    TempDir dir("gltf-writer-refuses");
    GltfModelData model;
    GltfMeshData mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.indices = {0, 1, 2};
    model.meshes = {mesh};
    EXPECT_THROW(writeGltf(dir.file("lit.obj"), model), UsageError);
    EXPECT_THROW(writeGltf(dir.file("missing/lit.glb"), model), UsageError);
    model.meshes[0].indices = {0, 1, 3};
    EXPECT_THROW(writeGltf(dir.file("lit.glb"), model), std::invalid_argument);
    model.meshes[0].indices = {0, 1, 2};
    model.meshes[0].colors = {1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 0.0f, 0.0f, 1.5f};
    EXPECT_THROW(writeGltf(dir.file("lit.glb"), model), std::invalid_argument);
    model.meshes[0].colors.clear();
    model.meshes[0].customAttributes = {{"HEAT", 1, {0.0f, 0.0f, 0.0f}}};
    EXPECT_THROW(writeGltf(dir.file("lit.glb"), model), std::invalid_argument);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.file("")), fs::directory_iterator()), 0);
}

// --- The command line -------------------------------------------------------------------------

const std::string kCornellBox =
    std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.gltf";

// Bakes the room `build` makes (written to `dir`) with `options`; the command's output.
std::string bakeRoom(const TempDir& dir, void (*build)(GltfBuilder&), const std::string& options) {
    GltfBuilder room;
    build(room);
    room.write(dir.file("room.gltf"));
    const CliResult result =
        runPenumbra("bake " + dir.file("room.gltf") + " -o " + dir.file("lit.glb") +
                    " --epsilon 0.05 --threads 2 " + options);
    EXPECT_EQ(result.status, 0) << result.output;
    return result.output;
}

// The radiosity solver's statistic `key` as the bake prints it ("  radiosity KEY: VALUE").
double statistic(const std::string& output, const std::string& key) {
    const size_t at = output.find("radiosity " + key + ": ");
    EXPECT_NE(at, std::string::npos) << key << " in " << output;
    return at == std::string::npos ? 0.0 : std::stod(output.substr(at + key.size() + 12));
}

TEST(BakeCommand, CornellBoxGivesALoadableModel) {
    TempDir dir("bake-cli");
    const std::string out = dir.file("cornell.glb");
    const CliResult result =
        runPenumbra("bake " + kCornellBox + " -o " + out +
                    " --epsilon 0.05 --min-element-area 0.002 --threads 2");  // about 0.5 s
    ASSERT_EQ(result.status, 0) << result.output;
    EXPECT_NE(result.output.find("exposure"), std::string::npos) << result.output;
    // The expected error, at every point drawn (the box's surfaces are covered nowhere but under
    // its blocks, where a point is drawn again).
    EXPECT_NE(result.output.find("expected error, at 256 points"), std::string::npos)
        << result.output;
    const SceneDescription baked = loadGltf(out);
    const SceneDescription input = loadGltf(kCornellBox);
    EXPECT_EQ(baked.meshes.size(), input.meshes.size());  // the box has no transmissive meshes
    EXPECT_EQ(baked.report.degenerateTriangles, 0u);
    // Same place: the bounds of the geometry in the file's frame agree.
    const auto bounds = [](const SceneDescription& d) {
        DVec3 lo(INFINITY), hi(-INFINITY);
        for (const Mesh& m : d.meshes) {
            for (const Vec3& p : m.positions) {
                lo = glm::min(lo, d.origin + DVec3(p));
                hi = glm::max(hi, d.origin + DVec3(p));
            }
        }
        return std::pair(lo, hi);
    };
    const auto [lo, hi] = bounds(baked);
    const auto [inputLo, inputHi] = bounds(input);
    EXPECT_LT(glm::length(lo - inputLo), 1e-5);
    EXPECT_LT(glm::length(hi - inputHi), 1e-5);
}

// The bake carries the solution's light through the scene's mirror (the radiosity pass's
// specular transfer) unless told not to: in the room under a mirror ceiling, the light the floor
// and walls send into the mirror comes back to them (tests/passes/specular_transfer_test.cpp
// measures it against the path tracer), and the solver's statistics say how much.
TEST(BakeCommand, CarriesTheLightThroughTheMirrorUnlessToldNot) {
    TempDir dir("bake-cli-transfer");
    const auto bake = [&](const std::string& options) {
        return bakeRoom(
            dir, [](GltfBuilder& scene) { addMirrorCeilingRoom(scene); }, options);
    };
    const std::string with = bake("");
    const std::string without = bake("--no-specular-transfer");
    EXPECT_GE(statistic(with, "specular_transfer_rounds"), 1.0);
    EXPECT_EQ(statistic(without, "specular_transfer_rounds"), 0.0);
    // The mirror sends back most of what the floor and walls send it (reflectance 0.95): the
    // indirect flux grows by a large part (measured 1.67 times: 15.8 lm against 9.4 lm).
    std::printf("indirect flux with the transfer %.4g lm, without %.4g lm\n",
                statistic(with, "indirect_flux_lm"), statistic(without, "indirect_flux_lm"));
    EXPECT_GT(statistic(with, "indirect_flux_lm"), 1.3 * statistic(without, "indirect_flux_lm"));
}

// The bake takes the lights' caustic photons unless told not to: in the room lit mostly through
// a mirror (a lamp facing up at it), most of the light reaches the floor through the mirror
// (L S D), which the solution's links cannot carry; the photons bring it (the statistics'
// deposited flux) and the reflected flux grows with it.
TEST(BakeCommand, TakesTheCausticPhotonsUnlessToldNot) {
    TempDir dir("bake-cli-caustics");
    const auto bake = [&](const std::string& options) {
        return bakeRoom(dir, addMirrorRoom, options);
    };
    const std::string with = bake("");
    const std::string without = bake("--no-caustics");
    const double reflected =
        statistic(with, "direct_flux_lm") + statistic(with, "indirect_flux_lm");
    const double reflectedWithout =
        statistic(without, "direct_flux_lm") + statistic(without, "indirect_flux_lm");
    std::printf("deposited %.4g lm; reflected flux with the photons %.4g lm, without %.4g lm\n",
                statistic(with, "deposited_flux_lm"), reflected, reflectedWithout);
    EXPECT_GT(statistic(with, "deposited_photons"), 0.0);
    EXPECT_EQ(statistic(without, "deposited_photons"), 0.0);
    // The mirror catches 86 % of the lamp's light (tests/passes/indirect_caustics_test.cpp):
    // without the photons most of the room's light is missing (measured: 9.5 lm against 1.9 lm).
    EXPECT_GT(reflected, 2.0 * reflectedWithout);
}

TEST(BakeCommand, RefusesABadExtensionAndWritesNothing) {
    TempDir dir("bake-cli-refuses");
    const CliResult result = runPenumbra("bake " + kCornellBox + " -o " + dir.file("lit.obj"));
    EXPECT_EQ(result.status, 2) << result.output;
    EXPECT_NE(result.output.find("lit.obj"), std::string::npos) << result.output;
    EXPECT_NE(result.output.find(".glb"), std::string::npos) << result.output;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.file("")), fs::directory_iterator()), 0);

    const CliResult epsilon =
        runPenumbra("bake " + kCornellBox + " -o " + dir.file("lit.glb") + " --epsilon -1");
    EXPECT_EQ(epsilon.status, 2) << epsilon.output;
    EXPECT_NE(epsilon.output.find("epsilon"), std::string::npos) << epsilon.output;
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.file("")), fs::directory_iterator()), 0);
}

}  // namespace
}  // namespace penumbra::test
