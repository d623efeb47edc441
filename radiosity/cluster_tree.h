// A bounding-volume hierarchy of clusters over the patches of a RadiosityMesh, for hierarchical
// radiosity with clustering (Smits, Arvo and Greenberg 1994, "A Clustering Algorithm for
// Radiosity in Complex Environments", SIGGRAPH '94; Sillion 1995, "A Unified Hierarchical
// Algorithm for Global Illumination with Scattering Volumes and Object Clusters", IEEE TVCG 1(3)).
// The solver links clusters with clusters and with elements, so that its initial linking starts
// from one self-link of the root instead of every pair of patches.
//
// Conventions:
//  - Cluster ids are ints, the root is 0; an inner cluster has exactly two children, a leaf holds
//    1 to kLeafPatches patches (element ids of patch roots of the mesh).
//  - A cluster's patches are a contiguous range of patches() of its own, and a child's range lies
//    inside its parent's.
//  - area is the area of the surface *sides* inside: both sides of every patch, 2 sum A_p, in
//    m², since each side of a patch is a node of its own with its own radiance.
//  - center and radius are a bounding sphere of the patches' corners, metres.
#pragma once

#include "core/math.h"

#include <array>
#include <span>
#include <vector>

namespace penumbra {

class RadiosityMesh;

struct Cluster {
    Vec3 center{0.0f};
    float radius = 0.0f;
    double area = 0.0;
    int first = 0;  // first patch in ClusterTree::patches(): range [first, first + count)
    int count = 0;
    std::array<int, 2> children{-1, -1};  // -1, -1 for a leaf
    bool emits = false;                   // some patch inside has Le > 0 on a side
    // |sum_p A_p n_p| / sum_p A_p over its patches' front normals: 1 for coplanar patches facing
    // one way (a wall), near 0 for surfaces facing every way (a closed object, foliage).
    float flatness = 0.0f;

    bool isLeaf() const { return children[0] < 0; }
};

class ClusterTree {
  public:
    static constexpr int kLeafPatches = 4;

    // Builds the tree over the mesh's patches (the roots of its element quadtrees) by median
    // splits of the patch centroids along the longest axis of their bounds, O(n log^2 n). The
    // mesh may be refined afterwards: patches never change. An empty mesh gives an empty tree.
    explicit ClusterTree(const RadiosityMesh& mesh);

    bool empty() const { return clusters_.empty(); }
    size_t size() const { return clusters_.size(); }
    const Cluster& operator[](int cluster) const { return clusters_[static_cast<size_t>(cluster)]; }
    // The patches of a cluster.
    std::span<const int> patches(int cluster) const;
    // A patch of the cluster chosen with probability proportional to its area, by inverting the
    // cumulative area with u in [0, 1); `u` is replaced by its remainder in [0, 1) within the
    // chosen patch's interval, so that it can be used again as a fresh uniform number.
    int samplePatch(int cluster, float& u) const;

  private:
    int build(const RadiosityMesh& mesh, std::vector<Vec3>& centroids, int first, int count);

    std::vector<Cluster> clusters_;
    std::vector<int> order_;          // patch ids, each cluster's a contiguous range
    std::vector<double> cumulative_;  // cumulative patch area along order_, size + 1
};

}  // namespace penumbra
