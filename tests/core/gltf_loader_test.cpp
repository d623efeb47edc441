// The glTF loader on small files written by the tests (geometry, transforms, materials, lights,
// cameras, and one file per kind of specification violation), and on every real scene under
// ../shared/scenes when that directory exists.
#include "core/gltf_loader.h"

#include "core/errors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

std::string base64(const std::vector<uint8_t>& bytes) {
    static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const uint32_t b0 = bytes[i];
        const uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0;
        const uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
        const uint32_t v = b0 << 16 | b1 << 8 | b2;
        out += kDigits[v >> 18 & 63];
        out += kDigits[v >> 12 & 63];
        out += i + 1 < bytes.size() ? kDigits[v >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? kDigits[v & 63] : '=';
    }
    return out;
}

// 2x2 RGBA 8-bit PNG, rows top to bottom: (128, 64, 255, 200) (0, 0, 0, 255) /
// (255, 255, 255, 0) (10, 20, 30, 40).
constexpr const char* kPng8 =
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAGklEQVR42mNocPh/"
    "goGB4T/D////GbhE5DQARhwG6Loa+UUAAAAASUVORK5CYII=";
// 1x1 16-bit grey PNG of value 0x8000.
constexpr const char* kPng16 =
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABEAAAAABq7kcWAAAAC0lEQVR42mNoYAAAAQMAga3o"
    "snQAAAAASUVORK5CYII=";

// Builds a glTF file around one binary buffer: each add* call appends a buffer view holding
// the values and an accessor reading them (accessor i uses buffer view i). The JSON texts of
// views and accessors are public so that a test can break them.
struct GltfBuilder {
    std::vector<uint8_t> bin;
    std::vector<std::string> bufferViews, accessors;

    int addView(const void* data, size_t size, const std::string& extra = "") {
        bin.resize((bin.size() + 3) / 4 * 4, 0);  // keep every view 4-byte aligned
        const size_t offset = bin.size();
        bin.resize(offset + size);
        std::memcpy(bin.data() + offset, data, size);
        bufferViews.push_back(R"({"buffer":0,"byteOffset":)" + std::to_string(offset) +
                              R"(,"byteLength":)" + std::to_string(size) + extra + "}");
        return static_cast<int>(bufferViews.size()) - 1;
    }
    int addAccessor(int view, int componentType, size_t count, const char* type,
                    const std::string& extra = "") {
        accessors.push_back(R"({"bufferView":)" + std::to_string(view) + R"(,"componentType":)" +
                            std::to_string(componentType) + R"(,"count":)" + std::to_string(count) +
                            R"(,"type":")" + type + "\"" + extra + "}");
        return static_cast<int>(accessors.size()) - 1;
    }
    int addFloats(const std::vector<float>& v, const char* type, int components) {
        return addAccessor(addView(v.data(), v.size() * 4), 5126, v.size() / components, type);
    }
    int addIndices(const std::vector<uint16_t>& v) {
        return addAccessor(addView(v.data(), v.size() * 2), 5123, v.size(), "SCALAR");
    }

    // The whole file; `rest` holds the other top-level properties. For GLB the buffer has no
    // uri (it is the BIN chunk, 3.6.1.2).
    std::string json(const std::string& rest, bool glb = false) const {
        std::string buffer = R"({"byteLength":)" + std::to_string(bin.size());
        if (!glb)
            buffer += R"(,"uri":"data:application/octet-stream;base64,)" + base64(bin) + "\"";
        return R"({"asset":{"version":"2.0"},"buffers":[)" + buffer + "}]," + R"("bufferViews":[)" +
               join(bufferViews) + R"(],"accessors":[)" + join(accessors) + "]" +
               (rest.empty() ? "" : "," + rest) + "}";
    }

    // A GLB container (chapter 4): header, JSON chunk padded with spaces, BIN chunk padded with
    // zeros.
    std::vector<uint8_t> glb(const std::string& rest) const {
        std::string text = json(rest, true);
        text.resize((text.size() + 3) / 4 * 4, ' ');
        std::vector<uint8_t> body = bin;
        body.resize((body.size() + 3) / 4 * 4, 0);
        std::vector<uint8_t> out;
        const auto u32 = [&out](uint32_t v) {
            for (int k = 0; k < 4; ++k)
                out.push_back(static_cast<uint8_t>(v >> (8 * k)));
        };
        u32(0x46546C67);
        u32(2);
        u32(static_cast<uint32_t>(12 + 8 + text.size() + 8 + body.size()));
        u32(static_cast<uint32_t>(text.size()));
        u32(0x4E4F534A);
        out.insert(out.end(), text.begin(), text.end());
        u32(static_cast<uint32_t>(body.size()));
        u32(0x004E4942);
        out.insert(out.end(), body.begin(), body.end());
        return out;
    }

    static std::string join(const std::vector<std::string>& parts) {
        std::string out;
        for (const std::string& p : parts)
            out += (out.empty() ? "" : ",") + p;
        return out;
    }
};

