// Hierarchical radiosity: HSA91's Refine / Link / GatherRad / PushPullRad, with an error-based
// refinement oracle, a linear push and links carrying form factor times visibility.
#include "radiosity/radiosity_solver.h"

#include "core/errors.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "core/stats.h"
#include "radiosity/direct_irradiance.h"
#include "radiosity/element_exposure.h"
#include "radiosity/element_sampling.h"
#include "radiosity/form_factor.h"
#include "radiosity/gather_divergence.h"
#include "radiosity/link_hierarchy.h"
#include "radiosity/link_transfer.h"
#include "radiosity/meshed_hit.h"
#include "radiosity/radiance_hierarchy.h"
#include "radiosity/solver_nodes.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>
#include <tuple>
#include <unordered_map>

namespace penumbra {

namespace {

// The final gather's sampler seed, apart from those of the links' visibility (link_transfer.cpp)
// and of the element points (ElementExposure::kPointSeed), so that they never share a sequence.
constexpr uint32_t kFinalGatherSeed = 0xc2b2ae35u;

// Passes of the final gather's defect correction (finalGather), at most, and the relative change
// of the correction below which they stop.
constexpr int kMaxFinalGatherPasses = 4;
constexpr double kFinalGatherChange = 1e-2;

// Threshold of the intermediate solves between refinement rounds: the oracle only needs the
// radiance to a few percent.
constexpr double kRoundConvergence = 2e-2;

// Relative change of a sweep below which it is rounding (iterate): a tenth of float's epsilon,
// as the area-weighted L1 change of one element's last bit is smaller still.
constexpr double kRoundingChange = 0.1 * std::numeric_limits<float>::epsilon();

// Units of a gather stage's progress (iterate): the fraction of the way to the threshold.
constexpr uint64_t kGatherProgressUnits = 1000;

// Passes of adaptive subdivision (subdivision_threshold) after the refinement rounds.
constexpr int kSubdivisionPasses = 4;

// The receiver-relative criterion's floor (exceedsThreshold), as a fraction of the scene's mean
// radiance in each channel: a receiver darker than this is refined as if it were this bright.
constexpr float kRelativeFloor = 0.1f;

}  // namespace

RadiositySolver::RadiositySolver(const Scene& scene, RadiosityMesh& mesh,
                                 const RadiositySettings& settings,
                                 const std::vector<FluxDeposit>& deposits)
    : scene_(scene),
      mesh_(mesh),
      settings_(settings),
      exposure_(std::make_unique<ElementExposure>(scene, mesh)),
      irradiance_(std::make_unique<DirectIrradiance>(scene, mesh, *exposure_,
                                                     settings.visibilitySamples, deposits)) {
    validateRadiositySettings(settings_);
    if (mesh_.patchCount() > static_cast<size_t>(settings_.clusterMinPatches))
        clusters_ = std::make_unique<ClusterTree>(mesh_);
    transfer_ =
        std::make_unique<LinkTransfer>(scene_, mesh_, *exposure_, clusters_.get(), settings_);
    links_ = std::make_unique<LinkHierarchy>(mesh_, *exposure_, clusters_ ? clusters_->size() : 0);
    radiance_ = std::make_unique<RadianceHierarchy>(
        mesh_, *exposure_, *irradiance_, clusters_.get(), *transfer_, *links_, settings_.iteration);
    resizeArrays();
}

void RadiositySolver::resizeArrays() {
    exposure_->resize();
    irradiance_->resize();
    links_->resize();
    radiance_->resize();
}

RadiositySolver::~RadiositySolver() = default;

Color RadiositySolver::elementRadiance(int e, bool side) const {
    return radiance_->L(node(e, side));
}

Color RadiositySolver::leafRadiance(int n, const Color& H) const {
    return radiance_->leafRadiance(n, H);
}

size_t RadiositySolver::linkCount() const {
    return links_->linkCount();
}

// --- Refinement --------------------------------------------------------------------------------

// The oracle's thresholds from the current solution. threshold_, the absolute one: epsilon times
// the scene's mean radiance, sum_i A_i max(L_i) / sum_i A_i over the patches (both sides counted
// in the sum, the area once), so that epsilon is a fraction of a typical radiance whatever the
// scene's units and brightness. With `relativeFloor` also relativeFloor_, the receiver-relative
// criterion's floor (exceedsThreshold): kRelativeFloor times the same mean per channel.
void RadiositySolver::updateThresholds(bool relativeFloor) {
    double largest = 0.0, area = 0.0;
    Color perChannel(0.0f);
    for (size_t p = 0; p < mesh_.patchCount(); ++p) {
        const int e = static_cast<int>(p);
        const Color &Lfront = radiance_->L(node(e, true)), &Lback = radiance_->L(node(e, false));
        const Color L = Lfront + Lback;
        area += mesh_.area(e);
        largest += mesh_.area(e) * static_cast<double>(maxComponent(Lfront) + maxComponent(Lback));
        perChannel += mesh_.area(e) * L;
    }
    if (!(area > 0.0))
        return;
    threshold_ = settings_.epsilon * largest / area;
    if (relativeFloor)
        relativeFloor_ = kRelativeFloor * perChannel / static_cast<float>(area);
}

// Whether a link's error (linkErrors, the larger of the two) is above what the oracle allows: the
// absolute threshold, and once a solution is known (relativeFloor_ set by refineLinks()) also
// epsilon times the receiver's own radiance in any channel (at least relativeFloor_). The absolute
// threshold alone, epsilon times the scene's mean radiance in its largest channel, leaves the
// faces lit only indirectly, and the weak channels of coloured light, with links whose error is
// several percent of what they receive: on the Cornell box the tall block's face towards the red
// wall, green 0.03 cd/m^2 against a mean of 0.5 in red, came out 3 % too bright (its middle 4-11
// %). The error in a channel is the link's error in the source's largest channel scaled by the
// source's colour and by the receiver's rho: what the receiver reflects of it.
bool RadiositySolver::exceedsThreshold(int receiver, int source, const LinkErrors& errors) const {
    const double error = std::max(errors.receiver, errors.source);
    if (error > threshold_)
        return true;
    if (isCluster(receiver) || !(maxComponent(relativeFloor_) > 0.0f))
        return false;
    const Color Ls = radiance_->nodeRadiance(source);
    const float LsMax = maxComponent(Ls);
    if (!(LsMax > 0.0f))
        return false;
    const Color rho = mesh_.rho(element(receiver));
    const Color Lr = radiance_->nodeRadiance(receiver);
    for (int c = 0; c < 3; ++c) {
        const double reflected = error * static_cast<double>(rho[c] * Ls[c] / LsMax);
        if (reflected > settings_.epsilon * static_cast<double>(glm::max(Lr[c], relativeFloor_[c])))
            return true;
    }
    return false;
}

bool RadiositySolver::subdivisible(int e) const {
    return !mesh_.isLeaf(e) || mesh_.canSplit(e);
}

// The first of e's four children, splitting e first if it is a leaf. New children start from the
// parent's radiance and direct light until the next sweep and finishSplits() replace them.
int RadiositySolver::children(int e) {
    if (!mesh_.isLeaf(e))
        return mesh_.firstChild(e);
    const int first = mesh_.split(e);
    resizeArrays();
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c) {
        for (const bool side : {true, false}) {
            radiance_->inherit(node(c, side), node(e, side));
            irradiance_->inherit(node(c, side), node(e, side));
        }
        created_.push_back(c);
    }
    return first;
}

