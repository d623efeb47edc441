// glTF mesh primitives to triangle meshes: topology conversion, degenerate triangles, normals,
// tangents, and the placement of a primitive by a node's global transform.
#include "core/gltf_detail.h"
#include "core/tangents.h"

#include <cmath>
#include <numeric>

namespace penumbra::gltf {
namespace {

// Accessor index of a vertex attribute, or -1.
int attribute(const tinygltf::Primitive& prim, const char* name) {
    const auto it = prim.attributes.find(name);
    return it == prim.attributes.end() ? -1 : it->second;
}

// NaN and infinities are forbidden in accessor data (3.6.2.2).
template <typename V>
void requireFinite(const Context& ctx, int accessor, const std::vector<V>& values,
                   const char* semantic) {
    for (size_t i = 0; i < values.size(); ++i) {
        for (int c = 0; c < V::length(); ++c) {
            if (!std::isfinite(values[i][c])) {
                ctx.fail(at("accessors", accessor),
                         std::string(semantic) + " element " + std::to_string(i) +
                             " has a non-finite component " + std::to_string(values[i][c]) +
                             "; NaN and infinities are forbidden (3.6.2.2)");
            }
        }
    }
}

// The primitive's vertex indices: its indices accessor, or 0 .. count-1 when it has none
// (3.7.2.1). Every index must be below the vertex count and must not be the primitive-restart
// value, the largest value of the component type (3.7.2.1).
std::vector<uint32_t> vertexIndices(const Context& ctx, const tinygltf::Primitive& prim,
                                    size_t vertexCount, const std::string& p) {
    if (prim.indices < 0) {
        std::vector<uint32_t> v(vertexCount);
        std::iota(v.begin(), v.end(), 0u);
        return v;
    }
    std::vector<uint32_t> v = readIndices(ctx, prim.indices);
    const int type = ctx.model.accessors[prim.indices].componentType;
    const uint32_t restart = type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 0xffu
                             : type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 0xffffu
                                                                              : 0xffffffffu;
    for (const uint32_t i : v) {
        if (i == restart) {
            ctx.fail(p + "/indices", "contains the primitive-restart value " +
                                         std::to_string(restart) + " (forbidden by 3.7.2.1)");
        }
        if (i >= vertexCount) {
            ctx.fail(p + "/indices", "index " + std::to_string(i) + " is past the vertex count " +
                                         std::to_string(vertexCount));
        }
    }
    return v;
}

// Triangles of a triangle-based topology, with the equations of 3.7.2.1 ("Topology types").
std::vector<glm::uvec3> assemble(const Context& ctx, const std::vector<uint32_t>& v, int mode,
                                 const std::string& p) {
    const size_t n = v.size();
    std::vector<glm::uvec3> triangles;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (n == 0 || n % 3) {
            ctx.fail(p,
                     std::to_string(n) + " vertex indices do not make whole triangles (3.7.2.1)");
        }
        triangles.resize(n / 3);
        for (size_t i = 0; i < n / 3; ++i)
            triangles[i] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
        return triangles;
    }
    if (n < 3)
        ctx.fail(p, "a strip or fan needs at least 3 vertex indices (3.7.2.1)");
    triangles.resize(n - 2);
    for (size_t i = 0; i + 2 < n; ++i) {
        // Strips: {v_i, v_i+(1+i%2), v_i+(2-i%2)} keeps every triangle counter-clockwise.
        // Fans: {v_i+1, v_i+2, v_0}.
        triangles[i] = mode == TINYGLTF_MODE_TRIANGLE_STRIP
                           ? glm::uvec3(v[i], v[i + 1 + i % 2], v[i + 2 - i % 2])
                           : glm::uvec3(v[i + 1], v[i + 2], v[0]);
    }
    return triangles;
}

// Removes triangles that repeat a vertex or have zero area: |e1 x e2| <= 1e-12 |e1| |e2|, i.e.
// the sine of the angle between the edges vanishes (in double, so only truly collinear or
// coincident vertices count). Returns how many were removed.
size_t dropDegenerate(std::vector<glm::uvec3>& triangles, const std::vector<Vec3>& positions) {
    const size_t before = triangles.size();
    std::erase_if(triangles, [&](const glm::uvec3& t) {
        if (t.x == t.y || t.y == t.z || t.z == t.x)
            return true;
        const glm::dvec3 p0(positions[t.x]);
        const glm::dvec3 e1 = glm::dvec3(positions[t.y]) - p0;
        const glm::dvec3 e2 = glm::dvec3(positions[t.z]) - p0;
        return glm::length(glm::cross(e1, e2)) <= 1e-12 * glm::length(e1) * glm::length(e2);
    });
    return before - triangles.size();
}

// NORMAL, normalised. Normals that are NaN, infinite or zero break the "normalized XYZ" rule
// (3.7.2.1); rather than reject a file for them they are replaced by the vertex's geometric
// normal (area-weighted over its triangles), with a warning.
void readNormals(const Context& ctx, int accessor, Mesh& mesh, const std::string& p) {
    mesh.normals = readVec3(ctx, accessor);
    std::vector<Vec3> geometric;
    size_t repaired = 0;
    for (size_t i = 0; i < mesh.normals.size(); ++i) {
        const float len = glm::length(mesh.normals[i]);
        if (len > 0.0f && std::isfinite(len)) {
            mesh.normals[i] /= len;
            continue;
        }
        if (geometric.empty())
            geometric = vertexNormals(mesh.positions, mesh.triangles);
        mesh.normals[i] = geometric[i];
        ++repaired;
    }
    if (repaired > 0) {
        ctx.warn(p + "/attributes/NORMAL",
                 std::to_string(repaired) +
                     " normals are NaN, infinite or zero; replaced by the geometric normal");
    }
}

// Tangents for a normal-mapped material: TANGENT when given (3.7.2.1: handedness is the sign
// of w), generated otherwise from the texture coordinates of the normal texture.
void addTangents(const Context& ctx, const tinygltf::Primitive& prim, const Material& material,
                 Mesh& mesh, const std::string& p) {
    const int given = attribute(prim, "TANGENT");
    // Without NORMAL, "the provided tangents (if present) MUST be ignored" (3.7.2.1).
    if (given >= 0 && !mesh.normals.empty()) {
        mesh.tangents = readVec4(ctx, given);
        requireFinite(ctx, given, mesh.tangents, "TANGENT");
        for (size_t i = 0; i < mesh.tangents.size(); ++i) {
            const Frame f = Frame::fromNormalTangent(mesh.normals[i], Vec3(mesh.tangents[i]));
            mesh.tangents[i] = Vec4(f.s, mesh.tangents[i].w < 0.0f ? -1.0f : 1.0f);
        }
        return;
    }
    // The tangent frame must follow the coordinates the normal texture is sampled with, so
    // KHR_texture_transform is applied before differentiating.
    const TextureRef& ref = material.normalTexture;
    std::vector<Vec2> uvs = ref.texCoord < 2 ? mesh.uvs[ref.texCoord] : std::vector<Vec2>();
    for (Vec2& uv : uvs)
        uv = ref.transform.apply(uv);
    if (uvs.empty()) {
        ctx.warn(p, "no TEXCOORD_" + std::to_string(ref.texCoord) +
                        " for the material's normal texture: arbitrary tangents");
    }
    mesh.tangents = computeTangents(mesh.positions, mesh.normals, uvs, mesh.triangles);
}

}  // namespace