// One scene with one node placing mesh 0 made of the given primitives.
std::string oneMesh(const std::string& primitives, const std::string& nodeExtra = "") {
    return R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0)" + nodeExtra +
           R"(}],"meshes":[{"primitives":[)" + primitives + "]}]";
}

// The counter-clockwise unit right triangle in the z = 0 plane, front face +Z.
const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
const std::vector<float> kUpNormals = {0, 0, 1, 0, 0, 1, 0, 0, 1};

Vec3 faceNormal(const Mesh& m, size_t t) {
    const glm::uvec3 tri = m.triangles[t];
    return glm::cross(m.positions[tri.y] - m.positions[tri.x],
                      m.positions[tri.z] - m.positions[tri.x]);
}

// A loaded position in the file's coordinates: the loader rebases the world on the centre of
// the geometry (SceneDescription::origin).
Vec3 inFile(const SceneDescription& d, const Vec3& p) {
    return Vec3(glm::dvec3(p) + d.origin);
}

void expectNear(const Vec3& a, const Vec3& b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

class GltfLoaderTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
        dir_ = fs::temp_directory_path() /
               ("penumbra_gltf_" + test + "_" +
                std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string write(const std::string& name, const std::string& text) const {
        const fs::path path = dir_ / name;
        std::ofstream(path, std::ios::binary) << text;
        return path.string();
    }

    // Loading `path` must throw a SceneError naming the file, the JSON pointer and `words`.
    static void expectError(const std::string& path, const std::string& pointer,
                            const std::string& words, int scene = -1) {
        try {
            loadGltf(path, scene);
            ADD_FAILURE() << "no error for " << path;
        } catch (const SceneError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find(fs::path(path).filename().string()), std::string::npos)
                << message;
            EXPECT_NE(message.find(pointer), std::string::npos) << message;
            EXPECT_NE(message.find(words), std::string::npos) << message;
        }
    }

    // The single triangle with normals, through `nodeExtra` node properties.
    std::string triangleFile(const std::string& name, const std::string& nodeExtra = "") const {
        GltfBuilder b;
        b.addFloats(kTriangle, "VEC3", 3);
        b.addFloats(kUpNormals, "VEC3", 3);
        b.addIndices({0, 1, 2});
        return write(name, b.json(oneMesh(R"({"attributes":{"POSITION":0,"NORMAL":1},"indices":2})",
                                          nodeExtra)));
    }

    fs::path dir_;
};

// ---- valid geometry ----------------------------------------------------------------------------

TEST_F(GltfLoaderTest, ValidTriangleKeepsPositionsWindingAndNormals) {
    const SceneDescription d = loadGltf(triangleFile("triangle.gltf"));
    ASSERT_EQ(d.meshes.size(), 1u);
    const Mesh& m = d.meshes[0];
    EXPECT_EQ(m.name, "0/0");
    EXPECT_EQ(m.source, "/meshes/0/primitives/0");
    ASSERT_EQ(m.positions.size(), 3u);
    expectNear(inFile(d, m.positions[1]), Vec3(1, 0, 0));
    ASSERT_EQ(m.triangles.size(), 1u);
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_GT(faceNormal(m, 0).z, 0.0f);  // counter-clockwise seen from +Z
    ASSERT_EQ(m.normals.size(), 3u);
    expectNear(m.normals[2], Vec3(0, 0, 1));
    EXPECT_TRUE(m.tangents.empty());
    EXPECT_TRUE(d.report.warnings.empty());
    EXPECT_EQ(d.report.degenerateTriangles, 0u);
}

