// HSA91's Refine / Link / RefineLinks with an error-based refinement oracle, over element sides
// and clusters.
#include "radiosity/link_refiner.h"

#include "core/stats.h"
#include "radiosity/solver_nodes.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace penumbra {

namespace {

// The receiver-relative criterion's floor (exceedsThreshold), as a fraction of the scene's mean
// radiance in each channel: a receiver darker than this is refined as if it were this bright.
constexpr float kRelativeFloor = 0.1f;

// Pairs of a level the oracle examines between two looks at the time limit (about 0.1 s of
// kernel samples on the modern hall's 2 cores).
constexpr size_t kRefineSlice = size_t{1} << 16;

// Once the time is up (coarse_), the radius, as a fraction of the root cluster's, under which
// close nodes are linked with a softened kernel rather than split (LinkTransfer::clusterKernel),
// and a cluster's pairs within itself are not linked at all.
constexpr float kCoarseRadius = 1.0f / 8.0f;

}  // namespace

LinkRefiner::LinkRefiner(RadiosityMesh& mesh, const RadiositySettings& settings,
                         const ElementExposure& exposure, const DirectIrradiance& irradiance,
                         const ClusterTree* clusters, const LinkTransfer& transfer,
                         LinkHierarchy& links, const RadianceHierarchy& radiance, Split split,
                         Settle settle)
    : mesh_(mesh),
      settings_(settings),
      exposure_(exposure),
      irradiance_(irradiance),
      clusters_(clusters),
      transfer_(transfer),
      links_(links),
      radiance_(radiance),
      split_(std::move(split)),
      settle_(std::move(settle)),
      coarseRadius_(clusters && !clusters->empty() ? (*clusters)[0].radius * kCoarseRadius : 0.0f) {
}

