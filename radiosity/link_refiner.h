// The refinement of the hierarchical solver's links (radiosity_solver.h): HSA91's Refine, Link and
// RefineLinks with an error-based oracle, generalised to clusters (Sillion 1995), the splitting of
// leaves by their punctual direct light and by contrast with their neighbours, and the evaluation
// of the new links' transfer (link_transfer.h). It owns the oracle's thresholds; the links it
// makes go to the LinkHierarchy, the radiance it weighs is the RadianceHierarchy's, and the
// elements it splits are announced to the solver, which grows its parts indexed by node.
#pragma once

#include "core/deadline.h"
#include "core/math.h"
#include "radiosity/cluster_tree.h"
#include "radiosity/direct_irradiance.h"
#include "radiosity/element_exposure.h"
#include "radiosity/link_hierarchy.h"
#include "radiosity/link_transfer.h"
#include "radiosity/pending_links.h"
#include "radiosity/radiance_hierarchy.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_settings.h"
#include "radiosity/solve_progress.h"

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace penumbra {

// A pair for the oracle; spread < 0: take the receiver-side spread from the kernel samples.
struct RefinePair {
    int receiver, source;
    float spread = -1.0f;
};
struct LinkErrors {
    double receiver, source;
};

class LinkRefiner {
  public:
    // Called when an element is split, with its first child: every part indexed by node makes
    // room, and the children start from their parent's values.
    using Split = std::function<void(int element, int firstChild)>;
    // Called with the elements split since the last call, before their links are evaluated:
    // their exposure and direct light.
    using Settle = std::function<void(const std::vector<int>& created)>;

    // All must outlive it; `clusters` is null without clustering.
    LinkRefiner(RadiosityMesh& mesh, const RadiositySettings& settings,
                const ElementExposure& exposure, const DirectIrradiance& irradiance,
                const ClusterTree* clusters, const LinkTransfer& transfer, LinkHierarchy& links,
                const RadianceHierarchy& radiance, Split split, Settle settle);

    // The progress sink of the solve, if any: the oracle's stages count the pairs they examine,
    // and each step's links get a stage "<step>: form factors and visibility".
    void setProgress(SolveProgress* progress) { progress_ = progress; }

    // What the refinement does once the deadline has passed, or the initial linking's oracle has
    // used its share of the time it had left (oracleTooLong): Coarsen links every pair it still
    // examines as it stands (the oracle allows any error from then on; close nodes under a radius,
    // and a cluster with an element that cannot be split, are linked with a softened kernel, and a
    // small cluster's pairs within itself are left out), a coarser solution at the price of the
    // links it has decided; Abandon, during the initial linking, stops and makes no more links
    // (abandoned()), for a caller that can do without the solution, also as soon as the rate of
    // the links' evaluation says they will not all be made by the deadline. `abandonAt` is when
    // the initial linking is abandoned, as Abandon does at the deadline (it is the deadline then):
    // with Coarsen, a later time, for a caller that traces without the solution rather than wait
    // for one past its whole time limit.
    enum class OnTimeUp { Coarsen, Abandon };
    void setTimeLimit(Deadline deadline, OnTimeUp onTimeUp, Deadline abandonAt = std::nullopt);
    bool abandoned() const { return abandoned_; }
    // HSA91's initial linking, with the oracle on the current radiance and epsilon times
    // `epsilonScale` (coarser links for a solve that refines them in rounds as time allows).
    void linkPatches(const std::string& step, float epsilonScale = 1.0f);
    // HSA91 "RefineLinks" with the radiance of the last solve. Returns whether any link was
    // refined.
    bool refineLinks(const std::string& step);
    // Splits the leaves whose punctual direct light spreads by more than the oracle allows.
    // Returns whether any element was split.
    bool refineDirect();
    // Splits the leaves whose reflected radiance differs too much from a neighbour's
    // (RadiositySettings::subdivisionThreshold). Returns whether any leaf was split.
    bool subdivideByContrast(const std::string& step);

    // Splits a leaf as the refinement does (the solver's parts make room, the children start
    // from their parent's values), down to children of minChildArea (RadiosityMesh::split), and
    // returns its first child; settleSplits() then gives the children split since the last call
    // their own exposure and direct light.
    int splitLeaf(int element, float minChildArea);
    void settleSplits() { finishSplits(); }

    size_t refinedLinks() const { return refinedLinks_; }
    uint64_t rays() const { return rays_; }  // the new links' shadow rays
    // The time spent on the form factors and visibility of new links.
    double secondsFormFactors() const { return secondsLinks_; }

  private:
    // The first of the element's four children, splitting it first if it is a leaf.
    int children(int element);
    void finishSplits();
    bool canSplitNode(int node) const;
    std::vector<int> nodeChildren(int node);
    void refineClusterPair(int receiver, int source, const ClusterKernel& k,
                           std::vector<RefinePair>& next, std::vector<PendingLink>& pending);
    void refine(std::vector<RefinePair> batch, std::vector<PendingLink>& pending);
    void refineSlice(std::span<const RefinePair> batch, std::vector<RefinePair>& next,
                     std::vector<PendingLink>& pending);
    LinkErrors linkErrors(int source, float spread, float Fmax) const;
    void evaluateLinks(const std::vector<PendingLink>& pending, const std::string& step);
    // refine(), then finishSplits() and evaluateLinks() on what it made, in that order.
    void refineAndLink(std::vector<RefinePair> pairs, const std::string& step);
    bool exceedsThreshold(int receiver, int source, const LinkErrors& errors) const;
    // Whether the deadline has passed (setTimeLimit); sets coarse_ when it has.
    bool timeIsUp();
    // Whether the initial linking's oracle has used 1/share of the time its linking had left to
    // `until` (half of it to abandonAt_: the solve is then abandoned; a quarter of it to the
    // deadline, with OnTimeUp::Coarsen: the links are then made as they stand).
    bool oracleTooLong(Deadline until, int share) const;
    // Whether the initial linking is to be abandoned now (abandonAt_).
    bool abandonLinking() const;
    bool smallTransfer(int source, float Fmax) const;
    // The softening radius of cluster kernels: coarseRadius_ once coarse_, else none.
    float softRadius() const { return coarse_ ? coarseRadius_ : 0.0f; }
    void updateThresholds(bool relativeFloor, float epsilonScale = 1.0f);

    RadiosityMesh& mesh_;
    const RadiositySettings& settings_;
    const ElementExposure& exposure_;
    const DirectIrradiance& irradiance_;
    const ClusterTree* clusters_;
    const LinkTransfer& transfer_;
    LinkHierarchy& links_;
    const RadianceHierarchy& radiance_;
    Split split_;
    Settle settle_;
    SolveProgress* progress_ = nullptr;

    double threshold_ = 0.0;  // the oracle's absolute threshold (radiance) of this round
    // The receiver-relative criterion's floor per channel (exceedsThreshold); 0 until the first
    // refinement round, when a solution is known (updateThresholds).
    Color relativeFloor_{0.0f};
    Deadline deadline_;
    OnTimeUp onTimeUp_ = OnTimeUp::Coarsen;
    Deadline abandonAt_;    // setTimeLimit
    bool linking_ = false;  // in linkPatches(), where the refinement may be abandoned
    std::chrono::steady_clock::time_point linkingStart_;  // when linkPatches() began
    // The time was up (or, in the initial linking, its oracle had used half of what was left):
    // the oracle refines nothing more and links pairs as they stand.
    bool coarse_ = false;
    float coarseRadius_;        // metres; see kCoarseRadius
    bool abandoned_ = false;    // the initial linking stopped with the time (OnTimeUp::Abandon)
    std::vector<int> created_;  // elements split off since the last finishSplits()
    size_t refinedLinks_ = 0;
    uint64_t rays_ = 0;
    double secondsLinks_ = 0.0;
};

}  // namespace penumbra