TEST_F(GltfLoaderTest, GlbLoadsLikeGltf) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    b.addIndices({0, 1, 2});
    const std::vector<uint8_t> glb = b.glb(oneMesh(R"({"attributes":{"POSITION":0},"indices":1})"));
    const std::string path = write("triangle.glb", std::string(glb.begin(), glb.end()));
    const SceneDescription d = loadGltf(path);
    ASSERT_EQ(d.meshes.size(), 1u);
    expectNear(inFile(d, d.meshes[0].positions[2]), Vec3(0, 1, 0));
    EXPECT_TRUE(d.meshes[0].normals.empty());  // no NORMAL: flat shading
}

// Parent TRS (non-uniform scale) times child matrix, checked against world positions computed
// by hand: p_world = T * R * S * (p + (1, 0, 0)) with R = 90 degrees about +Z.
TEST_F(GltfLoaderTest, NodeHierarchyComposesParentTimesChild) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    b.addFloats(kUpNormals, "VEC3", 3);
    const float s = std::sqrt(0.5f);
    const std::string nodes =
        R"("scene":0,"scenes":[{"nodes":[0,2]}],"nodes":[)"
        R"({"translation":[1,2,3],"rotation":[0,0,)" +
        std::to_string(s) + "," + std::to_string(s) +
        R"(],"scale":[2,3,4],"children":[1]},)"
        R"({"mesh":0,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 1,0,0,1]},)"
        R"({"mesh":0,"translation":[0,0,-1]}],)"
        R"("meshes":[{"name":"tri","primitives":[{"attributes":{"POSITION":0,"NORMAL":1}}]}])";
    const SceneDescription d = loadGltf(write("hierarchy.gltf", b.json(nodes)));
    ASSERT_EQ(d.meshes.size(), 2u);  // one mesh, instanced by two nodes
    const Mesh& m = d.meshes[0];
    EXPECT_EQ(m.name, "tri/0");
    expectNear(inFile(d, m.positions[0]), Vec3(1, 4, 3));
    expectNear(inFile(d, m.positions[1]), Vec3(1, 6, 3));
    expectNear(inFile(d, m.positions[2]), Vec3(-2, 4, 3));
    expectNear(m.normals[0], Vec3(0, 0, 1));
    EXPECT_GT(faceNormal(m, 0).z, 0.0f);
    expectNear(inFile(d, d.meshes[1].positions[1]), Vec3(1, 0, -1));
}

// A mirror in z maps the front side +Z to -Z: after the winding flip the geometric normal must
// agree with the (inverse-transpose transformed) shading normal.
TEST_F(GltfLoaderTest, NegativeScaleFlipsWinding) {
    const SceneDescription d = loadGltf(triangleFile("mirror.gltf", R"(,"scale":[1,1,-1])"));
    ASSERT_EQ(d.meshes.size(), 1u);
    const Mesh& m = d.meshes[0];
    expectNear(m.normals[0], Vec3(0, 0, -1));
    EXPECT_LT(faceNormal(m, 0).z, 0.0f);
    EXPECT_GT(glm::dot(faceNormal(m, 0), m.normals[0]), 0.0f);
}

// The same quad as indexed triangles, non-indexed triangles, a strip and a fan.
TEST_F(GltfLoaderTest, TopologiesGiveTheSameSurface) {
    const std::vector<float> corners = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<float> soup = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0};
    const std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    GltfBuilder b;
    b.addFloats(corners, "VEC3", 3);   // 0
    b.addIndices({0, 1, 2, 0, 2, 3});  // 1
    b.addFloats(soup, "VEC3", 3);      // 2
    b.addFloats(strip, "VEC3", 3);     // 3
    const std::string prims = R"({"attributes":{"POSITION":0},"indices":1},)"
                              R"({"attributes":{"POSITION":2}},)"
                              R"({"attributes":{"POSITION":3},"mode":5},)"
                              R"({"attributes":{"POSITION":0},"mode":6})";
    const SceneDescription d = loadGltf(write("topologies.gltf", b.json(oneMesh(prims))));
    ASSERT_EQ(d.meshes.size(), 4u);
    for (const Mesh& m : d.meshes) {
        ASSERT_EQ(m.triangles.size(), 2u) << m.name;
        float area = 0.0f;
        for (size_t t = 0; t < 2; ++t) {
            EXPECT_GT(faceNormal(m, t).z, 0.0f) << m.name << " triangle " << t;
            area += 0.5f * glm::length(faceNormal(m, t));
        }
        EXPECT_FLOAT_EQ(area, 1.0f) << m.name;
    }
    // Indexed and non-indexed: the same triangles vertex by vertex.
    for (size_t t = 0; t < 2; ++t) {
        for (int k = 0; k < 3; ++k) {
            expectNear(d.meshes[0].positions[d.meshes[0].triangles[t][k]],
                       d.meshes[1].positions[d.meshes[1].triangles[t][k]]);
        }
    }
}