void RadiositySolver::finishSplits() {
    rays_ += exposure_->compute(created_);
    rays_ += irradiance_->compute(created_);
    created_.clear();
}

// The new elements' exposed fractions come before the new links' evaluation: a link with a partly
// covered end counts only the exposed points (visibility, exposedFormFactor).
void RadiositySolver::refineAndLink(std::vector<RefinePair> pairs) {
    std::vector<PendingLink> pending;
    refine(std::move(pairs), pending);
    finishSplits();
    evaluateLinks(pending);
}

// The two errors a link (receiver <- source) makes, in radiance at the receiver. HSA91's BF oracle
// weighs the transfer itself, B_q F_pq (times A_p for power); these weigh what the link gets
// wrong instead, in the way of Lischinski, Smits and Greenberg 1994, "Bounds and Error Estimates
// for Radiosity", SIGGRAPH '94, which refines links by the spread of their transfer (estimated
// here from samples, not bounded):
//  - receiver side: what the linear push cannot follow of the form factor's variation over the
//    receiver, `spread` (Link::spread) times max(L_source);
//  - source side: the link carries the source's mean radiance while the radiance spreads by
//    (L_max - L_min) over the source's leaves: F_max (L_max - L_min).
// Weighing F alone misses the first: with HSA91's constant push, in the closed box a corner
// element gathers 1.9 times what it should from links that each carry under 1 %.
RadiositySolver::LinkErrors RadiositySolver::linkErrors(int source, float spread,
                                                        float Fmax) const {
    return {
        static_cast<double>(spread) * maxComponent(radiance_->nodeRadiance(source)),
        static_cast<double>(Fmax) * (radiance_->nodeLmax(source) - radiance_->nodeLmin(source))};
}

// HSA91 "Refine": while the larger of a link's errors exceeds the threshold and one of the two
// elements can still be subdivided, the side at fault is subdivided (the other if it cannot) and
// its children are refined against the other element; otherwise the pair is linked ("Link").
// HSA91 subdivides the element with the larger form factor estimate, i.e. the larger one; here
// the error says which side needs it. A pair's `spread` is its receiver-side spread, from the link
// for a link being refined, else (negative) from the samples.
//
// HSA91 recurse depth first; here the pairs are taken level by level, so that the kernel samples
// of a whole level are computed in parallel and only the decisions, which split elements, are
// sequential. The links made are the same.
void RadiositySolver::refine(std::vector<RefinePair> batch, std::vector<PendingLink>& pending) {
    while (!batch.empty()) {
        advanceStage(batch.size());  // the oracle's stage counts the pairs it examines
        std::vector<KernelSamples> samples(batch.size());
        std::vector<char> interacts(batch.size(), 0);
        tbb::parallel_for(size_t(0), batch.size(), [&](size_t i) {
            const RefinePair& p = batch[i];
            if (isCluster(p.receiver) || isCluster(p.source) ||
                !transfer_->mayInteract(p.receiver, p.source))
                return;
            interacts[i] = 1;
            samples[i] = transfer_->kernelSamples(p.receiver, p.source);
        });
        std::vector<RefinePair> next;
        for (size_t i = 0; i < batch.size(); ++i) {
            const RefinePair& p = batch[i];
            if (isCluster(p.receiver) || isCluster(p.source)) {
                refineClusterPair(p.receiver, p.source, next, pending);
                continue;
            }
            if (!interacts[i])
                continue;
            const KernelSamples& k = samples[i];
            const int er = element(p.receiver), es = element(p.source);
            const bool canR = subdivisible(er), canS = subdivisible(es);
            const LinkErrors errors =
                linkErrors(p.source, p.spread >= 0.0f ? p.spread : k.spread(1.0f), k.max());
            if (!exceedsThreshold(p.receiver, p.source, errors) || !(canR || canS)) {
                pending.push_back({p.receiver, p.source, k});
                continue;
            }
            const bool splitSource = canS && (!canR || errors.source > errors.receiver);
            const int first = children(splitSource ? es : er);
            for (int c = first; c < first + RadiosityMesh::kChildren; ++c) {
                next.push_back({splitSource ? p.receiver : node(c, front(p.receiver)),
                                splitSource ? node(c, front(p.source)) : p.source});
            }
        }
        batch = std::move(next);
    }
}

// Whether a link's whole transfer, F_max times the larger of its source's radiance and the
// scene's mean (which a dark source may reach once lit), is under the oracle's threshold: then an
// error in its visible fraction cannot matter more than the refinement tolerates. (Allowing a
// quarter of the transfer instead, on the grounds that four stratified pairs rarely miss more,
// lets the shadow of a block be missed: 12 % of the mean on a leaf against the dense solve.)
bool RadiositySolver::smallTransfer(int source, float Fmax) const {
    const double mean = threshold_ / settings_.epsilon;
    return Fmax *
               std::max(mean, static_cast<double>(maxComponent(radiance_->nodeRadiance(source)))) <=
           threshold_;
}