std::optional<Mesh> readPrimitive(const Context& ctx, int meshIndex, int primIndex,
                                  std::span<const Material> materials) {
    const tinygltf::Mesh& gm = ctx.model.meshes[meshIndex];
    const tinygltf::Primitive& prim = gm.primitives[primIndex];
    const std::string p = at("meshes", meshIndex) + "/primitives/" + std::to_string(primIndex);
    if (prim.mode < TINYGLTF_MODE_TRIANGLES) {
        ctx.warn(p, "points and lines are not rendered; primitive skipped");
        return std::nullopt;
    }
    // Without positions a client "SHOULD skip primitive's rendering" (3.7.2.1).
    const int position = attribute(prim, "POSITION");
    if (position < 0) {
        ctx.warn(p, "no POSITION attribute; primitive skipped");
        return std::nullopt;
    }
    if (!prim.targets.empty())
        ctx.warn(p, "morph targets are not supported; base shape used");

    Mesh mesh;
    mesh.name =
        (gm.name.empty() ? std::to_string(meshIndex) : gm.name) + "/" + std::to_string(primIndex);
    mesh.source = p;
    mesh.material = prim.material;
    mesh.positions = readVec3(ctx, position);
    requireFinite(ctx, position, mesh.positions, "POSITION");

    mesh.triangles =
        assemble(ctx, vertexIndices(ctx, prim, mesh.positions.size(), p), prim.mode, p);
    if (const size_t dropped = dropDegenerate(mesh.triangles, mesh.positions)) {
        ctx.report.degenerateTriangles += dropped;
        ctx.warn(p, std::to_string(dropped) + " degenerate triangles dropped (zero area or a " +
                        "repeated vertex; 3.7.2.1)");
    }

    if (const int normal = attribute(prim, "NORMAL"); normal >= 0) {
        readNormals(ctx, normal, mesh, p);
    }
    for (int set = 0; set < 2; ++set) {
        const int uv = attribute(prim, set == 0 ? "TEXCOORD_0" : "TEXCOORD_1");
        if (uv < 0)
            continue;
        mesh.uvs[set] = readVec2(ctx, uv);
        requireFinite(ctx, uv, mesh.uvs[set], set == 0 ? "TEXCOORD_0" : "TEXCOORD_1");
    }
    if (prim.material >= 0 && materials[prim.material].normalTexture.valid()) {
        addTangents(ctx, prim, materials[prim.material], mesh, p);
    }
    return mesh;
}

Mesh instantiate(const Mesh& local, const glm::dmat4& world) {
    Mesh mesh = local;
    const glm::dmat3 linear(world);
    const Mat3 normalMatrix(glm::transpose(glm::inverse(linear)));
    const Mat3 tangentMatrix(linear);
    const float handedness = glm::determinant(linear) < 0.0 ? -1.0f : 1.0f;
    // In double, so that a far-away node translation and the rebasing that undoes it
    // (SceneFlattener::flatten) cancel before the result is rounded to float.
    for (Vec3& p : mesh.positions)
        p = Vec3(world * glm::dvec4(glm::dvec3(p), 1.0));
    for (Vec3& n : mesh.normals)
        n = glm::normalize(normalMatrix * n);
    for (Vec4& t : mesh.tangents)
        t = Vec4(glm::normalize(tangentMatrix * Vec3(t)), t.w * handedness);
    // A mirroring transform turns counter-clockwise triangles clockwise (3.7.4); swapping two
    // vertices restores counter-clockwise = front.
    if (handedness < 0.0f) {
        for (glm::uvec3& t : mesh.triangles)
            std::swap(t.y, t.z);
    }
    return mesh;
}

}  // namespace penumbra::gltf