TEST_F(GltfLoaderTest, DegenerateTrianglesAreDroppedAndCounted) {
    GltfBuilder b;
    b.addFloats({0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0}, "VEC3", 3);
    // A good triangle, one repeating a vertex, one with collinear vertices.
    b.addIndices({0, 1, 2, 0, 1, 1, 0, 1, 3});
    const SceneDescription d = loadGltf(
        write("degenerate.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0},"indices":1})"))));
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.meshes[0].triangles.size(), 1u);
    EXPECT_EQ(d.report.degenerateTriangles, 2u);
    ASSERT_EQ(d.report.warnings.size(), 1u);
    EXPECT_NE(d.report.warnings[0].find("/meshes/0/primitives/0: 2 degenerate"), std::string::npos)
        << d.report.warnings[0];
}

TEST_F(GltfLoaderTest, SparseAccessorsAndNormalizedTexcoordsAreDecoded) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);  // 0
    const std::vector<uint16_t> sparseIndex = {2};
    const std::vector<float> sparseValue = {0, 2, 0};
    const int indexView = b.addView(sparseIndex.data(), 2);
    const int valueView = b.addView(sparseValue.data(), 12);
    // Accessor 1: the triangle with vertex 2 replaced by (0, 2, 0) (3.6.2.3).
    b.addAccessor(0, 5126, 3, "VEC3",
                  R"(,"sparse":{"count":1,"indices":{"bufferView":)" + std::to_string(indexView) +
                      R"(,"componentType":5123},"values":{"bufferView":)" +
                      std::to_string(valueView) + "}}");
    // Normalized unsigned bytes, padded to the 4-byte element alignment of 3.6.2.4.
    const std::vector<uint8_t> uv = {255, 0, 0, 0, 0, 128, 0, 0, 51, 255, 0, 0};
    b.addAccessor(b.addView(uv.data(), uv.size(), R"(,"byteStride":4)"), 5121, 3, "VEC2",
                  R"(,"normalized":true)");
    const SceneDescription d = loadGltf(
        write("sparse.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":1,"TEXCOORD_0":2}})"))));
    ASSERT_EQ(d.meshes.size(), 1u);
    expectNear(inFile(d, d.meshes[0].positions[2]), Vec3(0, 2, 0));
    expectNear(inFile(d, d.meshes[0].positions[1]), Vec3(1, 0, 0));
    ASSERT_EQ(d.meshes[0].uvs[0].size(), 3u);
    EXPECT_FLOAT_EQ(d.meshes[0].uvs[0][0].x, 1.0f);
    EXPECT_FLOAT_EQ(d.meshes[0].uvs[0][1].y, 128.0f / 255.0f);
    EXPECT_FLOAT_EQ(d.meshes[0].uvs[0][2].x, 0.2f);
    EXPECT_TRUE(d.meshes[0].uvs[1].empty());
}

TEST_F(GltfLoaderTest, PointsAreSkippedWithAWarning) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const SceneDescription d = loadGltf(
        write("points.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0},"mode":0})"))));
    EXPECT_TRUE(d.meshes.empty());
    ASSERT_EQ(d.report.warnings.size(), 1u);
    EXPECT_NE(d.report.warnings[0].find("/meshes/0/primitives/0"), std::string::npos);
}