// Form factor, visibility and linear model of new links, in parallel (the refinement that decided
// them is sequential because it splits elements). Links that carry nothing (F = 0, or fully
// occluded) are dropped: no oracle would refine them. A partly occluded link gets no slope (the
// visibility's variation is unknown) and a spread of its whole F_max, as a shadow boundary may
// cross the receiver anywhere. A link with a cluster at either end carries the isotropic kernel
// (clusterKernel) times the visible fraction, with no slope and its error bound as both spreads.
//
// A pair listed in both directions (as the initial linking makes many) is evaluated once: the
// reverse link takes F_ji = A_i F_ij / A_j and the same visible fraction, which halves its work and
// makes the pair's transfer exactly reciprocal. (Keeping form factors for a reverse link of a
// later round gained nothing measurable on the Cornell box: refinement weighs each source's own
// radiance, so it seldom asks for the reverse.)
void RadiositySolver::evaluateLinks(const std::vector<PendingLink>& pending) {
    const auto start = std::chrono::steady_clock::now();
    const size_t n = pending.size();
    // Pair each link with its reverse, if pending too.
    std::vector<int> reverse(n, -1);
    std::vector<char> primary(n, 1);
    {
        const auto key = [](int r, int s) {
            return (static_cast<uint64_t>(static_cast<uint32_t>(r)) << 32) |
                   static_cast<uint32_t>(s);
        };
        std::unordered_map<uint64_t, int> seen;
        seen.reserve(n);
        // A partly covered end makes the two directions' transfers differ (visibility,
        // exposedFormFactor).
        for (size_t i = 0; i < n; ++i) {
            if (exposure_->partlyCovered(pending[i].receiver) ||
                exposure_->partlyCovered(pending[i].source))
                continue;
            const auto it = seen.find(key(pending[i].source, pending[i].receiver));
            if (it != seen.end() && reverse[static_cast<size_t>(it->second)] < 0) {
                reverse[static_cast<size_t>(it->second)] = static_cast<int>(i);
                reverse[i] = it->second;
                primary[i] = 0;
            } else {
                seen.emplace(key(pending[i].receiver, pending[i].source), static_cast<int>(i));
            }
        }
    }
    const auto isClusterLink = [&](size_t i) {
        return isCluster(pending[i].receiver) || isCluster(pending[i].source);
    };
    // The unoccluded kernel and its largest value over the receiver (the oracle's bound for a
    // cluster link).
    std::vector<float> F(n, 0.0f), Fmax(n, 0.0f), spread(n, 0.0f);
    std::vector<Color> V(n, Color(0.0f));
    std::vector<ChildVisibility> childV(n);

    // The form factors and shadow rays are most of a refinement's time: the stage's bar counts
    // the pending links.
    if (n > 0) {
        endStage(std::to_string(n) + " links to evaluate");  // the oracle's stage
        beginStage(step_ + ": form factors and visibility", n);
    }
    tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
    parallelForWithProgress(n, progress_, [&](size_t i) {
        if (!primary[i])
            return;
        const PendingLink& p = pending[i];
        const int j = reverse[i];
        if (isClusterLink(i)) {
            const ClusterKernel k = transfer_->clusterKernel(p.receiver, p.source);
            F[i] = k.K;
            Fmax[i] = k.Kmax;
            spread[i] = k.error;
            if (j >= 0) {
                const ClusterKernel kr = transfer_->clusterKernel(p.source, p.receiver);
                Fmax[static_cast<size_t>(j)] = kr.Kmax;
                spread[static_cast<size_t>(j)] = kr.error;
            }
        } else if (p.samples.max() > 0.0f) {
            // Visibility first, with the kernel samples' largest value for F_max: a hidden pair
            // is dropped without its form factor (one pair in nine in the Cornell box).
            bool adaptive = smallTransfer(p.source, p.samples.max());
            if (j >= 0)
                adaptive = adaptive &&
                           smallTransfer(p.receiver, pending[static_cast<size_t>(j)].samples.max());
            V[i] = transfer_->visibility(p.receiver, p.source, rays.local(), adaptive, &childV[i]);
            if (j >= 0) {
                V[static_cast<size_t>(j)] = V[i];
                childV[static_cast<size_t>(j)] = childV[i].reversed();
            }
            if (maxComponent(V[i]) <= 0.0f)
                return;
            F[i] = transfer_->exposedFormFactor(
                p.receiver, p.source, transfer_->formFactor(p.receiver, p.source, &p.samples));
            Fmax[i] = glm::max(p.samples.max(), F[i]);
            if (j >= 0) {
                const size_t r = static_cast<size_t>(j);
                F[r] = F[i] * static_cast<float>(transfer_->nodeArea(p.receiver) /
                                                 transfer_->nodeArea(p.source));
                Fmax[r] = glm::max(pending[r].samples.max(), F[r]);
            }
            return;
        } else {
            F[i] = transfer_->exposedFormFactor(
                p.receiver, p.source, transfer_->formFactor(p.receiver, p.source, &p.samples));
            Fmax[i] = glm::max(p.samples.max(), F[i]);
        }
        if (!(F[i] > 0.0f))
            return;
        bool adaptive = smallTransfer(p.source, Fmax[i]);
        if (j >= 0) {
            const size_t r = static_cast<size_t>(j);
            F[r] = F[i] * static_cast<float>(transfer_->nodeArea(p.receiver) /
                                             transfer_->nodeArea(p.source));
            if (!isClusterLink(i))
                Fmax[r] = glm::max(pending[r].samples.max(), F[r]);
            adaptive = adaptive && smallTransfer(p.receiver, Fmax[r]);
        }
        V[i] = transfer_->visibility(p.receiver, p.source, rays.local(), adaptive, &childV[i]);
        if (j >= 0) {
            V[static_cast<size_t>(j)] = V[i];
            childV[static_cast<size_t>(j)] = childV[i].reversed();
        }
    });
    // The links, each from its own receiver's samples.
    std::vector<Link> evaluated(n);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
        const PendingLink& p = pending[i];
        Link& link = evaluated[i];
        link.source = p.source;
        link.F = F[i];
        link.Fmax = Fmax[i];
        link.K = F[i] * V[i];
        link.childV = childV[i];
        if (!(link.F > 0.0f))
            return;
        if (isClusterLink(i)) {
            // The oracle's error of a cluster link, on both sides (clusterKernel); a receiving
            // cluster keeps the direction towards the source for its directional push.
            link.spread = link.Fmax = spread[i];
            const Vec3 toward = transfer_->nodeCenter(p.source) - transfer_->nodeCenter(p.receiver);
            if (isCluster(p.receiver) && glm::dot(toward, toward) > 0.0f)
                link.g = glm::normalize(toward);
            return;
        }
        if (glm::min(V[i].r, glm::min(V[i].g, V[i].b)) < 1.0f) {
            link.spread = link.Fmax;
            return;
        }
        float limiter = 1.0f;
        link.g = transfer_->linearModel(p.receiver, p.samples, link.F, limiter);
        link.spread = p.samples.spread(limiter);
    });
    for (size_t i = 0; i < n; ++i) {
        if (maxComponent(evaluated[i].K) > 0.0f)
            links_->linksOf(pending[i].receiver).push_back(evaluated[i]);
    }
    rays_ += rays.combine(std::plus<uint64_t>());
    secondsLinks_ += secondsSince(start);
}

