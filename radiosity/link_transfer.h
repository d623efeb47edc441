// What a link of the hierarchical solver (radiosity_solver.h) transfers from its source node to
// its receiver node (element sides or clusters, solver_nodes.h): the unoccluded form factor and
// its point values over the receiver (the refinement oracle's kernel samples, the linear push's
// model), the visible fraction from shadow rays, and for a cluster at either end the isotropic
// kernel of Sillion 1995. It owns nothing that changes: it reads the mesh, the exposed parts of
// the element sides and the cluster tree as they stand.
#pragma once

#include "core/math.h"
#include "radiosity/cluster_tree.h"
#include "radiosity/element_exposure.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_settings.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace penumbra {

class Scene;

// Point values of the unoccluded form factor from points of a receiver to a source.
struct KernelSamples {
    std::array<float, 3> corner;  // at the receiver's corners (moved 1e-3 inwards)
    std::array<float, 3> mid;     // at the midpoints of its edges (corner i to i + 1)
    float centroid;               // at its centroid

    float cornerMean() const { return (corner[0] + corner[1] + corner[2]) / 3.0f; }
    float max() const {
        return std::max({centroid, corner[0], corner[1], corner[2], mid[0], mid[1], mid[2]});
    }
    // The receiver-side error factor of the refinement oracle for an unoccluded link, with the
    // linear model's positivity limiter (LinkTransfer::linearModel).
    float spread(float limiter) const;
};

// The visible fractions (means over the channels) of the four children of a link's receiver
// and of its source (RadiosityMesh::childAt), split yet or not, from the link's own shadow
// rays binned by the child each end of a ray falls in; kNoRays where none fell. Stored in
// steps of 1/254: they only share the link's transfer among the children (LinkHierarchy's
// setSourceWeights, setReceiverWeights).
struct ChildVisibility {
    static constexpr uint8_t kNoRays = 255;
    std::array<uint8_t, 4> receiver{kNoRays, kNoRays, kNoRays, kNoRays};
    std::array<uint8_t, 4> source{kNoRays, kNoRays, kNoRays, kNoRays};

    // From the children's fractions, negative where no ray fell in one.
    static std::array<uint8_t, 4> encode(const std::array<float, 4>& V) {
        std::array<uint8_t, 4> codes{};
        for (size_t c = 0; c < V.size(); ++c)
            codes[c] = V[c] < 0.0f
                           ? kNoRays
                           : static_cast<uint8_t>(std::lround(std::min(V[c], 1.0f) * 254.0f));
        return codes;
    }
    // The children's visible fractions, `otherwise` where no ray fell in one.
    static std::array<float, 4> decode(const std::array<uint8_t, 4>& codes, float otherwise) {
        std::array<float, 4> V{};
        for (size_t c = 0; c < V.size(); ++c)
            V[c] = codes[c] == kNoRays ? otherwise : static_cast<float>(codes[c]) / 254.0f;
        return V;
    }
    ChildVisibility reversed() const { return {source, receiver}; }
};

// The isotropic cluster kernel of a link with a cluster at one end or both
// (LinkTransfer::clusterKernel): its value at the centres, its largest value, the oracle's error
// per unit source radiance, and whether the two may be linked at all.
struct ClusterKernel {
    bool linkable = false;
    float K = 0.0f, Kmax = 0.0f, error = 0.0f;
};

class LinkTransfer {
  public:
    // All must outlive it; `clusters` is null without clustering.
    LinkTransfer(const Scene& scene, const RadiosityMesh& mesh, const ElementExposure& exposure,
                 const ClusterTree* clusters, const RadiositySettings& settings);

    // Bounding sphere of a node: a cluster's, or an element's about its centroid.
    Vec3 nodeCenter(int node) const;
    float nodeRadius(int node) const;
    double nodeArea(int node) const;  // m²; a cluster's counts both sides of its patches

    // Whether two element sides can exchange light at all.
    bool mayInteract(int receiver, int source) const;
    // The same for a pair with a cluster at one end or both.
    bool mayInteractWithCluster(int receiver, int source) const;
    // Form factor between two element sides; with `samples` (the pair's KernelSamples), a far
    // pair takes a cheaper rule.
    float formFactor(int receiver, int source, const KernelSamples* samples = nullptr) const;
    KernelSamples kernelSamples(int receiver, int source) const;
    // The relative gradient of the link's form factor over its receiver (Link::g,
    // link_hierarchy.h); sets `limiter` to the factor that keeps it non-negative.
    Vec3 linearModel(int receiver, const KernelSamples& samples, float F, float& limiter) const;
    // Visible fraction between two nodes. Adds the shadow rays it casts to `rays`; `adaptive`
    // may stop after a few that agree. With `children`, also the ends' children's visible
    // fractions.
    Color visibility(int receiver, int source, uint64_t& rays, bool adaptive,
                     ChildVisibility* children = nullptr) const;
    // The form factor F over the exposed part of a partly covered receiver.
    float exposedFormFactor(int receiver, int source, float F) const;
    // `softRadius` (metres) widens the radius under which a close pair is linked with a
    // softened distance rather than left unlinkable, and when positive so is every pair with an
    // element end that cannot be split (a hurried solve: LinkRefiner's coarse mode).
    ClusterKernel clusterKernel(int receiver, int source, float softRadius = 0.0f) const;

  private:
    const Scene& scene_;
    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    const ClusterTree* clusters_;
    int visibilitySamples_;   // shadow rays per link
    float clusterMinRadius_;  // metres, see clusterKernel
};

}  // namespace penumbra