// A normal-mapped quad without TANGENT: generated tangents follow dP/du, and the handedness
// makes cross(n, t) * w point along -dP/dv (glTF's v grows downwards).
TEST_F(GltfLoaderTest, TangentsAreGeneratedForNormalMaps) {
    GltfBuilder b;
    b.addFloats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, "VEC3", 3);
    b.addFloats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
    b.addFloats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 2);  // image upright on the quad
    b.addFloats({1, 1, 0, 1, 0, 0, 1, 0}, "VEC2", 2);  // mirrored in u
    b.addIndices({0, 1, 2, 0, 2, 3});
    const std::string rest =
        oneMesh(
            R"({"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":4,"material":0},)"
            R"({"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":3},"indices":4,"material":0})") +
        R"(,"materials":[{"normalTexture":{"index":0}}],"textures":[{"source":0}],)"
        R"("images":[{"uri":")" +
        std::string(kPng8) + "\"}]";
    const SceneDescription d = loadGltf(write("tangents.gltf", b.json(rest)));
    ASSERT_EQ(d.meshes.size(), 2u);
    for (const Vec4& t : d.meshes[0].tangents) {
        expectNear(Vec3(t), Vec3(1, 0, 0));
        EXPECT_EQ(t.w, 1.0f);
    }
    for (const Vec4& t : d.meshes[1].tangents) {
        expectNear(Vec3(t), Vec3(-1, 0, 0));
        EXPECT_EQ(t.w, -1.0f);
    }
}

// ---- materials and textures --------------------------------------------------------------------