// HSA91's initial linking: Refine every ordered pair of patch sides that can see each other (or,
// with clusters, the root cluster's self-link).
void RadiositySolver::linkPatches() {
    if (clusters_) {
        linkClusters();
        return;
    }
    updateThresholds(false);
    std::vector<RefinePair> pairs;
    const int roots = static_cast<int>(2 * mesh_.patchCount());
    for (int r = 0; r < roots; ++r) {
        for (int s = 0; s < roots; ++s)
            pairs.push_back({r, s});
    }
    refineAndLink(std::move(pairs));
}

// --- Clusters ----------------------------------------------------------------------------------

bool RadiositySolver::canSplitNode(int n) const {
    return isCluster(n) || subdivisible(element(n));
}

// The nodes one level below: a cluster's two child clusters, or both sides of each patch of a
// leaf cluster (those not wholly covered); an element side's four children (splitting the element
// if it is a leaf).
std::vector<int> RadiositySolver::nodeChildren(int n) {
    std::vector<int> result;
    if (isCluster(n)) {
        const Cluster& c = (*clusters_)[cluster(n)];
        if (!c.isLeaf()) {
            result = {clusterNode(c.children[0]), clusterNode(c.children[1])};
        } else {
            for (const int patch : clusters_->patches(cluster(n))) {
                for (const bool side : {true, false}) {
                    if (exposure_->exposed(node(patch, side)))
                        result.push_back(node(patch, side));
                }
            }
        }
        return result;
    }
    const int first = children(element(n));
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
        result.push_back(node(c, front(n)));
    return result;
}

// HSA91 "Refine" generalised to clusters (Sillion 1995, section 5): a pair with a cluster at one
// end or both is linked when clusterKernel allows it and its bound times the source's radiance is
// under the threshold; otherwise the larger of the two (by bounding radius, HSA91's choice) is
// replaced by its children, down to pairs of elements, which refine() takes over. A cluster's
// self-pair is all pairs of its children, self-pairs included. The pairs of children go to `next`.
void RadiositySolver::refineClusterPair(int receiver, int source, std::vector<RefinePair>& next,
                                        std::vector<PendingLink>& pending) {
    if (receiver == source) {
        const std::vector<int> c = nodeChildren(receiver);
        for (const int r : c) {
            for (const int s : c)
                next.push_back({r, s});
        }
        return;
    }
    if (!transfer_->mayInteractWithCluster(receiver, source))
        return;
    // An emitting cluster is never a source: the isotropic model would send the light of a lamp
    // facing down to the ceiling as much as to the floor. Emitters shine through their elements,
    // with their orientation (to clusters of receivers, though).
    const bool emittingSource = isCluster(source) && (*clusters_)[cluster(source)].emits;
    const ClusterKernel k = transfer_->clusterKernel(receiver, source);
    // The same oracle as refineLinks() applies, or a link it takes out for its receiver's sake
    // would come back unchanged every round.
    if (k.linkable && !emittingSource) {
        if (!exceedsThreshold(receiver, source, linkErrors(source, k.error, k.error))) {
            pending.push_back({receiver, source, {}});
            return;
        }
    }
    // A cluster can always be split; an element only while it is larger than the cluster.
    const float rr = transfer_->nodeRadius(receiver), rs = transfer_->nodeRadius(source);
    bool splitReceiver = rr >= rs;
    if (emittingSource)
        splitReceiver = false;
    else if (!isCluster(receiver))
        splitReceiver = rr > rs && canSplitNode(receiver);
    else if (!isCluster(source))
        splitReceiver = !(rs > rr && canSplitNode(source));
    for (const int c : nodeChildren(splitReceiver ? receiver : source))
        next.push_back(splitReceiver ? RefinePair{c, source} : RefinePair{receiver, c});
}

// Initial linking with clusters: the root's self-link, refined.
void RadiositySolver::linkClusters() {
    updateThresholds(false);
    refineAndLink({{clusterNode(0), clusterNode(0)}});
}

// HSA91 "RefineLinks": every link whose error (linkErrors) now exceeds the threshold, with the
// radiance of the last solve, is replaced by the links Refine() makes for the pair. Returns
// whether any link was refined.
bool RadiositySolver::refineLinks() {
    updateThresholds(true);
    std::vector<std::pair<int, Link>> candidates;
    const auto collect = [&](int receiver) {
        std::erase_if(links_->linksOf(receiver), [&](const Link& link) {
            const LinkErrors errors = linkErrors(link.source, link.spread, link.Fmax);
            const bool refinable = exceedsThreshold(receiver, link.source, errors) &&
                                   (canSplitNode(receiver) || canSplitNode(link.source));
            if (refinable)
                candidates.emplace_back(receiver, link);
            return refinable;
        });
    };
    for (size_t n = 0; n < links_->elementSides(); ++n)
        collect(static_cast<int>(n));
    for (size_t c = 0; c < links_->clusters(); ++c)
        collect(clusterNode(static_cast<int>(c)));
    std::vector<RefinePair> pairs;
    for (const auto& [receiver, link] : candidates)
        pairs.push_back({receiver, link.source, link.spread});
    refineAndLink(std::move(pairs));
    refinedLinks_ += candidates.size();
    return !candidates.empty();
}

// The punctual lights under the same oracle as links: a leaf whose direct term spreads over it by
// more than the threshold (a light pool's falloff, a shadow boundary) is split, down to the
// minimum area, and its children sample their own. Returns whether any element was split.
bool RadiositySolver::refineDirect() {
    updateThresholds(false);
    std::vector<int> queue;
    for (size_t e = 0; e < mesh_.elementCount(); ++e) {
        if (mesh_.isLeaf(static_cast<int>(e)))
            queue.push_back(static_cast<int>(e));
    }
    bool split = false;
    while (!queue.empty()) {
        for (const int e : queue) {
            const float spread =
                glm::max(irradiance_->spread(node(e, true)), irradiance_->spread(node(e, false)));
            if (spread > threshold_ && mesh_.canSplit(e))
                children(e);
        }
        queue = created_;
        split = split || !created_.empty();
        finishSplits();
    }
    return split;
}

