// The links of the hierarchical solver (radiosity_solver.h; HSA91): per node (solver_nodes.h),
// element side or cluster, the links it gathers through, each with its transfer (link_transfer.h)
// and, once its ends have children, the shares of that transfer the children take.
#pragma once

#include "core/math.h"
#include "radiosity/element_exposure.h"
#include "radiosity/link_transfer.h"
#include "radiosity/radiosity_mesh.h"

#include <array>
#include <vector>

namespace penumbra {

// A link, stored with its receiver.
struct Link {
    int source = -1;  // node gathered from
    float F = 0.0f;   // unoccluded form factor from the receiver to the source (its mean)
    Color K{0.0f};    // F times the visible fraction, per channel (thin glass tints)
    // The transfer at a point x of the receiver is K L_source (1 + g . (x - centroid)): the
    // linear model of F over the receiver, relative to F (1/m); zero when partly occluded.
    // For a receiving cluster: the unit direction towards the source.
    Vec3 g{0.0f};
    float spread = 0.0f;  // receiver-side error factor of the oracle (linkErrors)
    float Fmax = 0.0f;    // largest point value of F over the receiver (sampled)
    // Once the source has children: the shares of F V that fall on each of them, so that the
    // link gathers sum_c w_c L_c rather than the source's mean radiance; w[0] < 0 until set.
    std::array<float, 4> w{-1.0f, 0.0f, 0.0f, 0.0f};
    // Once the receiver has children: the shares of the transfer each of them gets, relative
    // to an even share (their visible fractions of the source over their mean), so that the
    // children hidden from the source get less; u[0] < 0 until set.
    std::array<float, 4> u{-1.0f, 0.0f, 0.0f, 0.0f};
    ChildVisibility childV;  // for w and u, where the link is partly occluded
};

class LinkHierarchy {
  public:
    // Both must outlive it; `clusters`: the cluster tree's size, 0 without clustering.
    LinkHierarchy(const RadiosityMesh& mesh, const ElementExposure& exposure, size_t clusters);

    // Makes room for the links of the mesh's new elements.
    void resize();
    // The links gathered by a node.
    std::vector<Link>& linksOf(int node);
    const std::vector<Link>& linksOf(int node) const;
    size_t linkCount() const;
    // The element sides (nodes [0, elementSides())) and clusters that gather links.
    size_t elementSides() const { return links_.size(); }
    size_t clusters() const { return clusterLinks_.size(); }
    // Sets the child weights of links whose source or receiver has been split since they were
    // made.
    void updateChildWeights();

  private:
    void setSourceWeights(int receiver, Link& link) const;
    void setReceiverWeights(int receiver, Link& link) const;

    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    std::vector<std::vector<Link>> links_;         // per element side
    std::vector<std::vector<Link>> clusterLinks_;  // per cluster (empty without clustering)
};

}  // namespace penumbra