TEST_F(GltfLoaderTest, TextureTransformAndColorSpaces) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string rest =
        oneMesh(R"({"attributes":{"POSITION":0},"material":0})") +
        R"(,"extensionsUsed":["KHR_texture_transform"],"materials":[{"pbrMetallicRoughness":{)"
        R"("baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":{)"
        R"("offset":[0.5,0.25],"rotation":0.3,"scale":[2,3],"texCoord":1}}},)"
        R"("metallicRoughnessTexture":{"index":0}},"emissiveTexture":{"index":1}}],)"
        R"("samplers":[{"wrapS":33071,"wrapT":33648}],)"
        R"("textures":[{"source":0,"sampler":0},{"source":1}],)"
        R"("images":[{"uri":")" +
        std::string(kPng8) + R"("},{"uri":")" + kPng16 + "\"}]";
    const SceneDescription d = loadGltf(write("texture.gltf", b.json(rest)));
    ASSERT_EQ(d.materials.size(), 1u);
    const Material& m = d.materials[0];
    const TextureRef& base = m.baseColorTexture;
    EXPECT_EQ(base.texCoord, 1);  // the extension's override
    EXPECT_FLOAT_EQ(base.transform.offset.x, 0.5f);
    EXPECT_FLOAT_EQ(base.transform.offset.y, 0.25f);
    EXPECT_FLOAT_EQ(base.transform.rotation, 0.3f);
    EXPECT_FLOAT_EQ(base.transform.scale.x, 2.0f);
    EXPECT_FLOAT_EQ(base.transform.scale.y, 3.0f);
    EXPECT_EQ(m.metallicRoughnessTexture.texCoord, 0);
    EXPECT_EQ(m.metallicRoughnessTexture.transform.rotation, 0.0f);
    // One image used as colour and as data gives two textures, plus the 16-bit emissive one.
    ASSERT_EQ(d.textures.size(), 3u);
    ASSERT_NE(base.texture, m.metallicRoughnessTexture.texture);
    const Texture& color = d.textures[base.texture];
    const Texture& data = d.textures[m.metallicRoughnessTexture.texture];
    ASSERT_EQ(color.width(), 2);
    // The centre of the top-left texel: (128, 64, 255, 200).
    const Vec4 c = color.sample(Vec2(0.25f, 0.25f));
    EXPECT_NEAR(c.r, srgbToLinear(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(c.g, srgbToLinear(64.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(c.a, 200.0f / 255.0f, 1e-6f);  // alpha stays linear
    const Vec4 l = data.sample(Vec2(0.25f, 0.25f));
    EXPECT_NEAR(l.r, 128.0f / 255.0f, 1e-6f);
    // The bottom-right texel through the sampler's wrap modes: clamp in s, mirror in t.
    EXPECT_NEAR(data.sample(Vec2(1.75f, 0.25f)).r, 0.0f, 1e-6f);
    EXPECT_NEAR(data.sample(Vec2(0.25f, 1.25f)).r, 1.0f, 1e-6f);
    const Vec4 e = d.textures[m.emissiveTexture.texture].sample(Vec2(0.5f));
    EXPECT_NEAR(e.g, srgbToLinear(32768.0f / 65535.0f), 1e-6f);
    EXPECT_EQ(d.report.extensionsUsed, std::vector<std::string>{"KHR_texture_transform"});
}

TEST_F(GltfLoaderTest, EmissiveStrengthMultipliesTheFactor) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string rest =
        oneMesh(R"({"attributes":{"POSITION":0},"material":0})") +
        R"(,"extensionsUsed":["KHR_materials_emissive_strength","KHR_materials_sheen"],)"
        R"("materials":[{"name":"lamp","emissiveFactor":[0.5,0.25,1],"extensions":{)"
        R"("KHR_materials_emissive_strength":{"emissiveStrength":4},)"
        R"("KHR_materials_sheen":{"sheenRoughnessFactor":0.5}}}])";
    const SceneDescription d = loadGltf(write("emissive.gltf", b.json(rest)));
    ASSERT_EQ(d.materials.size(), 1u);
    EXPECT_EQ(d.materials[0].name, "lamp");
    expectNear(d.materials[0].emissive, Vec3(2, 1, 4));
    EXPECT_EQ(d.report.extensionsUsed, std::vector<std::string>{"KHR_materials_emissive_strength"});
    EXPECT_EQ(d.report.extensionsIgnored, std::vector<std::string>{"KHR_materials_sheen"});
}

TEST_F(GltfLoaderTest, PrimitivesWithoutMaterialUseTheDefaultMaterial) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string rest = oneMesh(R"({"attributes":{"POSITION":0},"material":0},)"
                                     R"({"attributes":{"POSITION":0}},)"
                                     R"({"attributes":{"POSITION":0}})") +
                             R"(,"materials":[{"pbrMetallicRoughness":{"metallicFactor":0}}])";
    const SceneDescription d = loadGltf(write("default.gltf", b.json(rest)));
    ASSERT_EQ(d.meshes.size(), 3u);
    ASSERT_EQ(d.materials.size(), 2u);  // the file's material, then the default once
    EXPECT_EQ(d.meshes[0].material, 0);
    EXPECT_EQ(d.meshes[1].material, 1);
    EXPECT_EQ(d.meshes[2].material, 1);
    const Material& m = d.materials[1];
    EXPECT_EQ(m.baseColor, Color(1.0f));
    EXPECT_EQ(m.metallic, 1.0f);
    EXPECT_EQ(m.roughness, 1.0f);
    EXPECT_EQ(m.emissive, Color(0.0f));
    EXPECT_EQ(m.alphaMode, AlphaMode::Opaque);
    EXPECT_FALSE(m.doubleSided);
}

// ---- lights, cameras, extras -------------------------------------------------------------------

TEST_F(GltfLoaderTest, LightsAndCamerasArePlacedInWorldSpace) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const float s = std::sqrt(0.5f);
    const std::string q = std::to_string(s) + ",0,0," + std::to_string(s);  // 90 deg about +X
    const std::string rest =
        R"("extensionsUsed":["KHR_lights_punctual"],"extensions":{"KHR_lights_punctual":)"
        R"({"lights":[{"name":"lamp","type":"spot","color":[1,0.5,0.25],"intensity":5,)"
        R"("range":10,"spot":{"innerConeAngle":0.1,"outerConeAngle":0.5}},{"type":"point"}]}},)"
        R"("cameras":[{"type":"perspective","perspective":{"yfov":0.7,"znear":0.1,)"
        R"("aspectRatio":1.5}}],"scene":0,"scenes":[{"nodes":[0,1],"extras":{"sky":)"
        R"({"type":"uniform","radiance":[1,2,3]}}}],"nodes":[)"
        R"({"translation":[1,2,3],"rotation":[)" +
        q +
        R"(],"extensions":{"KHR_lights_punctual":{"light":0}}},)"
        R"({"camera":0,"translation":[0,1,5],"scale":[2,2,2]}])";
    const SceneDescription d = loadGltf(write("lights.gltf", b.json(rest)));
    ASSERT_EQ(d.lights.size(), 1u);
    const PunctualLightDesc& l = d.lights[0];
    EXPECT_EQ(l.name, "lamp");
    EXPECT_EQ(l.type, PunctualType::Spot);
    expectNear(inFile(d, l.position), Vec3(1, 2, 3));
    expectNear(l.direction, Vec3(0, 1, 0));  // -Z turned 90 degrees about +X
    expectNear(l.color, Vec3(1, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(l.intensity, 5.0f);
    EXPECT_FLOAT_EQ(l.range, 10.0f);
    EXPECT_FLOAT_EQ(l.innerConeAngle, 0.1f);
    EXPECT_FLOAT_EQ(l.outerConeAngle, 0.5f);
    ASSERT_EQ(d.cameras.size(), 1u);
    const CameraDesc& c = d.cameras[0];
    EXPECT_EQ(c.name, "camera 0");
    EXPECT_FLOAT_EQ(c.yfov, 0.7f);
    EXPECT_FLOAT_EQ(c.aspectRatio, 1.5f);
    EXPECT_FLOAT_EQ(c.znear, 0.1f);
    // The scale is removed: a rigid frame at the node's origin.
    expectNear(Vec3(c.cameraToWorld[0]), Vec3(1, 0, 0));
    expectNear(Vec3(c.cameraToWorld[2]), Vec3(0, 0, 1));
    expectNear(inFile(d, Vec3(c.cameraToWorld[3])), Vec3(0, 1, 5));
    EXPECT_NE(d.sceneExtrasJson.find("\"sky\""), std::string::npos) << d.sceneExtrasJson;
    EXPECT_NE(d.sceneExtrasJson.find("uniform"), std::string::npos) << d.sceneExtrasJson;
}

// ---- errors: each names the file and the JSON pointer ------------------------------------------

TEST_F(GltfLoaderTest, MissingFile) {
    expectError((dir_ / "nothere.gltf").string(), "nothere.gltf", "not found");
}

TEST_F(GltfLoaderTest, MalformedJson) {
    expectError(write("bad.gltf", R"({"asset": {"version": "2.0"}, "nodes": [ })"), "bad.gltf",
                "parse error");
}

TEST_F(GltfLoaderTest, IndexPastTheVertexCount) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    b.addIndices({0, 1, 7});
    expectError(
        write("index.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0},"indices":1})"))),
        "/meshes/0/primitives/0/indices", "index 7 is past the vertex count 3");
}