// Adaptive subdivision by contrast, a posteriori (Cohen and Wallace 1993, chapter 6, "Domain
// Subdivision": split where the solution differs too much between neighbouring elements): a leaf
// side whose reflected radiance a and a neighbour's b (leaves sharing a vertex
// of its boundary, T-vertices included) differ by |a - b| > subdivision_threshold max(a, b), and by
// more than the oracle's absolute threshold (so that darkness does not split on noise), is split
// if it can be; the links it gathered itself go to its children through Refine, so that they see
// the variation the leaf could not. Links gathered by its ancestors stay and are pushed down.
// Returns whether any leaf was split.
bool RadiositySolver::subdivideByContrast() {
    const std::vector<int> leaves = leafElements();
    std::unordered_map<uint32_t, std::vector<int>> around;  // vertex -> leaves on it
    std::vector<std::vector<uint32_t>> boundary(leaves.size());
    for (size_t i = 0; i < leaves.size(); ++i) {
        boundary[i] = mesh_.leafBoundary(leaves[i]);
        for (const uint32_t v : boundary[i])
            around[v].push_back(leaves[i]);
    }
    const auto reflected = [&](int e, bool side) {
        const int n = node(e, side);
        return static_cast<double>(
            maxComponent(glm::max(radiance_->L(n) - radiance_->emission(n), Color(0.0f))));
    };
    // Only exposed leaf sides show light to compare (ElementExposure).
    const auto exposed = [&](int e, bool side) {
        return exposure_->fraction(node(e, side)) > 0.0f;
    };
    const double relative = settings_.subdivisionThreshold;
    std::vector<int> marked;
    for (size_t i = 0; i < leaves.size(); ++i) {
        const int e = leaves[i];
        if (!mesh_.canSplit(e))
            continue;
        bool contrast = false;
        for (const bool side : {true, false}) {
            if (!exposed(e, side))
                continue;
            const double a = reflected(e, side);
            for (const uint32_t v : boundary[i]) {
                for (const int other : around[v]) {
                    if (!exposed(other, side))
                        continue;
                    const double b = reflected(other, side);
                    const double d = std::abs(a - b);
                    contrast = contrast || (d > relative * std::max(a, b) && d > threshold_);
                }
            }
        }
        if (contrast)
            marked.push_back(e);
    }
    std::vector<RefinePair> pairs;
    for (const int e : marked) {
        const int first = children(e);
        for (const bool side : {true, false}) {
            for (const Link& link : links_->linksOf(node(e, side))) {
                for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
                    pairs.push_back({node(c, side), link.source});
            }
            links_->linksOf(node(e, side)).clear();
        }
    }
    refineAndLink(std::move(pairs));
    return !marked.empty();
}

// Sweeps until the estimated relative error is below `threshold`. The estimate is the a
// posteriori bound of a contraction, ||L_k - L*|| <= q / (1 - q) ||L_k - L_{k-1}|| (Banach's
// fixed-point theorem's a posteriori estimate; e.g. Kress 1998, "Numerical Analysis", chapter 3),
// with the contraction
// factor q measured as the largest ratio of successive changes over the last three sweeps. A
// change alone would stop far too early for rho near 1, where it is only (1 - q) times the
// remaining error. A change under the float radiance's own rounding (kRoundingChange) ends the
// iteration as a zero change does: there the sweeps only flip last bits, so the ratio of
// successive changes is 1 and the estimate infinite (seen in a furnace with a block on its floor,
// refined further than by the defaults: one element's last bit alternated for all 5000 sweeps of
// max_iterations).
// A refinement splits the same transfer among more links and leaves the spectral radius of the
// iteration about where it was: the gathers after the first take the largest q measured so far
// for their first three sweeps (each round's gather used to need four sweeps to estimate q anew,
// mostly after the first already met its threshold).
void RadiositySolver::iterate(double threshold, int round, const std::string& stage) {
    beginStage(stage, kGatherProgressUnits);
    links_->updateChildWeights();
    std::vector<double> changes, absoluteChanges;
    converged_ = false;
    // The bar measures the error's way down on a log scale, from the first sweep's change to the
    // threshold: the error of a contraction falls geometrically, so the bar moves at a steady rate
    // and its ETA holds.
    const size_t firstSweep = iterations_.size();
    uint64_t reported = 0;
    const auto report = [&](double error) {
        const double first = changes.front();
        double f = 1.0;
        if (error > threshold && first > threshold)
            f = std::clamp(std::log(first / error) / std::log(first / threshold), 0.0, 1.0);
        const auto units = static_cast<uint64_t>(f * kGatherProgressUnits);
        if (units > reported) {
            advanceStage(units - reported);
            reported = units;
        }
    };
    while (iterations_.size() < static_cast<size_t>(settings_.maxIterations)) {
        RadiosityIteration it;
        it.round = round;
        const ChangeSums sums = radiance_->sweep();
        it.change = sums.norm > 0.0 ? sums.change / sums.norm : 0.0;
        changes.push_back(it.change);
        absoluteChanges.push_back(sums.change);
        if (gatherDiverges(absoluteChanges))
            throwDivergence(stage,
                            absoluteChanges.back() /
                                absoluteChanges[absoluteChanges.size() - 1 - kDivergenceSweeps]);
        it.errorBound = std::numeric_limits<double>::infinity();
        if (it.change < kRoundingChange) {
            it.errorBound = it.change;
        } else if (changes.size() >= 4) {
            double q = 0.0;
            for (size_t k = changes.size() - 3; k < changes.size(); ++k)
                q = std::max(q, changes[k] / changes[k - 1]);
            contraction_ = std::max(contraction_, q);
            if (q < 1.0)
                it.errorBound = it.change * q / (1.0 - q);
        } else if (contraction_ >= 0.0 && contraction_ < 1.0) {
            it.errorBound = it.change * contraction_ / (1.0 - contraction_);
        }
        iterations_.push_back(it);
        report(std::isfinite(it.errorBound) ? it.errorBound : it.change);
        if (it.errorBound < threshold) {
            converged_ = true;
            break;
        }
    }
    std::ostringstream summary;
    summary.precision(3);
    const size_t sweeps = iterations_.size() - firstSweep;
    summary << sweeps << (sweeps == 1 ? " sweep" : " sweeps") << ", residual "
            << (iterations_.empty() ? 0.0 : iterations_.back().change) << ", error bound "
            << (iterations_.empty() ? 0.0 : iterations_.back().errorBound)
            << (converged_ ? "" : ", not converged");
    endStage(summary.str());
}

