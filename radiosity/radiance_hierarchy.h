// The radiance of the hierarchical solver's nodes (radiosity_solver.h; solver_nodes.h): every
// element side of the quadtrees and every cluster gathers through its links (link_hierarchy.h)
// and pushes what it gathered down to the leaves, whose radiance is pulled back up (HSA91
// GatherRad and PushPullRad, with a linear push and, for clusters, a directional one).
#pragma once

#include "core/math.h"
#include "radiosity/cluster_tree.h"
#include "radiosity/direct_irradiance.h"
#include "radiosity/element_exposure.h"
#include "radiosity/link_hierarchy.h"
#include "radiosity/link_transfer.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_settings.h"

#include <array>
#include <vector>

namespace penumbra {

// Sum of the three channels, the norm the convergence test uses per element.
inline double channelSum(const Color& c) {
    return static_cast<double>(c.r) + c.g + c.b;
}

// Area-weighted L1 norms of one sweep's change and of its new radiance, over leaf sides.
struct ChangeSums {
    double change = 0.0, norm = 0.0;
};

// A symmetric 3x3 matrix per channel, sum t d d^T of transfers t from directions d: the
// components xx, yy, zz, xy, xz, yz.
struct SecondMoment {
    std::array<Color, 6> q{};

    void add(const Color& t, const Vec3& d) {
        q[0] += t * (d.x * d.x);
        q[1] += t * (d.y * d.y);
        q[2] += t * (d.z * d.z);
        q[3] += t * (d.x * d.y);
        q[4] += t * (d.x * d.z);
        q[5] += t * (d.y * d.z);
    }
    // n^T Q n per channel.
    Color along(const Vec3& n) const {
        return q[0] * (n.x * n.x) + q[1] * (n.y * n.y) + q[2] * (n.z * n.z) +
               2.0f * (q[3] * (n.x * n.y) + q[4] * (n.x * n.z) + q[5] * (n.y * n.z));
    }
    SecondMoment operator+(const SecondMoment& o) const {
        SecondMoment r;
        for (size_t k = 0; k < q.size(); ++k)
            r.q[k] = q[k] + o.q[k];
        return r;
    }
};

class RadianceHierarchy {
  public:
    // All must outlive it; the mesh may be refined meanwhile (resize()). `clusters` is null
    // without clustering.
    RadianceHierarchy(const RadiosityMesh& mesh, const ElementExposure& exposure,
                      const DirectIrradiance& irradiance, const ClusterTree* clusters,
                      const LinkTransfer& transfer, const LinkHierarchy& links,
                      RadiositySettings::Iteration iteration);

    // Makes room for the mesh's new elements.
    void resize();
    // A new child's side starts from its parent's radiance until the next sweep, and takes its
    // final gather correction and, once computeDirectPart() has run, its direct part (a leaf
    // split after the solve, for the direct light at the corners, shows its parent's values).
    void inherit(int childNode, int parentNode);

    // Radiance leaving an element side, emission included.
    const Color& L(int node) const { return L_[static_cast<size_t>(node)]; }
    size_t nodeCount() const { return L_.size(); }
    // Radiance of a node (a cluster's: the area-weighted mean over its element sides) and the
    // range of max(L) over its leaves.
    const Color& nodeRadiance(int node) const;
    float nodeLmin(int node) const;
    float nodeLmax(int node) const;
    Color emission(int node) const;
    // A leaf side's radiance from what it gathers, H (cd/m², the exposed part's mean).
    Color leafRadiance(int node, const Color& H) const;

    // One sweep over all patch sides, in the given iteration's order.
    ChangeSums sweep();
    // Pushes and pulls every tree with what was gathered last, without gathering.
    void pushPullAll();
    // The first reflection of the sources (elementDirect), with `irradiance`, the one the
    // solution reads, set aside for the push-pull of the emission.
    void computeDirectPart(DirectIrradiance& irradiance);
    // The first reflection of the sources' light on a leaf side and the rest of its reflected
    // light (RadiositySolver::elementDirect, elementIndirect).
    Color elementDirect(int element, bool front) const;
    Color elementIndirect(int element, bool front) const;
    size_t directPartBytes() const { return direct_.size() * sizeof(Color); }

    // The final gather's correction (RadiositySolver::finalGather): zero, then `delta` added to a
    // leaf side's, of which `directShare` corrects the first reflection of the sources (it moves
    // from elementIndirect to elementDirect).
    void clearCorrection() {
        correction_.assign(L_.size(), Color(0.0f));
        directCorrection_.assign(L_.size(), Color(0.0f));
    }
    void addCorrection(int node, const Color& delta, const Color& directShare) {
        correction_[static_cast<size_t>(node)] += delta;
        directCorrection_[static_cast<size_t>(node)] += directShare;
    }

  private:
    Color clusterRadianceToward(int cluster, const Vec3& toward) const;
    Color sourceRadiance(int receiver, const Link& link) const;
    void gather(int node);
    void gatherTree(int node);
    void gatherCluster(int cluster);
    Color sweepCluster(int cluster, const Color& Hdown, const Mat3& Wdown,
                       const SecondMoment& Qdown, ChangeSums& sums, bool gatherNow);
    Color pushPull(int node, const Color& Hdown, const Mat3& Gdown, ChangeSums& sums);

    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    const DirectIrradiance& irradiance_;
    const ClusterTree* clusters_;
    const LinkTransfer& transfer_;
    const LinkHierarchy& links_;
    RadiositySettings::Iteration iteration_;

    // Per node (2 * element + side).
    std::vector<Color> L_;  // radiance leaving, emission included
    std::vector<Color> H_;  // gathered through the node's links, at its centroid (cd/m²)
    std::vector<Mat3> G_;   // its gradient over the node: column k = d/dx_k of the channels
    // What the node's own links add to H on each of its children beyond the even share, by the
    // children's visibility of the sources (Link::u); sums to zero over the children.
    std::vector<std::array<Color, 4>> Hchild_;
    std::vector<float> Lmin_, Lmax_;  // range of max(L) over the node's leaves
    std::vector<Color> direct_;       // the first reflection of the sources (elementDirect)
    // What the final gather adds to each leaf side's radiance beyond the links' transfer, and the
    // part of it that is the first reflection of the sources; empty without a final gather.
    std::vector<Color> correction_;
    std::vector<Color> directCorrection_;

    // Per cluster (empty without clustering).
    std::vector<Color> clusterL_, clusterH_;
    std::vector<Mat3> clusterW_;          // gathered sum K L d, column k: the channels times d_k
    std::vector<SecondMoment> clusterQ_;  // gathered sum K L d d^T
    // sum over the patches of A (L_front - L_back) n, column k: the channels times n_k
    // (clusterRadianceToward)
    std::vector<Mat3> clusterM_;
    std::vector<float> clusterLmin_, clusterLmax_;
};

}  // namespace penumbra