TEST_F(GltfLoaderTest, AccessorPastItsBufferView) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    b.accessors[0] = R"({"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"})";
    expectError(write("accessor.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0}})"))),
                "/accessors/0", "buffer view 0");
}

TEST_F(GltfLoaderTest, BufferViewPastItsBuffer) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    b.bufferViews[0] = R"({"buffer":0,"byteOffset":12,"byteLength":36})";
    expectError(write("view.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0}})"))),
                "/bufferViews/0", "past the end of buffer 0");
}

TEST_F(GltfLoaderTest, WrongComponentTypeForPosition) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    b.accessors[0] = R"({"bufferView":0,"componentType":5123,"count":3,"type":"VEC3"})";
    expectError(write("ctype.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0}})"))),
                "/meshes/0/primitives/0/attributes/POSITION", "unsigned short");
}

TEST_F(GltfLoaderTest, UnsupportedRequiredExtension) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string rest = oneMesh(R"({"attributes":{"POSITION":0}})") +
                             R"(,"extensionsUsed":["KHR_draco_mesh_compression"],)"
                             R"("extensionsRequired":["KHR_draco_mesh_compression"])";
    expectError(write("draco.gltf", b.json(rest)), "/extensionsRequired",
                "KHR_draco_mesh_compression");
}

// The asset's version (glTF 2.0, "Asset"): a 1.0 file, a version that is not one, a minVersion
// above the version or above 2.0 are refused at /asset; a 2.1 file without a minVersion loads.
TEST_F(GltfLoaderTest, AssetVersionsPenumbraCannotRead) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string json = b.json(oneMesh(R"({"attributes":{"POSITION":0}})"));
    const auto withAsset = [&](const std::string& asset) {
        std::string text = json;
        const std::string from = R"("asset":{"version":"2.0"})";
        text.replace(text.find(from), from.size(), R"("asset":)" + asset);
        return text;
    };
    expectError(write("v1.gltf", withAsset(R"({"version":"1.0"})")), "/asset/version",
                "penumbra reads glTF 2.0");
    expectError(write("vx.gltf", withAsset(R"({"version":"2"})")), "/asset/version",
                "not a glTF version");
    expectError(write("min.gltf", withAsset(R"({"version":"2.1","minVersion":"2.1"})")),
                "/asset/minVersion", "needs a glTF 2.1 loader");
    expectError(write("over.gltf", withAsset(R"({"version":"2.0","minVersion":"2.1"})")),
                "/asset/minVersion", "greater than the version");
    EXPECT_NO_THROW(loadGltf(write("v21.gltf", withAsset(R"({"version":"2.1"})")), -1));
    EXPECT_NO_THROW(
        loadGltf(write("min20.gltf", withAsset(R"({"version":"2.0","minVersion":"2.0"})")), -1));
}