Color RadiositySolver::elementDirect(int e, bool side) const {
    return radiance_->elementDirect(e, side);
}

Color RadiositySolver::elementIndirect(int e, bool side) const {
    return radiance_->elementIndirect(e, side);
}

// The final gather: a Monte Carlo gather of each leaf side's indirect light from the solution, as
// Rushmeier, Patterson and Veerasamy 1993 ("Geometric Simplification for Indirect Illumination
// Calculations", Graphics Interface '93) gather from a coarse radiosity solution. The links'
// transfer errs where clusters stand for many patches (a receiving cluster gives all its patches
// one visible fraction: docs/benchmarks.md, "Where the rest of the walls' deficit lies"); rays
// see the solution itself. With x_k stratified over the side's exposed part and w_k
// cosine-distributed about its normal,
//     G = rho / N sum_k T_k L_r(y_k),
// y_k the first surface the mesh holds along the ray (meshed_hit.h, through thin glass of
// transmittance T_k) and L_r the reflected radiance of the leaf side there (reflectedAt), is an
// unbiased estimate of the light the side reflects of the others' reflected light, its indirect
// part (the first reflection of the sources, elementDirect, stays the links': an emitter seen by a
// few cosine rays would make G far noisier).
//
// One gather only corrects the last bounce; its light keeps the links' error one bounce back.
// So the gather drives a defect correction (iterative refinement with the links' operator as the
// approximate inverse): with T_h the links' transfer and T the gather's, the solution of
//     L = Le + rho D + T_h L + C,   C = (T - T_h) L
// solves L = Le + rho D + T L. Each pass adds to every leaf side's correction C (RadianceHierarchy,
// added in leafRadiance) the difference between G and its current indirect light, then the gather
// sweeps converge with the links (iterate). The error falls by the norm of (I - T_h)^-1 (T - T_h)
// per pass, small where the links are nearly right: the relative change of the correction was
// 2.2 % then 0.1 % on the modern hall, 1.3 % then 0.05 % on the Cornell box. The rays are the same
// in every pass (the same sampler seeds), so that the passes converge to the fixed point of one
// estimator rather than wander with new noise.
//
// The difference is taken as its mean over the patch side's exposed area, not per leaf: per leaf,
// 64 rays showed as blotches on the Cornell box's walls; the links' error it corrects (a cluster's
// one visible fraction, a far link's form factor) varies slowly over a patch. Measured on the
// modern hall (variant C of docs/benchmarks.md), per patch keeps about three quarters of what per
// leaf gains: walls 0.954 -> 0.960 (0.961 per leaf) of the path tracer.
void RadiositySolver::finalGather() {
    const std::vector<int> leaves = leafElements();
    radiance_->clearCorrection();
    for (int pass = 1; pass <= kMaxFinalGatherPasses; ++pass) {
        const std::string stage = "final gather " + std::to_string(pass);
        beginStage(stage + ": rays", mesh_.leafCount());
        const uint64_t raysBefore = finalGatherRays_;
        const std::vector<Color> gathered = gatherIndirect(leaves);
        // The change of each patch side's correction: the exposed-area mean of G less the
        // indirect light over its leaves.
        const size_t nodes = radiance_->nodeCount();
        std::vector<Color> patchDelta(2 * mesh_.patchCount(), Color(0.0f));
        std::vector<double> patchArea(2 * mesh_.patchCount(), 0.0);
        for (size_t nd = 0; nd < nodes; ++nd) {
            if (!(gathered[nd].r >= 0.0f))
                continue;
            const int n = static_cast<int>(nd);
            const double area = mesh_.area(element(n)) * exposure_->fraction(n);
            const int root = node(mesh_.patch(element(n)), front(n));
            patchDelta[root] += static_cast<float>(area) *
                                (gathered[nd] - (radiance_->L(n) - radiance_->emission(n) -
                                                 radiance_->elementDirect(element(n), front(n))));
            patchArea[root] += area;
        }
        // Area-weighted L1 norms of the change and of the gathered light, over leaf sides.
        double change = 0.0, norm = 0.0;
        for (size_t nd = 0; nd < nodes; ++nd) {
            if (!(gathered[nd].r >= 0.0f))
                continue;
            const int n = static_cast<int>(nd);
            const int root = node(mesh_.patch(element(n)), front(n));
            const Color delta = patchDelta[root] / static_cast<float>(patchArea[root]);
            radiance_->addCorrection(n, delta);
            const double area = mesh_.area(element(n)) * exposure_->fraction(n);
            change += area * channelSum(glm::abs(delta));
            norm += area * channelSum(gathered[nd]);
        }
        const double relativeChange = norm > 0.0 ? change / norm : 0.0;
        std::ostringstream summary;
        summary.precision(3);
        summary << finalGatherRays_ - raysBefore << " rays, change " << relativeChange;
        endStage(summary.str());
        finalGatherPasses_ = pass;
        iterate(settings_.convergence, rounds_, stage + ": gather");
        computeVertexValues();
        if (relativeChange < kFinalGatherChange)
            break;
    }
}

// The reflected radiance of the leaf side a final-gather ray meets, flat as the solution holds it
// (the Gouraud-interpolated values of the view mix the sides of a crease at its vertices, and their
// mean over an element is not the element's, which the fluxes and the links use).
Color RadiositySolver::reflectedAt(const MeshedHit& y) const {
    const int leaf = mesh_.locate(y.hit.mesh, y.hit.triangle, y.hit.barycentric).element;
    const auto [e, side] =
        leafSideSeenAt(scene_, mesh_, exposure_->coincident(), leaf, y.front, y.hit.p);
    const int n = node(e, side);
    return glm::max(radiance_->L(n) - radiance_->emission(n), Color(0.0f));
}

std::vector<int> RadiositySolver::leafElements() const {
    std::vector<int> leaves;
    for (size_t e = 0; e < mesh_.elementCount(); ++e) {
        if (mesh_.isLeaf(static_cast<int>(e)))
            leaves.push_back(static_cast<int>(e));
    }
    return leaves;
}

int RadiositySolver::finalGatherRays() const {
    if (settings_.finalGatherRays != RadiositySettings::kAutoFinalGather)
        return settings_.finalGatherRays;
    return clusters_ ? RadiositySettings::kClusterFinalGatherRays : 0;
}

