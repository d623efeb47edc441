// The indirect light of a radiosity solution as it is shown: gathered with rays at the corners of
// every leaf and interpolated linearly in between, instead of the Gouraud interpolation of the
// element means. Where surfaces meet (a ceiling along a wall, the floor at a block's foot) the
// indirect light changes within an element: a point in the corner sees the other surface at
// grazing angles and less of the room. The element means average that away, and the vertex
// values, means of the elements around a vertex, show the corner as bright as the middle of the
// face (8-11 % too bright in the Cornell box's upper corners, docs/radiosity.md).
//
// At a corner x (a thousandth of the leaf's size inside it, as ShownDirect's corners, so that a
// leaf beside a contact line takes the limit from its own side) the gather is the final gather's
// estimator (final_gather.cpp) at one point:
//     I(x) = rho / N sum_k T_k L_r(y_k),
// w_k cosine-distributed about the side's normal from an Owen-scrambled (0,2)-sequence, y_k the
// first meshed surface along the ray and L_r the reflected radiance the solution sends back along
// it (GatheredRadiance::seen, gathered_radiance.h: its leaf side's, the glossy lobes followed).
// The corners that several leaves have at one mesh vertex, on one side of one plane, are gathered
// once (from the first leaf's corner), so that they show one value and the interpolation stays
// continuous across the leaves' edges; a crease keeps a value per plane. Every corner is probed
// for covers first (element_exposure.h): a covered one, which would gather from under a block or
// inside a solid, takes the mean of its leaf side's exposed corners, or with none the fallback
// the caller gives (the element mean the solution shows without corners). The values are then
// anchored at T-vertices (leaf_corner_values.h).
//
// Between its corners a leaf shows m + sum_k b_k w_k (c_k - m): m the element mean (the
// fallback), b_k the point's barycentrics, w_k = min(1, R_k / d_k), d_k its distance to corner k
// and R_k the harmonic mean length of that corner's rays, how far its value holds (the validity
// radius of Ward, Rubinstein and Clear 1988, "A Ray Tracing Solution for Diffuse
// Interreflection"), but never less than kCreaseSize (crease_refinement.h). On leaves smaller
// than their corners' reach this is the corners' linear interpolation; a large leaf touching
// another surface that the refinement at creases could not split (its budget spent) keeps the
// contact's darkness near the contact instead of along its length. The floor is the smallest
// leaf that refinement makes: at a crease R_k is a few micrometres (half the rays meet the other
// surface at once), and without it the leaves there, refined to show the crease's dip, would
// show their element mean up to the crease (the path tracer's dip, a centimetre wide at the
// Cornell box's short block, is what those leaves' corners hold; the minimum clamp on the
// validity radius of Tabellion and Lamorlette 2004, "An Approximate Global Illumination System
// for Computer Generated Films", plays the same part).
#pragma once

#include "core/deadline.h"
#include "core/math.h"
#include "radiosity/corner_rays.h"
#include "radiosity/leaf_corner_values.h"
#include "radiosity/meshed_hit.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/solve_progress.h"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace penumbra {

class Scene;
struct ElementSample;

class IndirectAtCorners {
  public:
    // What gather() reads of the solver: whether an element side shows light (is exposed),
    // whether the side is covered at a point (adding its probe rays), the reflected radiance a
    // ray's hit sends back along it (cd/m², emission left out; drawing from the ray's sampler and
    // adding the rays it casts), the indirect light a side reflects
    // that rays cannot gather (what the specular transfer carried through solid glass), added
    // to its gathered corners, and the value shown at a side with no exposed corner.
    struct Solution {
        std::function<bool(int element, bool front)> exposed;
        std::function<bool(int element, const ElementSample& x, bool front, uint64_t& rays)>
            covered;
        std::function<Color(const MeshedHit& hit, Sampler& sampler, uint64_t& rays)> seenAt;
        std::function<Color(int element, bool front)> unseen, fallback;
    };

    // Both must outlive it. `raysPerCorner`: rays per corner and side on the solve's leaves.
    // `firstCreaseLeaf`: the first element the refinement at creases made (crease_refinement.h;
    // any larger id if it made none); a leaf of it d levels below the solve's leaf gathers with
    // raysPerCorner / 2^d rays, at least CreaseRefinement::kProbeRays (raysAt()).
    IndirectAtCorners(const Scene& scene, const RadiosityMesh& mesh, int raysPerCorner,
                      int firstCreaseLeaf);