// The oracle's thresholds from the current solution. threshold_, the absolute one: epsilon times
// the scene's mean radiance, sum_i A_i max(L_i) / sum_i A_i over the patches (both sides counted
// in the sum, the area once), so that epsilon is a fraction of a typical radiance whatever the
// scene's units and brightness. With `relativeFloor` also relativeFloor_, the receiver-relative
// criterion's floor (exceedsThreshold): kRelativeFloor times the same mean per channel.
void LinkRefiner::updateThresholds(bool relativeFloor, float epsilonScale) {
    double largest = 0.0, area = 0.0;
    Color perChannel(0.0f);
    for (size_t p = 0; p < mesh_.patchCount(); ++p) {
        const int e = static_cast<int>(p);
        const Color &Lfront = radiance_.L(node(e, true)), &Lback = radiance_.L(node(e, false));
        const Color L = Lfront + Lback;
        area += mesh_.area(e);
        largest += mesh_.area(e) * static_cast<double>(maxComponent(Lfront) + maxComponent(Lback));
        perChannel += mesh_.area(e) * L;
    }
    if (!(area > 0.0))
        return;
    threshold_ = epsilonScale * settings_.epsilon * largest / area;
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
bool LinkRefiner::exceedsThreshold(int receiver, int source, const LinkErrors& errors) const {
    if (coarse_)
        return false;
    const double error = std::max(errors.receiver, errors.source);
    if (error > threshold_)
        return true;
    if (isCluster(receiver) || !(maxComponent(relativeFloor_) > 0.0f))
        return false;
    const Color Ls = radiance_.nodeRadiance(source);
    const float LsMax = maxComponent(Ls);
    if (!(LsMax > 0.0f))
        return false;
    const Color rho = mesh_.rho(element(receiver));
    const Color Lr = radiance_.nodeRadiance(receiver);
    for (int c = 0; c < 3; ++c) {
        const double reflected = error * static_cast<double>(rho[c] * Ls[c] / LsMax);
        if (reflected > settings_.epsilon * static_cast<double>(glm::max(Lr[c], relativeFloor_[c])))
            return true;
    }
    return false;
}

// The first of e's four children, splitting e first if it is a leaf. New children start from the
// parent's radiance and direct light until the next sweep and finishSplits() replace them.
int LinkRefiner::children(int e) {
    if (!mesh_.isLeaf(e))
        return mesh_.firstChild(e);
    return splitLeaf(e, mesh_.minElementArea(e));
}

int LinkRefiner::splitLeaf(int e, float minChildArea) {
    const int first = mesh_.split(e, minChildArea);
    split_(e, first);
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
        created_.push_back(c);
    return first;
}

void LinkRefiner::finishSplits() {
    settle_(created_);
    created_.clear();
}

// The new elements' exposed fractions come before the new links' evaluation: a link with a partly
// covered end counts only the exposed points (visibility, exposedFormFactor).
void LinkRefiner::refineAndLink(std::vector<RefinePair> pairs, const std::string& step) {
    std::vector<PendingLink> pending;
    refine(std::move(pairs), pending);
    if (abandoned_)
        return;
    finishSplits();
    evaluateLinks(pending, step);
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
LinkErrors LinkRefiner::linkErrors(int source, float spread, float Fmax) const {
    return {static_cast<double>(spread) * maxComponent(radiance_.nodeRadiance(source)),
            static_cast<double>(Fmax) * (radiance_.nodeLmax(source) - radiance_.nodeLmin(source))};
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
void LinkRefiner::refine(std::vector<RefinePair> batch, std::vector<PendingLink>& pending) {
    while (!batch.empty()) {
        std::vector<RefinePair> next;
        // In slices, so that a time limit is seen within a level too (setTimeLimit).
        for (size_t begin = 0; begin < batch.size(); begin += kRefineSlice) {
            if (abandonLinking()) {
                abandoned_ = true;
                return;
            }
            const bool late = timeIsUp() || (linking_ && onTimeUp_ == OnTimeUp::Coarsen &&
                                             oracleTooLong(deadline_, 4));
            coarse_ = coarse_ || late;
            const size_t end = std::min(batch.size(), begin + kRefineSlice);
            refineSlice(std::span(batch).subspan(begin, end - begin), next, pending);
        }
        batch = std::move(next);
    }
}

// A slice of one level's pairs of refine(): their kernel samples (a cluster pair's kernel) in
// parallel, then the decisions in order.
void LinkRefiner::refineSlice(std::span<const RefinePair> batch, std::vector<RefinePair>& next,
                              std::vector<PendingLink>& pending) {
    if (progress_)
        progress_->advance(batch.size());  // the oracle's stage counts the pairs it examines
    std::vector<KernelSamples> samples(batch.size());
    std::vector<ClusterKernel> clusterKernels(batch.size());
    std::vector<char> interacts(batch.size(), 0);
    tbb::parallel_for(size_t(0), batch.size(), [&](size_t i) {
        const RefinePair& p = batch[i];
        if (isCluster(p.receiver) || isCluster(p.source)) {
            if (p.receiver != p.source && transfer_.mayInteractWithCluster(p.receiver, p.source)) {
                interacts[i] = 1;
                clusterKernels[i] = transfer_.clusterKernel(p.receiver, p.source, softRadius());
            }
            return;
        }
        if (!transfer_.mayInteract(p.receiver, p.source))
            return;
        interacts[i] = 1;
        samples[i] = transfer_.kernelSamples(p.receiver, p.source);
    });
    for (size_t i = 0; i < batch.size(); ++i) {
        const RefinePair& p = batch[i];
        if (isCluster(p.receiver) || isCluster(p.source)) {
            if (p.receiver == p.source || interacts[i])
                refineClusterPair(p.receiver, p.source, clusterKernels[i], next, pending);
            continue;
        }
        if (!interacts[i])
            continue;
        const KernelSamples& k = samples[i];
        const int er = element(p.receiver), es = element(p.source);
        const bool canR = mesh_.subdivisible(er), canS = mesh_.subdivisible(es);
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
}

void LinkRefiner::setTimeLimit(Deadline deadline, OnTimeUp onTimeUp, Deadline abandonAt) {
    deadline_ = deadline;
    onTimeUp_ = onTimeUp;
    abandonAt_ = onTimeUp == OnTimeUp::Abandon ? deadline : abandonAt;
}

// The links the oracle decides must all be evaluated after it, which costs more than deciding
// them: an oracle that has used half of the time its linking had left will not see its links
// made in time (the grey-white room lit by its sky: 39 s of oracle, then abandoned at the
// deadline, leaving the path tracer 13 s of 64). A solve that coarsens instead cannot stop the
// evaluation, so its oracle stops at a quarter: there, with the links as they stood at its
// deadline, the evaluation took 2.5 times as long as the oracle.
bool LinkRefiner::oracleTooLong(Deadline until, int share) const {
    if (!until)
        return false;
    const auto now = std::chrono::steady_clock::now();
    return now - linkingStart_ > (*until - linkingStart_) / share;
}

bool LinkRefiner::abandonLinking() const {
    return linking_ && abandonAt_ && (deadlinePassed(abandonAt_) || oracleTooLong(abandonAt_, 2));
}

bool LinkRefiner::timeIsUp() {
    coarse_ = coarse_ || deadlinePassed(deadline_);
    return coarse_;
}

// Whether a link's whole transfer, F_max times the larger of its source's radiance and the
// scene's mean (which a dark source may reach once lit), is under the oracle's threshold: then an
// error in its visible fraction cannot matter more than the refinement tolerates. (Allowing a
// quarter of the transfer instead, on the grounds that four stratified pairs rarely miss more,
// lets the shadow of a block be missed: 12 % of the mean on a leaf against the dense solve.)
bool LinkRefiner::smallTransfer(int source, float Fmax) const {
    const double mean = threshold_ / settings_.epsilon;
    return Fmax *
               std::max(mean, static_cast<double>(maxComponent(radiance_.nodeRadiance(source)))) <=
           threshold_;
}

// Form factor, visibility and linear model of new links, in parallel (the refinement that decided
// them is sequential because it splits elements). Links that carry nothing (F = 0, or fully
// occluded) are dropped: no oracle would refine them. A partly occluded link gets no slope (the
// visibility's variation is unknown) and a spread of its whole F_max, as a shadow boundary may
// cross the receiver anywhere. Once the time is up (coarse_), every link's visibility is
// estimated adaptively (LinkTransfer::visibility), a rougher but quicker solution. A link with a
// cluster at either end carries the isotropic kernel (clusterKernel) times the visible fraction,
// with no slope and its error bound as both spreads.
//
// A pair listed in both directions (as the initial linking makes many) is evaluated once: the
// reverse link takes F_ji = A_i F_ij / A_j and the same visible fraction, which halves its work and
// makes the pair's transfer exactly reciprocal. (Keeping form factors for a reverse link of a
// later round gained nothing measurable on the Cornell box: refinement weighs each source's own
// radiance, so it seldom asks for the reverse.)
void LinkRefiner::evaluateLinks(const std::vector<PendingLink>& pending, const std::string& step) {
    const auto start = std::chrono::steady_clock::now();
    const size_t n = pending.size();
    // Pair each link with its reverse, if pending too. A partly covered end makes the two
    // directions' transfers differ (visibility, exposedFormFactor).
    const ReversePairs pairs = pairReverses(pending, [&](const PendingLink& p) {
        return !exposure_.partlyCovered(p.receiver) && !exposure_.partlyCovered(p.source);
    });
    const std::vector<int>& reverse = pairs.reverse;
    const std::vector<char>& primary = pairs.primary;
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
    if (n > 0 && progress_) {
        progress_->endStage(std::to_string(n) + " links to evaluate");  // the oracle's stage
        progress_->beginStage(step + ": form factors and visibility", n);
    }
    tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
    // Once the deadline has passed, made coarser between chunks: the links after take their
    // visibility adaptively. The initial linking of a solve that may be abandoned (abandonAt_) is
    // abandoned (no link is made) once that time has passed, or as soon as the links evaluated
    // so far say the rest will not be done by then, so that the time goes to the pass that
    // traces without it. The rest is projected at its recent pace (RecentPace), since the links
    // went coarse if they did, as coarse links are quicker; one that goes coarse before it would
    // be abandoned is judged only at that pace (on the grey-white room's 16-s previews, whose
    // share ends early in the evaluation, the pace before it gave up links made by 14 s).
    const Deadline abandonAt = linking_ ? abandonAt_ : std::nullopt;
    RecentPace pace(n);
    const auto evaluationStart = std::chrono::steady_clock::now();
    const auto late = [&](size_t done) {
        if (!coarse_ && timeIsUp())
            pace.restart(secondsSince(evaluationStart), done);
        if (!abandonAt)
            return false;
        const double secondsLeft =
            std::chrono::duration<double>(*abandonAt - std::chrono::steady_clock::now()).count();
        if (secondsLeft <= 0.0)
            return true;
        if (!coarse_ && *deadline_ < *abandonAt)
            return false;
        return pace.overruns(secondsSince(evaluationStart), done, secondsLeft);
    };
    const bool complete = parallelForWithProgress(
        n, progress_,
        [&](size_t i) {
            if (!primary[i])
                return;
            const PendingLink& p = pending[i];
            const int j = reverse[i];
            if (isClusterLink(i)) {
                const ClusterKernel k = transfer_.clusterKernel(p.receiver, p.source, softRadius());
                F[i] = k.K;
                Fmax[i] = k.Kmax;
                spread[i] = k.error;
                if (j >= 0) {
                    const ClusterKernel kr =
                        transfer_.clusterKernel(p.source, p.receiver, softRadius());
                    Fmax[static_cast<size_t>(j)] = kr.Kmax;
                    spread[static_cast<size_t>(j)] = kr.error;
                }
            } else if (p.samples.max() > 0.0f) {
                // Visibility first, with the kernel samples' largest value for F_max: a hidden pair
                // is dropped without its form factor (one pair in nine in the Cornell box).
                bool adaptive = coarse_ || smallTransfer(p.source, p.samples.max());
                if (j >= 0)
                    adaptive =
                        adaptive &&
                        smallTransfer(p.receiver, pending[static_cast<size_t>(j)].samples.max());
                V[i] =
                    transfer_.visibility(p.receiver, p.source, rays.local(), adaptive, &childV[i]);
                if (j >= 0) {
                    V[static_cast<size_t>(j)] = V[i];
                    childV[static_cast<size_t>(j)] = childV[i].reversed();
                }
                if (maxComponent(V[i]) <= 0.0f)
                    return;
                F[i] = transfer_.exposedFormFactor(
                    p.receiver, p.source, transfer_.formFactor(p.receiver, p.source, &p.samples));
                Fmax[i] = glm::max(p.samples.max(), F[i]);
                if (j >= 0) {
                    const size_t r = static_cast<size_t>(j);
                    F[r] = F[i] * static_cast<float>(transfer_.nodeArea(p.receiver) /
                                                     transfer_.nodeArea(p.source));
                    Fmax[r] = glm::max(pending[r].samples.max(), F[r]);
                }
                return;
            } else {
                F[i] = transfer_.exposedFormFactor(
                    p.receiver, p.source, transfer_.formFactor(p.receiver, p.source, &p.samples));
                Fmax[i] = glm::max(p.samples.max(), F[i]);
            }
            if (!(F[i] > 0.0f))
                return;
            bool adaptive = coarse_ || smallTransfer(p.source, Fmax[i]);
            if (j >= 0) {
                const size_t r = static_cast<size_t>(j);
                F[r] = F[i] * static_cast<float>(transfer_.nodeArea(p.receiver) /
                                                 transfer_.nodeArea(p.source));
                if (!isClusterLink(i))
                    Fmax[r] = glm::max(pending[r].samples.max(), F[r]);
                adaptive = adaptive && smallTransfer(p.receiver, Fmax[r]);
            }
            V[i] = transfer_.visibility(p.receiver, p.source, rays.local(), adaptive, &childV[i]);
            if (j >= 0) {
                V[static_cast<size_t>(j)] = V[i];
                childV[static_cast<size_t>(j)] = childV[i].reversed();
            }
        },
        deadline_ ? std::function<bool(size_t)>(late) : nullptr);
    if (!complete) {
        abandoned_ = true;
        return;
    }
    // The links that carry light, each from its own receiver's samples, appended to their
    // receivers' lists in the order of `pending` (the gather's sums, and so the solution, do not
    // depend on the thread count): grouped by receiver, each receiver's list filled by one task.
    const auto makeLink = [&](size_t i) {
        const PendingLink& p = pending[i];
        Link link;
        link.source = p.source;
        link.F = F[i];
        link.Fmax = Fmax[i];
        link.K = F[i] * V[i];
        link.childV = childV[i];
        if (isClusterLink(i)) {
            // The oracle's error of a cluster link, on both sides (clusterKernel); a receiving
            // cluster keeps the direction towards the source for its directional push.
            link.spread = link.Fmax = spread[i];
            const Vec3 toward = transfer_.nodeCenter(p.source) - transfer_.nodeCenter(p.receiver);
            if (isCluster(p.receiver) && glm::dot(toward, toward) > 0.0f)
                link.g = glm::normalize(toward);
            return link;
        }
        if (glm::min(V[i].r, glm::min(V[i].g, V[i].b)) < 1.0f) {
            link.spread = link.Fmax;
            return link;
        }
        float limiter = 1.0f;
        link.g = transfer_.linearModel(p.receiver, p.samples, link.F, limiter);
        link.spread = p.samples.spread(limiter);
        return link;
    };
    const ReceiverGroups groups(pending,
                                [&](size_t i) { return maxComponent(F[i] * V[i]) > 0.0f; });
    tbb::parallel_for(size_t(0), groups.size(), [&](size_t g) {
        const std::span<const uint32_t> members = groups.members(g);
        std::vector<Link>& links = links_.linksOf(pending[members.front()].receiver);
        links.reserve(links.size() + members.size());
        for (const uint32_t i : members)
            links.push_back(makeLink(i));
    });
    rays_ += rays.combine(std::plus<uint64_t>());
    secondsLinks_ += secondsSince(start);
}

// HSA91's initial linking: Refine every ordered pair of patch sides that can see each other (or,
// with clusters, the root cluster's self-link).
void LinkRefiner::linkPatches(const std::string& step, float epsilonScale) {
    linking_ = true;
    linkingStart_ = std::chrono::steady_clock::now();
    updateThresholds(false, epsilonScale);
    if (clusters_) {
        refineAndLink({{clusterNode(0), clusterNode(0)}}, step);
    } else {
        std::vector<RefinePair> pairs;
        const int roots = static_cast<int>(2 * mesh_.patchCount());
        for (int r = 0; r < roots; ++r) {
            for (int s = 0; s < roots; ++s)
                pairs.push_back({r, s});
        }
        refineAndLink(std::move(pairs), step);
    }
    linking_ = false;
}

bool LinkRefiner::canSplitNode(int n) const {
    return isCluster(n) || mesh_.subdivisible(element(n));
}

// The nodes one level below: a cluster's two child clusters, or both sides of each patch of a
// leaf cluster (those not wholly covered); an element side's four children (splitting the element
// if it is a leaf).
std::vector<int> LinkRefiner::nodeChildren(int n) {
    std::vector<int> result;
    if (isCluster(n)) {
        const Cluster& c = (*clusters_)[cluster(n)];
        if (!c.isLeaf()) {
            result = {clusterNode(c.children[0]), clusterNode(c.children[1])};
        } else {
            for (const int patch : clusters_->patches(cluster(n))) {
                for (const bool side : {true, false}) {
                    if (exposure_.exposed(node(patch, side)))
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
// Called for a self-pair and for a pair that may interact (mayInteractWithCluster), with its
// clusterKernel `k`.
void LinkRefiner::refineClusterPair(int receiver, int source, const ClusterKernel& k,
                                    std::vector<RefinePair>& next,
                                    std::vector<PendingLink>& pending) {
    if (receiver == source) {
        // Once coarse, the light a small cluster exchanges within itself is left out: linking
        // its parts pair by pair is what the time could not afford.
        if (coarse_ && transfer_.nodeRadius(receiver) < coarseRadius_)
            return;
        const std::vector<int> c = nodeChildren(receiver);
        for (const int r : c) {
            for (const int s : c)
                next.push_back({r, s});
        }
        return;
    }
    // An emitting cluster is never a source: the isotropic model would send the light of a lamp
    // facing down to the ceiling as much as to the floor. Emitters shine through their elements,
    // with their orientation (to clusters of receivers, though).
    const bool emittingSource = isCluster(source) && (*clusters_)[cluster(source)].emits;
    // The same oracle as refineLinks() applies, or a link it takes out for its receiver's sake
    // would come back unchanged every round.
    if (k.linkable && !emittingSource) {
        if (!exceedsThreshold(receiver, source, linkErrors(source, k.error, k.error))) {
            pending.push_back({receiver, source, {}});
            return;
        }
    }
    // A cluster can always be split; an element only while it is larger than the cluster.
    const float rr = transfer_.nodeRadius(receiver), rs = transfer_.nodeRadius(source);
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

// HSA91 "RefineLinks": every link whose error (linkErrors) now exceeds the threshold, with the
// radiance of the last solve, is replaced by the links Refine() makes for the pair. Returns
// whether any link was refined.
bool LinkRefiner::refineLinks(const std::string& step) {
    updateThresholds(true);
    std::vector<std::pair<int, Link>> candidates;
    const auto collect = [&](int receiver) {
        std::erase_if(links_.linksOf(receiver), [&](const Link& link) {
            const LinkErrors errors = linkErrors(link.source, link.spread, link.Fmax);
            const bool refinable = exceedsThreshold(receiver, link.source, errors) &&
                                   (canSplitNode(receiver) || canSplitNode(link.source));
            if (refinable)
                candidates.emplace_back(receiver, link);
            return refinable;
        });
    };
    for (size_t n = 0; n < links_.elementSides(); ++n)
        collect(static_cast<int>(n));
    for (size_t c = 0; c < links_.clusters(); ++c)
        collect(clusterNode(static_cast<int>(c)));
    std::vector<RefinePair> pairs;
    for (const auto& [receiver, link] : candidates)
        pairs.push_back({receiver, link.source, link.spread});
    refineAndLink(std::move(pairs), step);
    refinedLinks_ += candidates.size();
    return !candidates.empty();
}

// The punctual lights under the same oracle as links: a leaf whose direct term spreads over it by
// more than the threshold (a light pool's falloff, a shadow boundary) is split, down to the
// minimum area, and its children sample their own. Returns whether any element was split.
bool LinkRefiner::refineDirect() {
    updateThresholds(false);
    std::vector<int> queue;
    for (size_t e = 0; e < mesh_.elementCount(); ++e) {
        if (mesh_.isLeaf(static_cast<int>(e)))
            queue.push_back(static_cast<int>(e));
    }
    bool split = false;
    while (!queue.empty() && !timeIsUp()) {
        for (const int e : queue) {
            const float spread =
                glm::max(irradiance_.spread(node(e, true)), irradiance_.spread(node(e, false)));
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
bool LinkRefiner::subdivideByContrast(const std::string& step) {
    const std::vector<int> leaves = mesh_.leafElements();
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
            maxComponent(glm::max(radiance_.L(n) - radiance_.emission(n), Color(0.0f))));
    };
    // Only exposed leaf sides show light to compare (ElementExposure).
    const auto exposed = [&](int e, bool side) { return exposure_.fraction(node(e, side)) > 0.0f; };
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
            for (const Link& link : links_.linksOf(node(e, side))) {
                for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
                    pairs.push_back({node(c, side), link.source});
            }
            links_.linksOf(node(e, side)).clear();
        }
    }
    refineAndLink(std::move(pairs), step);
    return !marked.empty();
}

}  // namespace penumbra