// G of finalGather() for every exposed side of `leaves` that reflects, per node; -1 elsewhere.
std::vector<Color> RadiositySolver::gatherIndirect(const std::vector<int>& leaves) {
    const auto n = static_cast<uint32_t>(finalGatherRays());
    std::vector<Color> gathered(radiance_->nodeCount(), Color(-1.0f));
    tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
    parallelForWithProgress(leaves.size(), progress_, [&](size_t i) {
        const int e = leaves[i];
        const Color rho = mesh_.rho(e);
        if (!(maxComponent(rho) > 0.0f))
            return;
        uint64_t& count = rays.local();
        for (const bool side : {true, false}) {
            const int nd = node(e, side);
            if (!exposure_->exposed(nd))
                continue;
            Sampler sampler(kFinalGatherSeed);
            Color sum(0.0f);
            uint32_t used = 0;
            for (uint32_t k = 0; k < n; ++k) {
                sampler.startPixelSample(IVec2(e, side ? 0 : 1), k);
                const ElementSample x = sampleElement(scene_, mesh_, e, sampler.get2D());
                const Vec3 normal = side ? x.n : -x.n;
                if (exposure_->partlyCovered(nd) && exposure_->covered(e, x, normal, count))
                    continue;
                const Vec3 w =
                    Frame::fromNormal(normal).toWorld(sampleCosineHemisphere(sampler.get2D()));
                ++used;
                const std::optional<MeshedHit> y = firstMeshedHit(
                    scene_, mesh_, Ray{offsetRayOrigin(x.p, x.pError, x.n, w), w}, count);
                if (y)
                    sum += y->transmittance * reflectedAt(*y);
            }
            if (used > 0)
                gathered[static_cast<size_t>(nd)] = rho * sum / static_cast<float>(used);
        }
    });
    const uint64_t cast = rays.combine(std::plus<uint64_t>());
    finalGatherRays_ += cast;
    rays_ += cast;
    return gathered;
}

void RadiositySolver::computeVertexValues() {
    // The whole reflected radiance last, so that the mesh is left with the front's reflected
    // radiance.
    vertexIndirect_.compute(mesh_, exposure_->shownValues([this](int e, bool side) {
        return elementIndirect(e, side);
    }));
    vertexReflected_.compute(mesh_, exposure_->shownValues([this](int element, bool side) {
        const int n = node(element, side);
        return glm::max(radiance_->L(n) - radiance_->emission(n), Color(0.0f));
    }));
}

void RadiositySolver::beginStage(const std::string& name, uint64_t total) {
    if (progress_)
        progress_->beginStage(name, total);
}

void RadiositySolver::advanceStage(uint64_t work) {
    if (progress_)
        progress_->advance(work);
}

void RadiositySolver::endStage(const std::string& summary) {
    if (progress_)
        progress_->endStage(summary);
}

// --- The whole solution ------------------------------------------------------------------------

// HSA91's "HierarchicalRadiosity" with brightness-weighted refinement: link the patches with the
// oracle on the initial radiance (emission and punctual direct light), then alternate solving and
// refining the links with the current radiance until nothing is refined.
void RadiositySolver::solve(SolveProgress* progress) {
    progress_ = progress;
    const auto start = std::chrono::steady_clock::now();
    const auto linksAndLeaves = [&] {
        return std::to_string(linkCount()) + " links, " + std::to_string(mesh_.leafCount()) +
               " leaves";
    };

    // Stage 1: the punctual lights' direct light; the initial radiance is Le + rho D.
    const std::vector<int> leaves = leafElements();
    std::vector<int> elements(mesh_.elementCount());
    std::iota(elements.begin(), elements.end(), 0);
    rays_ += exposure_->compute(elements);
    const bool punctual = !punctualLights(scene_).empty();
    if (punctual)
        beginStage("direct light of the punctual lights", leaves.size());
    rays_ += irradiance_->compute(leaves, progress_);
    radiance_->pushPullAll();
    refineDirect();
    radiance_->pushPullAll();
    if (punctual)
        endStage(std::to_string(mesh_.leafCount()) + " leaves");
    secondsDirect_ = secondsSince(start);
    peakDirect_ = peakMemoryMiB();

    // Stage 2: initial links between the patches (the oracle, then the links' form factors).
    auto stageStart = std::chrono::steady_clock::now();
    step_ = "linking";
    beginStage("linking: refinement oracle", 0);
    linkPatches();
    endStage(linksAndLeaves());
    secondsLinking_ = secondsSince(stageStart);
    peakLinking_ = peakMemoryMiB();

    // Stage 3: gather sweeps and refinement rounds.
    const double roundThreshold = std::max(settings_.convergence, kRoundConvergence);
    stageStart = std::chrono::steady_clock::now();
    iterate(roundThreshold, 0, "gather");
    secondsSolve_ += secondsSince(stageStart);
    // One refinement step, then, if it changed anything, the solve of the new round.
    int round = 0;
    const auto step = [&](const std::string& name, const auto& refineStep) {
        stageStart = std::chrono::steady_clock::now();
        step_ = name + " " + std::to_string(round + 1);
        beginStage(step_ + ": refinement oracle", 0);
        const bool refined = refineStep();
        endStage(refined ? linksAndLeaves() : "nothing to refine");
        secondsRefine_ += secondsSince(stageStart);
        peakRefine_ = peakMemoryMiB();
        if (!refined)
            return false;
        rounds_ = ++round;
        stageStart = std::chrono::steady_clock::now();
        iterate(roundThreshold, round, "gather, round " + std::to_string(round));
        secondsSolve_ += secondsSince(stageStart);
        return true;
    };
    const auto refineRound = [&] {
        const bool links = refineLinks();
        return refineDirect() || links;
    };
    while (round < settings_.maxRefinements && step("refinement round", refineRound)) {
    }
    // Adaptive subdivision by contrast with the neighbours (subdivision_threshold).
    const auto subdivide = [&] { return subdivideByContrast(); };
    for (int pass = 0; pass < kSubdivisionPasses && settings_.subdivisionThreshold > 0.0f; ++pass) {
        if (!step("subdivision round", subdivide))
            break;
    }
    stageStart = std::chrono::steady_clock::now();
    iterate(settings_.convergence, round, "gather to convergence");
    beginStage("push-pull of the direct part, vertex values", 0);
    radiance_->computeDirectPart(*irradiance_);
    computeVertexValues();
    endStage(std::to_string(mesh_.vertexCount()) + " vertices");
    secondsSolve_ += secondsSince(stageStart);
    if (finalGatherRays() > 0) {
        stageStart = std::chrono::steady_clock::now();
        finalGather();
        secondsFinalGather_ = secondsSince(stageStart);
    }
    secondsTotal_ = secondsSince(start);
    peakSolve_ = peakMemoryMiB();
    progress_ = nullptr;
}

