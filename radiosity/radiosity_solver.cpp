// Hierarchical radiosity: HSA91's Refine / Link / GatherRad / PushPullRad, with an error-based
// refinement oracle, a linear push and links carrying form factor times visibility.
#include "radiosity/radiosity_solver.h"

#include "core/scene.h"
#include "core/stats.h"
#include "radiosity/cluster_tree.h"
#include "radiosity/direct_irradiance.h"
#include "radiosity/element_exposure.h"
#include "radiosity/element_sampling.h"
#include "radiosity/final_gather.h"
#include "radiosity/gather_iteration.h"
#include "radiosity/indirect_at_corners.h"
#include "radiosity/link_hierarchy.h"
#include "radiosity/link_refiner.h"
#include "radiosity/link_transfer.h"
#include "radiosity/radiance_hierarchy.h"
#include "radiosity/shown_direct.h"
#include "radiosity/solver_nodes.h"

#include <algorithm>
#include <chrono>
#include <numeric>
#include <optional>
#include <sstream>

namespace penumbra {

namespace {

// Passes of the final gather's defect correction (finalGather), at most, and the relative change
// of the correction below which they stop.
constexpr int kMaxFinalGatherPasses = 4;
constexpr double kFinalGatherChange = 1e-2;

// Threshold of the intermediate solves between refinement rounds: the oracle only needs the
// radiance to a few percent.
constexpr double kRoundConvergence = 2e-2;

// The initial linking's epsilon over the settings' under a deadline (solve): on the Cornell box
// links 4 times coarser then one refinement round give the corrected hybrid the same error per
// sample as linking at epsilon (relMSE 0.000468 against 0.000467 at 256 spp).
constexpr float kCoarseLinkingScale = 4.0f;

// Passes of adaptive subdivision (subdivision_threshold) after the refinement rounds.
constexpr int kSubdivisionPasses = 4;

// The most leaves the refinement for the direct light at the corners may leave: this many times
// the solve's, and at least kShownMinLeaves (a lone floor under a downlight needs ten thousand).
constexpr size_t kShownLeavesPerLeaf = 4;
constexpr size_t kShownMinLeaves = 65536;
// The most leaves the refinement at creases may leave: this many times the solve's, and at
// least kShownMinLeaves (the modern hall's creases need 6 times its 41 000 leaves, 8 times
// with contact lines).
constexpr size_t kCreaseLeavesPerLeaf = 16;
// A reflectance below which a channel's D is not recovered from its reflected light
// (elementDirect / rho): a tiny rho would blow its rounding up into a huge D.
constexpr float kMinReflectance = 1e-4f;

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
    const auto split = [this](int e, int first) { inheritSplit(e, first); };
    const auto settle = [this](const std::vector<int>& created) {
        rays_ += exposure_->compute(created);
        rays_ += irradiance_->compute(created);
    };
    refiner_ =
        std::make_unique<LinkRefiner>(mesh_, settings_, *exposure_, *irradiance_, clusters_.get(),
                                      *transfer_, *links_, *radiance_, split, settle);
    iteration_ = std::make_unique<GatherIteration>(scene_, mesh_, *links_, *radiance_,
                                                   settings_.maxIterations);
    finalGather_ = std::make_unique<FinalGather>(scene_, mesh_, *exposure_, *irradiance_,
                                                 *radiance_, finalGatherRays());
    resizeArrays();
}

void RadiositySolver::resizeArrays() {
    exposure_->resize();
    irradiance_->resize();
    links_->resize();
    radiance_->resize();
}

RadiositySolver::~RadiositySolver() = default;

void RadiositySolver::inheritSplit(int e, int first) {
    resizeArrays();
    for (int c = first; c < first + RadiosityMesh::kChildren; ++c) {
        for (const bool side : {true, false}) {
            radiance_->inherit(node(c, side), node(e, side));
            irradiance_->inherit(node(c, side), node(e, side));
        }
    }
}

Color RadiositySolver::elementRadiance(int e, bool side) const {
    return radiance_->L(node(e, side));
}

Color RadiositySolver::leafRadiance(int n, const Color& H) const {
    return radiance_->leafRadiance(n, H);
}

size_t RadiositySolver::linkCount() const {
    return links_->linkCount();
}

bool RadiositySolver::converged() const {
    return iteration_->converged();
}

const std::vector<RadiosityIteration>& RadiositySolver::iterations() const {
    return iteration_->iterations();
}

Color RadiositySolver::elementDirect(int e, bool side) const {
    return radiance_->elementDirect(e, side);
}

Color RadiositySolver::elementIndirect(int e, bool side) const {
    return radiance_->elementIndirect(e, side);
}

// The final gather's passes (final_gather.cpp): each gathers the indirect light with rays and
// corrects the solution, and the gather sweeps then converge with the correction, until it
// changes by less than kFinalGatherChange.
// Under a deadline, a pass is taken to last as long as the one before: the grey-white room's
// 132 689 leaves take 4 s a pass, and a time-limited solve that had linked in time ran four.
void RadiositySolver::finalGather(Deadline deadline) {
    const std::vector<int> leaves = mesh_.leafElements();
    radiance_->clearCorrection();
    for (int pass = 1; pass <= kMaxFinalGatherPasses; ++pass) {
        const auto passStart = std::chrono::steady_clock::now();
        const std::string stage = "final gather " + std::to_string(pass);
        beginStage(stage + ": rays", mesh_.leafCount());
        const uint64_t raysBefore = finalGather_->rays();
        const double relativeChange = finalGather_->pass(leaves, pass == 1, progress_);
        std::ostringstream summary;
        summary.precision(3);
        summary << finalGather_->rays() - raysBefore << " rays, change " << relativeChange;
        endStage(summary.str());
        finalGatherPasses_ = pass;
        iteration_->run(settings_.convergence, rounds_, stage + ": gather", progress_);
        computeVertexValues();
        if (relativeChange < kFinalGatherChange)
            break;
        if (nextStepWouldOverrun(std::chrono::steady_clock::now() - passStart, deadline))
            break;
    }
}

int RadiositySolver::finalGatherRays() const {
    if (settings_.finalGatherRays != RadiositySettings::kAutoFinalGather)
        return settings_.finalGatherRays;
    return clusters_ ? RadiositySettings::kClusterFinalGatherRays : 0;
}

void RadiositySolver::refineAtCreases(const std::function<bool()>& stop) {
    const auto start = std::chrono::steady_clock::now();
    firstCreaseLeaf_ = static_cast<int>(mesh_.elementCount());
    std::vector<int> created;  // the children of a round's splits
    const CreaseRefinement::Solver solver{
        .shown =
            [this](int e, bool side) {
                return (side || mesh_.twoSided(e)) && exposure_->fraction(node(e, side)) > 0.0f;
            },
        .split =
            [this, &created](int leaf, float minChildArea) {
                const int first = mesh_.split(leaf, minChildArea);
                inheritSplit(leaf, first);
                if (shown_)
                    shown_->inheritSplit(leaf, first);
                for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
                    created.push_back(c);
                return first;
            },
        // The children's exposure and caustic deposits only: their direct light is the
        // corners' they inherit (or, without them, their parent's mean), as the solve left it.
        .settle =
            [this, &created] {
                rays_ += exposure_->compute(created);
                irradiance_->updateDeposits();
                created.clear();
            },
        .stop = stop};
    const size_t maxLeaves = std::max(kCreaseLeavesPerLeaf * mesh_.leafCount(), kShownMinLeaves);
    creases_ = CreaseRefinement::run(scene_, mesh_, solver, maxLeaves, progress_);
    if (creases_.leavesSplit > 0)
        computeVertexValues();
    secondsCreases_ = secondsSince(start);
}

void RadiositySolver::showDirectAtCorners(const std::function<bool()>& stop) {
    const auto start = std::chrono::steady_clock::now();
    auto shown = std::make_unique<ShownDirect>(scene_, mesh_, [this](int e, bool side) {
        return exposure_->fraction(node(e, side)) > 0.0f;
    });
    const size_t maxLeaves = std::max(kShownLeavesPerLeaf * mesh_.leafCount(), kShownMinLeaves);
    // An element side's mean D over its exposed part, from its first reflection of the sources.
    const auto exposedMean = [this](int e, bool side) {
        const Color rho = mesh_.rho(e);
        const Color direct = radiance_->elementDirect(e, side);
        Color D(0.0f);
        for (int c = 0; c < 3; ++c)
            D[c] = rho[c] > kMinReflectance ? direct[c] / rho[c] : 0.0f;
        return glm::max(D - irradiance_->depositedSources(node(e, side)), Color(0.0f));
    };
    const ShownDirect::Solver solver{
        .split = [this](int leaf,
                        float minChildArea) { return refiner_->splitLeaf(leaf, minChildArea); },
        .settle = [this] { refiner_->settleSplits(); },
        .punctualMean = [this](int e, bool side) { return irradiance_->punctual(node(e, side)); },
        .exposedMean = exposedMean,
        .shownMeans = [this, exposedMean] { return exposure_->shownValues(exposedMean); },
        .covered =
            [this](int e, const ElementSample& x, bool side, uint64_t& rays) {
                return exposure_->covered(e, x, side ? x.n : -x.n, rays);
            },
        .stop = stop};
    // The new leaves keep their parent's radiance and its split into the direct part and the
    // rest (RadianceHierarchy::inherit): the solve did not resolve them.
    shown->refine(solver, maxLeaves, progress_);
    shown_ = std::move(shown);
    secondsShownDirect_ = secondsSince(start);
}

void RadiositySolver::showIndirectAtCorners(SolveProgress* progress, Deadline deadline) {
    if (settings_.indirectAtCorners <= 0)
        return;
    const auto start = std::chrono::steady_clock::now();
    progress_ = progress;
    indirectCorners_ = std::make_unique<IndirectAtCorners>(
        scene_, mesh_, settings_.indirectAtCorners, firstCreaseLeaf_);
    const IndirectAtCorners::Solution solution{
        .exposed = [this](int e, bool side) { return exposure_->fraction(node(e, side)) > 0.0f; },
        .covered =
            [this](int e, const ElementSample& x, bool side, uint64_t& rays) {
                return exposure_->covered(e, x, side ? x.n : -x.n, rays);
            },
        .seenAt = [gathered =
                       GatheredRadiance(scene_, mesh_, *exposure_, *irradiance_, *radiance_)](
                      const MeshedHit& y, Sampler& sampler,
                      uint64_t& rays) { return gathered.seen(y, sampler, rays); },
        .unseen =
            [this](int e, bool side) {
                return mesh_.rho(e) * irradiance_->transferredD(node(e, side));
            },
        .fallback =
            exposure_->shownValues([this](int e, bool side) { return elementIndirect(e, side); })};
    beginStage("indirect light at the corners", mesh_.leafCount());
    if (indirectCorners_->gather(solution, progress_, deadline)) {
        endStage(std::to_string(indirectCorners_->rays()) + " rays, " +
                 std::to_string(indirectCorners_->raysPerCorner()) + " per corner");
    } else {
        endStage("skipped: too little time before the time limit");
        indirectCorners_.reset();
    }
    computeVertexValues();
    progress_ = nullptr;
    const double seconds = secondsSince(start);
    secondsIndirectAtCorners_ += seconds;
    secondsTotal_ += seconds;
}

Color RadiositySolver::shownIndirect(const ElementPoint& point, bool front) const {
    return indirectCorners_ ? indirectCorners_->at(point, front)
                            : vertexIndirect_.interpolate(mesh_, point, front);
}

void RadiositySolver::computeVertexValues() {
    // A leaf side wholly covered (a piece of floor under a block) shows a stand-in value: it
    // counts at its corners only where nothing visible does.
    const SideVertexValues::Weights visibleArea = [this](int e, bool side) {
        return exposure_->fraction(node(e, side)) > 0.0f ? mesh_.area(e) : 0.0f;
    };
    // The whole reflected radiance last, so that the mesh is left with the front's reflected
    // radiance.
    vertexIndirect_.compute(mesh_, exposure_->shownValues([this](int e, bool side) {
        return elementIndirect(e, side);
    }),
                            nullptr, visibleArea);
    if (!shown_ && !indirectCorners_) {
        vertexReflected_.compute(mesh_, exposure_->shownValues([this](int element, bool side) {
            return reflectedRadiance(element, side);
        }),
                                 nullptr, visibleArea);
        return;
    }
    // The part of the reflected light that neither the corners of shown_ nor those of
    // indirectCorners_ hold: the first reflection of the deposited flux with shown_, the whole
    // first reflection of the sources without.
    const auto rest = exposure_->shownValues([this](int element, bool side) {
        const Color first =
            shown_ ? mesh_.rho(element) * irradiance_->depositedSources(node(element, side))
                   : elementDirect(element, side);
        return indirectCorners_ ? first : first + elementIndirect(element, side);
    });
    vertexRest_.compute(mesh_, rest, nullptr, visibleArea);
    // What the mesh's own vertex values (the bake's) hold: the rest plus the corners' light,
    // averaged over the leaves at each vertex.
    vertexReflected_.compute(
        mesh_, rest,
        [this](int element, bool side) {
            std::array<Color, 3> corners{};
            if (shown_) {
                corners = shown_->cornerD(element, side);
                for (Color& D : corners)
                    D *= mesh_.rho(element);
            }
            if (indirectCorners_) {
                const std::array<Color, 3> indirect = indirectCorners_->corners(element, side);
                for (size_t k = 0; k < 3; ++k)
                    corners[k] += indirect[k];
            }
            return corners;
        },
        visibleArea);
}

void RadiositySolver::beginStage(const std::string& name, uint64_t total) {
    if (progress_)
        progress_->beginStage(name, total);
}

void RadiositySolver::endStage(const std::string& summary) {
    if (progress_)
        progress_->endStage(summary);
}

// --- The whole solution ------------------------------------------------------------------------

// HSA91's "HierarchicalRadiosity" with brightness-weighted refinement: link the patches with the
// oracle on the initial radiance (emission and punctual direct light), then alternate solving and
// refining the links with the current radiance until nothing is refined.
void RadiositySolver::solve(SolveProgress* progress, Deadline deadline,
                            LinkRefiner::OnTimeUp onTimeUp, Deadline abandonAt) {
    progress_ = progress;
    refiner_->setProgress(progress);
    if (onTimeUp == LinkRefiner::OnTimeUp::Abandon)
        abandonAt = deadline;
    refiner_->setTimeLimit(deadline, onTimeUp, abandonAt);
    const auto timeUp = [&] { return deadlinePassed(deadline); };
    const auto start = std::chrono::steady_clock::now();
    const auto linksAndLeaves = [&] {
        return std::to_string(linkCount()) + " links, " + std::to_string(mesh_.leafCount()) +
               " leaves";
    };
    // The seconds from the start to a deadline (0 without one).
    const auto secondsTo = [&](Deadline d) {
        return d ? std::chrono::duration<double>(*d - start).count() : 0.0;
    };
    const auto abandon = [&](bool staged) {
        abandoned_ = stoppedRefining_ = true;
        if (staged)
            endStage("abandoned: its time is up");
        secondsDirect_ = secondsTotal_ = secondsSince(start);
        refiner_->setProgress(nullptr);
        progress_ = nullptr;
    };

    // Stage 1: the punctual lights' direct light; the initial radiance is Le + rho D. First the
    // elements' exposed fractions, abandoned once projected to take more than a third of the time
    // to abandonAt: the two stages after it each took longer than it on the grey-white room (at
    // 4 s: exposure 2.4 s, the direct light with one point per leaf 2.9 s, the coarse links
    // 2.8 s), so the solve could not end by then.
    const std::vector<int> leaves = mesh_.leafElements();
    std::vector<int> elements(mesh_.elementCount());
    std::iota(elements.begin(), elements.end(), 0);
    const std::function<bool(size_t)> exposureOverruns = [&](size_t done) {
        const double elapsed = secondsSince(start);
        return projectedToOverrun(elapsed, done, elements.size(),
                                  secondsTo(abandonAt) / 3.0 - elapsed);
    };
    beginStage("exposed parts of the elements", elements.size());
    bool stopped = false;
    rays_ +=
        exposure_->compute(elements, progress_, abandonAt ? exposureOverruns : nullptr, &stopped);
    if (stopped) {
        abandon(true);
        return;
    }
    endStage(std::to_string(elements.size()) + " elements");
    const bool punctual = !punctualLights(scene_).empty() || scene_.environment();
    if (punctual)
        beginStage("direct light of the punctual lights", leaves.size());
    // As soon as this stage alone is projected to take half of the time to the deadline (the
    // links take longer still), a solve that is abandoned then is (OnTimeUp::Abandon; the
    // grey-white room lit by its sky: 7 s of direct light, then the linking abandoned; the path
    // tracer lost 9 s of its 16), and any other samples the rest of the leaves with one point
    // each (there: 21 s of direct light for a solve given 8 s); at that pace it is abandoned once
    // projected to take half of the time to abandonAt.
    using Pace = DirectIrradiance::Pace;
    std::optional<size_t> hurriedFrom;  // the leaves done when it began to hurry
    auto paceStart = std::chrono::steady_clock::now();
    size_t paceFrom = 0;  // the leaves done when the current pace began
    const auto overruns = [&](size_t done, double secondsToEnd) {
        return projectedToOverrun(secondsSince(paceStart), done - paceFrom,
                                  leaves.size() - paceFrom, secondsToEnd - secondsSince(start));
    };
    const std::function<Pace(size_t)> pace = [&](size_t done) {
        if (!hurriedFrom && overruns(done, 0.5 * secondsTo(deadline))) {
            if (onTimeUp == LinkRefiner::OnTimeUp::Abandon)
                return Pace::Stop;
            hurriedFrom = paceFrom = done;
            paceStart = std::chrono::steady_clock::now();
        }
        if (hurriedFrom && abandonAt && overruns(done, 0.5 * secondsTo(abandonAt)))
            return Pace::Stop;
        return hurriedFrom ? Pace::Hurry : Pace::Full;
    };
    rays_ += irradiance_->compute(leaves, progress_,
                                  deadline ? pace : std::function<Pace(size_t)>{}, &stopped);
    if (stopped) {
        abandon(punctual);
        return;
    }
    radiance_->pushPullAll();
    refiner_->refineDirect();
    radiance_->pushPullAll();
    if (punctual)
        endStage(std::to_string(mesh_.leafCount()) + " leaves" +
                 (hurriedFrom ? ", one point each from leaf " + std::to_string(*hurriedFrom) +
                                    " on (time limit)"
                              : ""));
    secondsDirect_ = secondsSince(start);
    peakDirect_ = peakMemoryMiB();

    // Stage 2: initial links between the patches (the oracle, then the links' form factors).
    auto stageStart = std::chrono::steady_clock::now();
    beginStage("linking: refinement oracle", 0);
    // With a deadline the links start coarse and the refinement rounds refine them as time
    // allows, so that the solve has a whole solution early instead of a fine one late.
    refiner_->linkPatches("linking", deadline ? kCoarseLinkingScale : 1.0f);
    abandoned_ = refiner_->abandoned();
    // An abandoned solve's refinement was stopped by the time limit too, also when its oracle
    // gave up before the deadline (LinkRefiner::oracleTooLong).
    stoppedRefining_ = timeUp() || abandoned_;
    endStage(abandoned_ ? "abandoned: its time is up" : linksAndLeaves());
    // The time of the last linking or refinement step, which the next one is taken to last.
    auto lastStep = std::chrono::steady_clock::now() - stageStart;
    secondsLinking_ = std::chrono::duration<double>(lastStep).count();
    peakLinking_ = peakMemoryMiB();
    if (abandoned_) {
        secondsTotal_ = secondsSince(start);
        refiner_->setProgress(nullptr);
        progress_ = nullptr;
        return;
    }

    // Stage 3: gather sweeps and refinement rounds.
    const double roundThreshold = std::max(settings_.convergence, kRoundConvergence);
    stageStart = std::chrono::steady_clock::now();
    iteration_->run(roundThreshold, 0, "gather", progress_);
    secondsSolve_ += secondsSince(stageStart);
    // One refinement step, then, if it changed anything, the solve of the new round.
    int round = 0;
    const auto step = [&](const std::string& name, const auto& refineStep) {
        stageStart = std::chrono::steady_clock::now();
        const std::string stepName = name + " " + std::to_string(round + 1);
        beginStage(stepName + ": refinement oracle", 0);
        const bool refined = refineStep(stepName);
        endStage(refined ? linksAndLeaves() : "nothing to refine");
        lastStep = std::chrono::steady_clock::now() - stageStart;
        secondsRefine_ += std::chrono::duration<double>(lastStep).count();
        peakRefine_ = peakMemoryMiB();
        if (!refined)
            return false;
        rounds_ = ++round;
        stageStart = std::chrono::steady_clock::now();
        iteration_->run(roundThreshold, round, "gather, round " + std::to_string(round), progress_);
        secondsSolve_ += secondsSince(stageStart);
        return true;
    };
    const auto refineRound = [&](const std::string& stepName) {
        const bool links = refiner_->refineLinks(stepName);
        return refiner_->refineDirect() || links;
    };
    // Whether the caller's time is up, or would be before another step as long as the last
    // (the linking or the last round) ended: the solve then ends with what it has.
    const auto stop = [&] {
        stoppedRefining_ = stoppedRefining_ || nextStepWouldOverrun(lastStep, deadline);
        return stoppedRefining_;
    };
    while (round < settings_.maxRefinements && !stop() && step("refinement round", refineRound)) {
    }
    // Adaptive subdivision by contrast with the neighbours (subdivision_threshold).
    const auto subdivide = [&](const std::string& stepName) {
        return refiner_->subdivideByContrast(stepName);
    };
    for (int pass = 0; pass < kSubdivisionPasses && settings_.subdivisionThreshold > 0.0f; ++pass) {
        if (stop() || !step("subdivision round", subdivide))
            break;
    }
    stageStart = std::chrono::steady_clock::now();
    iteration_->run(settings_.convergence, round, "gather to convergence", progress_);
    beginStage("push-pull of the direct part, vertex values", 0);
    radiance_->computeDirectPart(*irradiance_);
    computeVertexValues();
    endStage(std::to_string(mesh_.vertexCount()) + " vertices");
    secondsSolve_ += secondsSince(stageStart);
    if (finalGatherRays() > 0 && !stop()) {
        stageStart = std::chrono::steady_clock::now();
        finalGather(deadline);
        secondsFinalGather_ = secondsSince(stageStart);
    }
    if (settings_.directAtCorners && !timeUp()) {
        showDirectAtCorners(timeUp);
        computeVertexValues();
    }
    // After the direct light's refinement, whose corners the new leaves inherit: it refines
    // where the direct light needs it, and evaluating the sources (a sky's directions, an
    // emitter's contour) at every corner along every crease would double the daylit room's view.
    if (settings_.indirectAtCorners > 0 && !timeUp())
        refineAtCreases(timeUp);
    secondsTotal_ = secondsSince(start);
    peakSolve_ = peakMemoryMiB();
    refiner_->setProgress(nullptr);
    progress_ = nullptr;
}

void RadiositySolver::transferThroughSpecular(const std::vector<FluxDeposit>& deposits,
                                              SolveProgress* progress) {
    const auto start = std::chrono::steady_clock::now();
    progress_ = progress;
    ++transferRounds_;
    const std::string stage = "specular transfer " + std::to_string(transferRounds_);
    irradiance_->setTransferred(deposits);
    iteration_->run(settings_.convergence, rounds_, stage + ": gather", progress_);
    beginStage(stage + ": push-pull of the direct part, vertex values", 0);
    radiance_->computeDirectPart(*irradiance_);
    // The corners' gather saw the solution before this transfer.
    indirectCorners_.reset();
    computeVertexValues();
    endStage(std::to_string(irradiance_->transferred()->count()) + " deposits");
    progress_ = nullptr;
    const double seconds = secondsSince(start);
    secondsTransfer_ += seconds;
    secondsTotal_ += seconds;
}

Color RadiositySolver::reflectedRadiance(int element, bool front) const {
    const int n = node(element, front);
    return glm::max(radiance_->L(n) - radiance_->emission(n), Color(0.0f));
}

float RadiositySolver::exposedFraction(int element, bool front) const {
    return exposure_->fraction(node(element, front));
}

Color RadiositySolver::radiance(uint32_t mesh, uint32_t triangle, Vec3 b, bool includeEmission,
                                bool front) const {
    return shownRadiance(mesh_.locate(mesh, triangle, b), includeEmission, front);
}

Color RadiositySolver::cornerRadiance(int leaf, size_t corner, bool includeEmission,
                                      bool front) const {
    Vec3 weights(0.0f);
    weights[int(corner)] = 1.0f;
    return shownRadiance(ElementPoint{leaf, weights}, includeEmission, front);
}

Color RadiositySolver::shownRadiance(const ElementPoint& point, bool includeEmission,
                                     bool front) const {
    if (point.element < 0 || vertexReflected_.empty())
        return Color(0.0f);
    Color L = vertexReflected_.interpolate(mesh_, point, front);
    if (shown_ || indirectCorners_) {
        L = vertexRest_.interpolate(mesh_, point, front);
        if (shown_)
            L += mesh_.rho(point.element) * shown_->D(point, front);
        if (indirectCorners_)
            L += shownIndirect(point, front);
    }
    if (!includeEmission)
        return L;
    // A side hidden under a coincident face shows that face's light (shownValues), its emission
    // too.
    const auto [e, side] = exposure_->shownSide(point.element, front);
    return L + radiance_->emission(node(e, side));
}

Color RadiositySolver::indirectRadiance(uint32_t mesh, uint32_t triangle, Vec3 b,
                                        bool front) const {
    const ElementPoint point = mesh_.locate(mesh, triangle, b);
    if (point.element < 0)
        return Color(0.0f);
    return shownIndirect(point, front);
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
              vertexRest_.memoryBytes() + radiance_->directPartBytes() + exposure_->memoryBytes() +
              (shown_ ? shown_->memoryBytes() : 0) +
              (indirectCorners_ ? indirectCorners_->memoryBytes() : 0);
    const std::vector<RadiosityIteration>& iterations = iteration_->iterations();
    const RadiosityIteration last = iterations.empty() ? RadiosityIteration{} : iterations.back();
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
    const DepositedFlux* transferred = irradiance_->transferred();
    const uint64_t rays = rays_ + refiner_->rays() + finalGather_->rays() + creases_.rays;
    return {{"patches", std::to_string(mesh.patches)},
            {"elements", std::to_string(mesh.elements)},
            {"leaves", std::to_string(mesh.leaves)},
            {"cut_triangles", std::to_string(mesh.cutTriangles)},
            {"cut_pieces", std::to_string(mesh.pieces)},
            {"clusters", std::to_string(clusters_ ? clusters_->size() : 0)},
            {"sealed_solids", std::to_string(exposure_->sealed().count())},
            {"coincident_patches", std::to_string(exposure_->coincident().hiddenPatches())},
            {"coincident_area_m2", formatStat(exposure_->coincident().hiddenArea())},
            {"links", std::to_string(links)},
            {"refinement_rounds", std::to_string(rounds_)},
            {"refinement_stopped_by_time_limit", stoppedRefining_ ? "yes" : "no"},
            {"abandoned_by_time_limit", abandoned_ ? "yes" : "no"},
            {"refined_links", std::to_string(refiner_->refinedLinks())},
            {"iterations", std::to_string(iterations.size())},
            {"residual", formatStat(last.change)},
            {"error_bound", formatStat(last.errorBound)},
            {"converged", converged() ? "yes" : "no"},
            {"rays", std::to_string(rays)},
            {"deposited_photons", std::to_string(deposits ? deposits->count() : 0)},
            {"deposited_flux_lm", formatStat(depositedFlux)},
            {"specular_transfer_rounds", std::to_string(transferRounds_)},
            {"specular_transfer_deposits", std::to_string(transferred ? transferred->count() : 0)},
            {"specular_transfer_flux_lm",
             formatStat(transferred ? luminance(transferred->totalPower()) : 0.0f)},
            {"seconds_specular_transfer", formatStat(secondsTransfer_)},
            {"direct_flux_lm", formatStat(directFlux)},
            {"indirect_flux_lm", formatStat(indirectFlux)},
            {"memory_mib", formatStat(static_cast<double>(memory) / (1024.0 * 1024.0))},
            {"seconds_direct", formatStat(secondsDirect_)},
            {"seconds_linking", formatStat(secondsLinking_)},
            {"seconds_form_factors", formatStat(refiner_->secondsFormFactors())},
            {"seconds_refine", formatStat(secondsRefine_)},
            {"seconds_solve", formatStat(secondsSolve_)},
            {"final_gather_rays_per_side", std::to_string(finalGatherRays())},
            {"final_gather_passes", std::to_string(finalGatherPasses_)},
            {"final_gather_rays", std::to_string(finalGather_->rays())},
            {"seconds_final_gather", formatStat(secondsFinalGather_)},
            {"crease_splits", std::to_string(creases_.leavesSplit)},
            {"crease_budget_reached", creases_.budgetReached ? "yes" : "no"},
            {"crease_rays", std::to_string(creases_.rays)},
            {"seconds_creases", formatStat(secondsCreases_)},
            {"direct_at_corners_splits", std::to_string(shown_ ? shown_->leavesSplit() : 0)},
            {"direct_at_corners_budget_reached", shown_ && shown_->budgetReached() ? "yes" : "no"},
            {"direct_at_corners_stopped_by_time_limit", shown_ && shown_->stopped() ? "yes" : "no"},
            {"direct_at_corners_rays", std::to_string(shown_ ? shown_->rays() : 0)},
            {"seconds_direct_at_corners", formatStat(secondsShownDirect_)},
            {"indirect_at_corners_rays",
             std::to_string(indirectCorners_ ? indirectCorners_->rays() : 0)},
            {"indirect_at_corners_rays_per_corner",
             std::to_string(indirectCorners_ ? indirectCorners_->raysPerCorner() : 0)},
            {"seconds_indirect_at_corners", formatStat(secondsIndirectAtCorners_)},
            {"seconds", formatStat(secondsTotal_)},
            {"peak_memory_mib_direct", formatStat(peakDirect_)},
            {"peak_memory_mib_linking", formatStat(peakLinking_)},
            {"peak_memory_mib_refine", formatStat(peakRefine_)},
            {"peak_memory_mib_solve", formatStat(peakSolve_)}};
}

}  // namespace penumbra
