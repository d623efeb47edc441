#include "radiosity/cluster_tree.h"

#include "radiosity/radiosity_mesh.h"

#include <algorithm>

namespace penumbra {

ClusterTree::ClusterTree(const RadiosityMesh& mesh) {
    const int patches = static_cast<int>(mesh.patchCount());
    if (patches == 0)
        return;
    std::vector<Vec3> centroids(static_cast<size_t>(patches));
    order_.resize(static_cast<size_t>(patches));
    for (int p = 0; p < patches; ++p) {
        centroids[static_cast<size_t>(p)] = mesh.centroid(p);
        order_[static_cast<size_t>(p)] = p;
    }
    // A binary tree over n patches with leaves of up to kLeafPatches has fewer than 2n nodes.
    clusters_.reserve(2 * static_cast<size_t>(patches));
    build(mesh, centroids, 0, patches);
    cumulative_.resize(order_.size() + 1, 0.0);
    for (size_t i = 0; i < order_.size(); ++i)
        cumulative_[i + 1] = cumulative_[i] + mesh.area(order_[i]);
}

// Median split along the longest axis of the centroids' bounds (a balanced tree, so that the
// refinement's descent from the root is O(log n) deep). The sphere is centred on the box of the
// corners and reaches the farthest corner.
int ClusterTree::build(const RadiosityMesh& mesh, std::vector<Vec3>& centroids, int first,
                       int count) {
    const int id = static_cast<int>(clusters_.size());
    clusters_.emplace_back();
    Bounds3 box, centres;
    double area = 0.0;
    bool emits = false;
    Vec3 weightedNormal(0.0f);
    for (int i = first; i < first + count; ++i) {
        const int p = order_[static_cast<size_t>(i)];
        for (const Vec3& c : mesh.corners(p))
            box.extend(c);
        centres.extend(centroids[static_cast<size_t>(p)]);
        area += 2.0 * mesh.area(p);
        emits = emits || maxComponent(mesh.Le(p)) > 0.0f;
        weightedNormal += mesh.area(p) * mesh.normal(p);
    }
    Cluster cluster;
    cluster.center = box.center();
    for (int i = first; i < first + count; ++i) {
        for (const Vec3& c : mesh.corners(order_[static_cast<size_t>(i)]))
            cluster.radius = glm::max(cluster.radius, glm::distance(c, cluster.center));
    }
    cluster.area = area;
    cluster.emits = emits;
    cluster.flatness =
        area > 0.0 ? glm::length(weightedNormal) / static_cast<float>(0.5 * area) : 0.0f;
    cluster.first = first;
    cluster.count = count;
    if (count > kLeafPatches) {
        const Vec3 extent = centres.diagonal();
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        const int half = count / 2;
        const auto begin = order_.begin() + first;
        std::nth_element(begin, begin + half, begin + count, [&](int a, int b) {
            return centroids[static_cast<size_t>(a)][axis] <
                   centroids[static_cast<size_t>(b)][axis];
        });
        cluster.children[0] = build(mesh, centroids, first, half);
        cluster.children[1] = build(mesh, centroids, first + half, count - half);
    }
    clusters_[static_cast<size_t>(id)] = cluster;
    return id;
}

std::span<const int> ClusterTree::patches(int cluster) const {
    const Cluster& c = (*this)[cluster];
    return std::span<const int>(order_).subspan(static_cast<size_t>(c.first),
                                                static_cast<size_t>(c.count));
}

int ClusterTree::samplePatch(int cluster, float& u) const {
    const Cluster& c = (*this)[cluster];
    const double lo = cumulative_[static_cast<size_t>(c.first)];
    const double hi = cumulative_[static_cast<size_t>(c.first + c.count)];
    const double target = lo + static_cast<double>(u) * (hi - lo);
    // The last patch whose interval starts at or before the target.
    const auto begin = cumulative_.begin() + c.first;
    auto it = std::upper_bound(begin + 1, begin + c.count + 1, target) - 1;
    const size_t i = static_cast<size_t>(it - cumulative_.begin());
    const double width = cumulative_[i + 1] - cumulative_[i];
    u = width > 0.0
            ? static_cast<float>(std::clamp((target - cumulative_[i]) / width, 0.0, 0x1.fffffep-1))
            : 0.0f;
    return order_[i];
}

}  // namespace penumbra