Color RadiositySolver::radiance(uint32_t mesh, uint32_t triangle, Vec3 b, bool includeEmission,
                                bool front) const {
    const ElementPoint point = mesh_.locate(mesh, triangle, b);
    if (point.element < 0 || vertexReflected_.empty())
        return Color(0.0f);
    Color L = vertexReflected_.interpolate(mesh_, point, front);
    if (!includeEmission)
        return L;
    // A side hidden under a coincident face shows that face's light (shownValues), its emission
    // too.
    const auto [e, side] = exposure_->shownSide(point.element, front);
    return L + radiance_->emission(node(e, side));
}

Color RadiositySolver::indirectRadiance(uint32_t mesh, uint32_t triangle, Vec3 b,
                                        bool front) const {
    return vertexIndirect_.interpolate(mesh_, mesh_.locate(mesh, triangle, b), front);
}

// A diverging gather comes from the scene: some receiver's rho times the sum of its form factors
// exceeds 1, which closed geometry cannot do unless surfaces are counted twice. Coincident faces
// in one plane are counted once (coincident_faces.h; they caused this in the modern hall);
// whatever else still does it, the error names the scene mesh and the place where the radiance
// grew most, the brightest leaf.
void RadiositySolver::throwDivergence(const std::string& stage, double growth) const {
    int brightest = -1;
    float most = -1.0f;
    for (size_t n = 0; n < radiance_->nodeCount(); ++n) {
        const int e = element(static_cast<int>(n));
        const Color& L = radiance_->L(static_cast<int>(n));
        if (mesh_.isLeaf(e) && maxComponent(L) > most) {
            most = maxComponent(L);
            brightest = e;
        }
    }
    const SceneDescription& description = scene_.description();
    const Mesh& mesh = description.meshes[mesh_.sceneMesh(brightest)];
    const glm::dvec3 at = glm::dvec3(mesh_.centroid(brightest)) + description.origin;
    std::ostringstream message;
    message << "mesh " << mesh.name << ", around (" << at.x << ", " << at.y << ", " << at.z
            << ") m: the radiosity gather diverges in " << stage << " (the change of a sweep grew "
            << kDivergenceSweeps << " sweeps in a row, " << growth
            << " times in all): rho times the sum of a receiver's form factors exceeds 1 there, "
               "surfaces counted twice (duplicated or interpenetrating geometry?)";
    throw SceneError(description.file, mesh.source, message.str());
}

// --- Statistics --------------------------------------------------------------------------------

PassStats RadiositySolver::stats() const {
    const RadiosityMeshStats mesh = mesh_.stats();
    const size_t links = linkCount();
    size_t memory = mesh.memoryBytes + links * sizeof(Link) +
                    links_->elementSides() * (sizeof(std::vector<Link>) + 3 * sizeof(Color) +
                                              sizeof(std::array<Color, 4>)) +
                    links_->clusters() * (sizeof(Cluster) + sizeof(std::vector<Link>));
    memory += vertexReflected_.memoryBytes() + vertexIndirect_.memoryBytes() +
              radiance_->directPartBytes() + exposure_->memoryBytes();
    const RadiosityIteration last = iterations_.empty() ? RadiosityIteration{} : iterations_.back();
    // The reflected luminous flux of each part, pi sum A Y(L) over the leaf sides (lm).
    double directFlux = 0.0, indirectFlux = 0.0;
    for (size_t e = 0; e < mesh_.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh_.isLeaf(element))
            continue;
        for (const bool side : {true, false}) {
            const double area = mesh_.area(element) * exposure_->fraction(node(element, side));
            directFlux += kPi * area * luminance(elementDirect(element, side));
            indirectFlux += kPi * area * luminance(elementIndirect(element, side));
        }
    }
    const DepositedFlux* deposits = irradiance_->deposits();
    const float depositedFlux = deposits ? luminance(deposits->totalPower()) : 0.0f;
    return {{"patches", std::to_string(mesh.patches)},
            {"elements", std::to_string(mesh.elements)},
            {"leaves", std::to_string(mesh.leaves)},
            {"clusters", std::to_string(clusters_ ? clusters_->size() : 0)},
            {"sealed_solids", std::to_string(exposure_->sealed().count())},
            {"coincident_patches", std::to_string(exposure_->coincident().hiddenPatches())},
            {"coincident_area_m2", formatStat(exposure_->coincident().hiddenArea())},
            {"links", std::to_string(links)},
            {"refinement_rounds", std::to_string(rounds_)},
            {"refined_links", std::to_string(refinedLinks_)},
            {"iterations", std::to_string(iterations_.size())},
            {"residual", formatStat(last.change)},
            {"error_bound", formatStat(last.errorBound)},
            {"converged", converged_ ? "yes" : "no"},
            {"rays", std::to_string(rays_)},
            {"deposited_photons", std::to_string(deposits ? deposits->count() : 0)},
            {"deposited_flux_lm", formatStat(depositedFlux)},
            {"direct_flux_lm", formatStat(directFlux)},
            {"indirect_flux_lm", formatStat(indirectFlux)},
            {"memory_mib", formatStat(static_cast<double>(memory) / (1024.0 * 1024.0))},
            {"seconds_direct", formatStat(secondsDirect_)},
            {"seconds_linking", formatStat(secondsLinking_)},
            {"seconds_form_factors", formatStat(secondsLinks_)},
            {"seconds_refine", formatStat(secondsRefine_)},
            {"seconds_solve", formatStat(secondsSolve_)},
            {"final_gather_rays_per_side", std::to_string(finalGatherRays())},
            {"final_gather_passes", std::to_string(finalGatherPasses_)},
            {"final_gather_rays", std::to_string(finalGatherRays_)},
            {"seconds_final_gather", formatStat(secondsFinalGather_)},
            {"seconds", formatStat(secondsTotal_)},
            {"peak_memory_mib_direct", formatStat(peakDirect_)},
            {"peak_memory_mib_linking", formatStat(peakLinking_)},
            {"peak_memory_mib_refine", formatStat(peakRefine_)},
            {"peak_memory_mib_solve", formatStat(peakSolve_)}};
}

}  // namespace penumbra
