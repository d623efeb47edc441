#include "radiosity/leaf_corner_values.h"

#include <algorithm>
#include <unordered_map>

namespace penumbra {

namespace {

// Whether two leaves lie in one plane: a coarse leaf's values along its edge are those of its
// own plane, not of a face meeting it at a crease.
bool coplanar(const RadiosityMesh& mesh, int a, int b) {
    return glm::dot(mesh.normal(a), mesh.normal(b)) > 0.9999f;
}

}  // namespace

void LeafCornerValues::inheritSplit(int parent, int firstChild) {
    values_.resize(
        std::max(values_.size(), static_cast<size_t>(firstChild + RadiosityMesh::kChildren)));
    const std::array<Color, 6> v = values_[static_cast<size_t>(parent)];
    for (size_t side = 0; side < 2; ++side) {
        const size_t o = 3 * side;
        // The parent's corners c0 c1 c2 and edge midpoints m01 m12 m20.
        const std::array<Color, 6> points = {v[o],
                                             v[o + 1],
                                             v[o + 2],
                                             0.5f * (v[o] + v[o + 1]),
                                             0.5f * (v[o + 1] + v[o + 2]),
                                             0.5f * (v[o + 2] + v[o])};
        for (int k = 0; k < RadiosityMesh::kChildren; ++k)
            for (size_t j = 0; j < 3; ++j)
                values_[static_cast<size_t>(firstChild + k)][o + j] =
                    points[static_cast<size_t>(RadiosityMesh::kChildCorners[k][j])];
    }
}

void LeafCornerValues::anchorTVertices(const RadiosityMesh& mesh, const SideShows& shows) {
    std::vector<int> leaves = mesh.leafElements();
    std::unordered_multimap<uint32_t, std::pair<int, size_t>> cornersAt;  // vertex -> (leaf, k)
    for (const int e : leaves)
        for (size_t k = 0; k < 3; ++k)
            cornersAt.emplace(mesh.vertices(e)[k], std::make_pair(e, k));
    // Coarse first: a leaf's own corners are anchored before it anchors those on its edges.
    std::stable_sort(leaves.begin(), leaves.end(),
                     [&](int a, int b) { return mesh.area(a) > mesh.area(b); });
    for (const int e : leaves) {
        const std::vector<uint32_t> ring = mesh.leafBoundary(e);
        if (ring.size() == 3)
            continue;
        const std::array<uint32_t, 3>& v = mesh.vertices(e);
        // The ring runs counter-clockwise from corner 0; corner c's edge ends at corner c + 1.
        size_t edge = 0;
        for (const uint32_t t : ring) {
            if (t == v[(edge + 1) % 3]) {
                ++edge;
                continue;
            }
            if (t == v[edge] || mesh.edgeOnCut(e, edge))
                continue;  // across a cut's line the light may step: no continuity there
            const Vec3 a = mesh.position(v[edge]), b = mesh.position(v[(edge + 1) % 3]);
            const float s = glm::dot(mesh.position(t) - a, b - a) / glm::dot(b - a, b - a);
            for (const bool front : {true, false}) {
                if (!shows(e, front))
                    continue;
                const Color value =
                    (1.0f - s) * at(e, front, edge) + s * at(e, front, (edge + 1) % 3);
                const auto [first, last] = cornersAt.equal_range(t);
                for (auto it = first; it != last; ++it)
                    if (coplanar(mesh, e, it->second.first))
                        at(it->second.first, front, it->second.second) = value;
            }
        }
    }
}

}  // namespace penumbra
