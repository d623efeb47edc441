#include "core/tangents.h"

#include <cmath>

namespace penumbra {

std::vector<Vec3> vertexNormals(std::span<const Vec3> positions,
                                std::span<const glm::uvec3> triangles) {
    std::vector<Vec3> sum(positions.size(), Vec3(0.0f));
    for (const glm::uvec3& t : triangles) {
        // The unnormalised cross product weights each face by twice its area.
        const Vec3 n = glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]);
        for (int k = 0; k < 3; ++k)
            sum[t[k]] += n;
    }
    for (Vec3& n : sum) {
        const float len = glm::length(n);
        n = len > 0.0f && std::isfinite(len) ? n / len : Vec3(0.0f, 0.0f, 1.0f);
    }
    return sum;
}

std::vector<Vec4> computeTangents(std::span<const Vec3> positions, std::span<const Vec3> normals,
                                  std::span<const Vec2> uvs,
                                  std::span<const glm::uvec3> triangles) {
    const std::vector<Vec3> flatNormals =
        normals.empty() ? vertexNormals(positions, triangles) : std::vector<Vec3>();
    const std::span<const Vec3> n = normals.empty() ? std::span<const Vec3>(flatNormals) : normals;

    // Lengyel 2001: solve [e1 e2] = [dP/du dP/dv] [[s1 s2] [t1 t2]] per triangle and accumulate
    // dP/du (sdir) and dP/dv (tdir) on its vertices.
    std::vector<Vec3> dpdu(positions.size(), Vec3(0.0f)), dpdv(positions.size(), Vec3(0.0f));
    if (!uvs.empty()) {
        for (const glm::uvec3& t : triangles) {
            const Vec3 e1 = positions[t.y] - positions[t.x], e2 = positions[t.z] - positions[t.x];
            const Vec2 d1 = uvs[t.y] - uvs[t.x], d2 = uvs[t.z] - uvs[t.x];
            const float det = d1.x * d2.y - d2.x * d1.y;
            // Zero UV area: this triangle says nothing about the texture's orientation.
            if (!(std::abs(det) > 1e-20f))
                continue;
            const float r = 1.0f / det;
            const Vec3 sdir = (d2.y * e1 - d1.y * e2) * r;
            const Vec3 tdir = (d1.x * e2 - d2.x * e1) * r;
            if (!isFinite(sdir) || !isFinite(tdir))
                continue;
            for (int k = 0; k < 3; ++k) {
                dpdu[t[k]] += sdir;
                dpdv[t[k]] += tdir;
            }
        }
    }

    std::vector<Vec4> tangents(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        // Gram-Schmidt against the normal; Frame falls back to an arbitrary orthonormal tangent
        // when dP/du is zero (degenerate or missing UVs) or parallel to the normal.
        const Frame frame = Frame::fromNormalTangent(n[i], dpdu[i]);
        // glTF's bitangent cross(n, t) * w must point along -dP/dv: v grows downwards in glTF
        // texture space while normal maps store +Y upwards.
        const float w = glm::dot(glm::cross(n[i], frame.s), dpdv[i]) > 0.0f ? -1.0f : 1.0f;
        tangents[i] = Vec4(frame.s, w);
    }
    return tangents;
}

}  // namespace penumbra