    // Gathers at the corners of every leaf side that is exposed and reflects; the other leaves'
    // corners take the fallback. Advances `progress`, if any, by one per gather (per vertex and
    // plane). With a deadline, it gives up as soon as the probes for covers are projected to
    // take more than half of the time to it; then every kProbeStride-th gather is made first
    // with the rays asked, until those have taken kProbeShare of the time to the deadline, and
    // all of them again with fewer rays than asked if the time those took says that the asked
    // count would end after the deadline (raysPerCorner() then tells how many); if fewer than
    // kFewestBudgetedRays would, it stops there. Having given up, it returns false: the corners
    // show nothing, and the caller shows the element means.
    bool gather(const Solution& solution, SolveProgress* progress = nullptr,
                Deadline deadline = std::nullopt);

    // The indirect light at a point of a leaf, cd/m²: its corners weighted by the point's
    // barycentrics and by how far their values hold (above); zero on no element or before
    // gather().
    Color at(const ElementPoint& point, bool front) const;
    // A leaf side's values at its three corners, in the order of RadiosityMesh::vertices().
    std::array<Color, 3> corners(int element, bool front) const {
        return corners_.corners(element, front);
    }

    uint64_t rays() const { return rays_; }
    // Rays per corner on the solve's leaves: as asked, or what a deadline left of it.
    int raysPerCorner() const { return raysPerCorner_; }
    size_t memoryBytes() const {
        return corners_.memoryBytes() + reach_.capacity() * sizeof(reach_[0]) +
               means_.capacity() * sizeof(means_[0]);
    }

  private:
    // The probe under a deadline: one gather in kProbeStride, spread over the mesh by the
    // gathers' order (by vertex), with the rays asked, for at most kProbeShare of the time to the
    // deadline (and its last chunk). With the rays asked, as a gather's fixed costs make fewer
    // rays a poor guide (probing with 24 rays and scaling the time by the rays, the hall's
    // corners at 16 s got 31-36 rays where the time allowed 46-49); with a cap, as one gather in
    // 64 with 256 rays took 1.5 s on the grey-white room at 16 s, which left no time for the rest.
    static constexpr size_t kProbeStride = 64;
    static constexpr double kProbeShare = 0.1;
    // Under a deadline, the fewest rays per corner worth gathering: on the modern hall's
    // `distribution` preview at 16 s (relMSE 0.0167 with the element means) corners of 2 and 11
    // rays made it worse (0.218, 0.0209: a few corners' noise over large leaves), 13 rays
    // better (0.0149), 27-49 rays 0.0102-0.0151 (docs/radiosity.md, "After the solve, under a
    // time limit").
    static constexpr int kFewestBudgetedRays = 24;

    enum class CornerState : uint8_t { None, Exposed, Covered };
    using CornerStates = std::array<CornerState, 6>;  // [front c0, c1, c2, back c0, c1, c2]
    // An exposed corner of a leaf side, and the key of the corners gathered with it (cornerKey,
    // corner_rays.h).
    struct Corner {
        int leaf = 0;
        bool front = true;
        size_t k = 0;
        CornerKey key{};
    };
    // A corner's gather: the mean reflected radiance its rays meet (the gather less rho), and
    // the harmonic mean of their lengths, how far from the corner its value holds.
    struct Gathered {
        Color L;
        float reach = 0.0f;
    };
    // Per leaf: which of its sides' corners show light (exposed, reflecting), and which of those
    // are covered (adding the probe rays).
    // Under a deadline, nothing once they are projected to take more than half of the time to
    // it.
    std::optional<std::vector<CornerStates>> cornerStates(const Solution& solution,
                                                          const std::vector<int>& leaves,
                                                          Deadline deadline);
    std::vector<Corner> exposedCorners(const std::vector<int>& leaves,
                                       const std::vector<CornerStates>& states) const;
    Gathered meanReflected(const Solution& solution, const Corner& corner, uint32_t n,
                           uint64_t& rays) const;
    int raysAt(int leaf) const;
    // The corners not gathered: covered ones the mean of their side's exposed corners; those of
    // a side with none (covered, hidden under a coincident face, or not reflecting) the
    // fallback, so that the vertex values around them (the bake's) are not pulled down.
    void fillCovered(const Solution& solution, const std::vector<int>& leaves,
                     const std::vector<CornerStates>& states);

    const Scene& scene_;
    const RadiosityMesh& mesh_;
    int raysPerCorner_;
    int firstCreaseLeaf_;
    LeafCornerValues corners_;
    std::vector<std::array<float, 6>>
        reach_;  // per leaf corner, as corners_ (a covered corner: the farthest of its leaf side's
                 // exposed corners, 0 with none)
    std::vector<std::array<Color, 2>> means_;  // per leaf side [front, back]: fallback()
    uint64_t rays_ = 0;
};

}  // namespace penumbra