TEST_F(GltfLoaderTest, NanPosition) {
    GltfBuilder b;
    std::vector<float> p = kTriangle;
    p[4] = std::numeric_limits<float>::quiet_NaN();
    b.addFloats(p, "VEC3", 3);
    expectError(write("nan.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0}})"))),
                "/accessors/0", "POSITION element 1");
}

TEST_F(GltfLoaderTest, MaterialIndexOutOfRange) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    expectError(
        write("material.gltf", b.json(oneMesh(R"({"attributes":{"POSITION":0},"material":3})"))),
        "/meshes/0/primitives/0/material", "index 3 is out of range");
}

TEST_F(GltfLoaderTest, NodeCycle) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string rest = R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"children":[1]},)"
                             R"({"children":[0]}],"meshes":[{"primitives":[)"
                             R"({"attributes":{"POSITION":0}}]}])";
    expectError(write("cycle.gltf", b.json(rest)), "/nodes/0/children/0", "cycle");
}

TEST_F(GltfLoaderTest, MissingImage) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string rest = oneMesh(R"({"attributes":{"POSITION":0},"material":0})") +
                             R"(,"materials":[{"emissiveTexture":{"index":0}}],)"
                             R"("textures":[{"source":0}],"images":[{"uri":"gone.png"}])";
    expectError(write("image.gltf", b.json(rest)), "/images/0", "'gone.png'");
}

TEST_F(GltfLoaderTest, BadSceneIndex) {
    expectError(triangleFile("scene.gltf"), "/scenes", "scene 4 requested", 4);
}

TEST_F(GltfLoaderTest, SpotConeAnglesOutOfOrder) {
    GltfBuilder b;
    b.addFloats(kTriangle, "VEC3", 3);
    const std::string rest = oneMesh(R"({"attributes":{"POSITION":0}})") +
                             R"(,"extensions":{"KHR_lights_punctual":{"lights":[{"type":"spot",)"
                             R"("spot":{"innerConeAngle":0.6,"outerConeAngle":0.5}}]}})";
    expectError(write("spot.gltf", b.json(rest)), "/extensions/KHR_lights_punctual/lights/0/spot",
                "innerConeAngle");
}

// ---- the real scenes ---------------------------------------------------------------------------

TEST(GltfSharedScenes, EverySceneLoadsWithTriangles) {
    const fs::path root = fs::path(PENUMBRA_SOURCE_DIR) / ".." / "shared" / "scenes";
    if (!fs::is_directory(root))
        GTEST_SKIP() << root << " does not exist";
    int loaded = 0;
    for (const fs::directory_entry& dir : fs::directory_iterator(root)) {
        if (!dir.is_directory())
            continue;
        for (const fs::directory_entry& file : fs::directory_iterator(dir.path())) {
            const std::string ext = file.path().extension().string();
            if (ext != ".gltf" && ext != ".glb")
                continue;
            SCOPED_TRACE(file.path().string());
            const auto start = std::chrono::steady_clock::now();
            SceneDescription d;
            EXPECT_NO_THROW(d = loadGltf(file.path().string())) << file.path();
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            size_t triangles = 0;
            for (const Mesh& m : d.meshes)
                triangles += m.triangles.size();
            EXPECT_GT(triangles, 0u);
            std::cout << dir.path().filename().string() << "/" << file.path().filename().string()
                      << ": " << triangles << " triangles, " << d.materials.size() << " materials, "
                      << d.textures.size() << " textures, " << d.lights.size() << " lights, "
                      << d.cameras.size() << " cameras, " << seconds << " s, "
                      << d.report.warnings.size() << " warnings\n";
            for (const std::string& name : d.report.extensionsIgnored) {
                std::cout << "    ignored extension " << name << "\n";
            }
            // A few warnings per scene; the rest are counted above.
            for (size_t i = 0; i < std::min<size_t>(d.report.warnings.size(), 3); ++i)
                std::cout << "    " << d.report.warnings[i] << "\n";
            ++loaded;
        }
    }
    EXPECT_GT(loaded, 0);
}

}  // namespace
}  // namespace penumbra
