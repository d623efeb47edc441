// Per-vertex tangent frames for normal mapping, for meshes that come without them.
#pragma once

#include "core/math.h"

#include <span>
#include <vector>

namespace penumbra {

// Per-vertex tangents from positions and texture coordinates, after E. Lengyel, "Computing Tangent
// Space Basis Vectors for an Arbitrary Mesh", Terathon Software 3D Graphics Library, 2001: each
// triangle's dP/du and dP/dv are accumulated on its vertices, then Gram-Schmidt makes the
// tangent orthogonal to the vertex normal and the handedness is the sign of the bitangent.
//
// Returns one tangent per vertex: xyz unit and orthogonal to the normal, w = +1 or -1 such that
// the glTF bitangent cross(normal, tangent.xyz) * w points towards decreasing v (glTF texture
// coordinates have their origin at the top-left, glTF 2.0 3.8.3, and normal maps are authored
// with +Y up). `normals` may be empty (flat-shaded mesh): the area-weighted vertex normal is used
// instead. Where the texture coordinates are degenerate (zero UV area around a vertex) or `uvs`
// is empty, an arbitrary tangent orthogonal to the normal is returned with w = +1.
std::vector<Vec4> computeTangents(std::span<const Vec3> positions, std::span<const Vec3> normals,
                                  std::span<const Vec2> uvs, std::span<const glm::uvec3> triangles);

// Area-weighted vertex normals (the sum of the unnormalised face normals around each vertex,
// normalised); (0, 0, 1) for a vertex that no triangle of non-zero area uses.
std::vector<Vec3> vertexNormals(std::span<const Vec3> positions,
                                std::span<const glm::uvec3> triangles);

}  // namespace penumbra
