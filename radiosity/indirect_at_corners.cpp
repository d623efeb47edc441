#include "radiosity/indirect_at_corners.h"

#include "core/scene.h"
#include "core/stats.h"
#include "radiosity/crease_refinement.h"
#include "radiosity/element_sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <tuple>

namespace penumbra {

namespace {

// The corner gather's sampler seed, apart from the final gather's and the links' so that they
// never share a sequence.
constexpr uint32_t kCornerGatherSeed = 0x27d4eb2fu;

}  // namespace

IndirectAtCorners::IndirectAtCorners(const Scene& scene, const RadiosityMesh& mesh,
                                     int raysPerCorner, int firstCreaseLeaf)
    : scene_(scene),
      mesh_(mesh),
      raysPerCorner_(raysPerCorner),
      firstCreaseLeaf_(firstCreaseLeaf) {}

// The rays a leaf's corners gather with. A corner's value is shown over its leaves, so its
// gather's variance sigma^2 / n weighs in the squared error over the surface with their area,
// about s^2 for leaves of size s: the sum of s_i^2 sigma^2 / n_i over the corners, for a given
// number of rays, is least at n_i proportional to s_i (the optimal allocation of stratified
// sampling, Neyman 1934, "On the Two Different Aspects of the Representative Method", with the
// squared error's weight s^2). The solve's leaves keep raysPerCorner_; a leaf the refinement at
// creases made d levels below them (each level halves the size) gathers with raysPerCorner_ / 2^d,
// but with no fewer rays than its probe cast (CreaseRefinement::kProbeRays).
// On the modern hall, where the refinement at creases makes six times as many leaves as the
// solve's, the gather casts 41 M rays instead of 102 M (docs/radiosity.md).
int IndirectAtCorners::raysAt(int leaf) const {
    if (leaf < firstCreaseLeaf_)
        return raysPerCorner_;
    int solveLeaf = leaf;
    while (solveLeaf >= firstCreaseLeaf_)
        solveLeaf = mesh_.parent(solveLeaf);
    const int depth = std::min(mesh_.level(leaf) - mesh_.level(solveLeaf), 30);
    const int fewest = std::min(raysPerCorner_, static_cast<int>(CreaseRefinement::kProbeRays));
    return std::max(raysPerCorner_ >> depth, fewest);
}

bool IndirectAtCorners::gather(const Solution& solution, SolveProgress* progress,
                               Deadline deadline) {
    corners_.assign(mesh_.elementCount());
    reach_.assign(mesh_.elementCount(), {});
    means_.assign(mesh_.elementCount(), {});
    const std::vector<int> leaves = mesh_.leafElements();
    std::optional<std::vector<CornerStates>> probed = cornerStates(solution, leaves, deadline);
    if (!probed)
        return false;
    const std::vector<CornerStates>& states = *probed;
    std::vector<Corner> corners = exposedCorners(leaves, states);
    // Sorted by key, so that each run of equal keys is one gather, at its first corner (the
    // lowest leaf id: the same whatever the threads).
    std::sort(corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
        return std::tie(a.key, a.leaf) < std::tie(b.key, b.leaf);
    });
    std::vector<size_t> runs;
    for (size_t i = 0; i < corners.size(); ++i)
        if (i == 0 || corners[i].key != corners[i - 1].key)
            runs.push_back(i);
    runs.push_back(corners.size());
    const size_t gathers = runs.size() - 1;
    std::atomic<uint64_t> rays{0};
    const auto gatherRun = [&](size_t r) {
        // The run's largest leaf decides: the value is shown over it too.
        int n = 0;
        for (size_t i = runs[r]; i < runs[r + 1]; ++i)
            n = std::max(n, raysAt(corners[i].leaf));
        uint64_t count = 0;
        const Gathered g =
            meanReflected(solution, corners[runs[r]], static_cast<uint32_t>(n), count);
        for (size_t i = runs[r]; i < runs[r + 1]; ++i) {
            const Corner& corner = corners[i];
            corners_.at(corner.leaf, corner.front, corner.k) =
                mesh_.rho(corner.leaf) * g.L + solution.unseen(corner.leaf, corner.front);
            reach_[static_cast<size_t>(corner.leaf)][(corner.front ? 0 : 3) + corner.k] = g.reach;
        }
        rays += count;
    };
    if (deadline) {
        // Every kProbeStride-th gather first, with the rays asked, for the time a gather takes,
        // until they have taken a tenth of the time to the deadline; then every gather with as
        // many rays as end by the deadline, no more than asked (the probe's gathers again, so
        // that it changes no value).
        const size_t probes = (gathers + kProbeStride - 1) / kProbeStride;
        const auto probeStart = std::chrono::steady_clock::now();
        const double probeSeconds =
            kProbeShare * std::chrono::duration<double>(*deadline - probeStart).count();
        size_t probed = probes;
        parallelForWithProgress(
            probes, nullptr, [&](size_t p) { gatherRun(p * kProbeStride); },
            [&](size_t done) {
                if (secondsSince(probeStart) <= probeSeconds)
                    return false;
                probed = done;
                return true;
            });
        const auto now = std::chrono::steady_clock::now();
        const double perGather = std::chrono::duration<double>(now - probeStart).count() /
                                 static_cast<double>(std::max<size_t>(probed, 1));
        const double projected = perGather * static_cast<double>(gathers);
        const double secondsLeft = std::chrono::duration<double>(*deadline - now).count();
        if (projected > secondsLeft) {
            raysPerCorner_ =
                static_cast<int>(raysPerCorner_ * std::max(secondsLeft, 0.0) / projected);
            if (raysPerCorner_ < kFewestBudgetedRays) {
                rays_ += rays;
                return false;
            }
        }
    }
    parallelForWithProgress(gathers, progress, gatherRun);
    fillCovered(solution, leaves, states);
    corners_.anchorTVertices(mesh_, solution.exposed);
    for (const int e : leaves)
        for (const bool front : {true, false})
            means_[static_cast<size_t>(e)][front ? 0 : 1] = solution.fallback(e, front);
    rays_ += rays;
    return true;
}

std::optional<std::vector<IndirectAtCorners::CornerStates>> IndirectAtCorners::cornerStates(
    const Solution& solution, const std::vector<int>& leaves, Deadline deadline) {
    std::vector<CornerStates> states(leaves.size());
    std::atomic<uint64_t> rays{0};
    // Under a deadline, the probes for covers must leave the gathers at least half of the time.
    const auto start = std::chrono::steady_clock::now();
    const auto tooLong = [&](size_t done) {
        const double half = 0.5 * std::chrono::duration<double>(*deadline - start).count();
        const double elapsed = secondsSince(start);
        return projectedToOverrun(elapsed, done, leaves.size(), half - elapsed);
    };
    const bool complete = parallelForWithProgress(
        leaves.size(), nullptr,
        [&](size_t i) {
            const int e = leaves[i];
            if (!(maxComponent(mesh_.rho(e)) > 0.0f))
                return;
            const ElementSampler points(scene_, mesh_, e);
            uint64_t count = 0;
            for (const bool front : {true, false}) {
                if (!solution.exposed(e, front))
                    continue;
                for (size_t k = 0; k < 3; ++k) {
                    const ElementSample x = points.insetCorner(k);
                    states[i][(front ? 0 : 3) + k] = solution.covered(e, x, front, count)
                                                         ? CornerState::Covered
                                                         : CornerState::Exposed;
                }
            }
            rays += count;
        },
        deadline ? std::function<bool(size_t)>(tooLong) : nullptr);
    rays_ += rays;
    if (!complete)
        return std::nullopt;
    return states;
}

std::vector<IndirectAtCorners::Corner> IndirectAtCorners::exposedCorners(
    const std::vector<int>& leaves, const std::vector<CornerStates>& states) const {
    std::vector<Corner> corners;
    for (size_t i = 0; i < leaves.size(); ++i) {
        const int e = leaves[i];
        for (size_t c = 0; c < 6; ++c) {
            if (states[i][c] != CornerState::Exposed)
                continue;
            const bool front = c < 3;
            const size_t k = c % 3;
            corners.push_back({e, front, k, cornerKey(mesh_, e, front, k)});
        }
    }
    return corners;
}

IndirectAtCorners::Gathered IndirectAtCorners::meanReflected(const Solution& solution,
                                                             const Corner& corner, uint32_t n,
                                                             uint64_t& rays) const {
    const ElementSample x = ElementSampler(scene_, mesh_, corner.leaf).insetCorner(corner.k);
    Color sum(0.0f);
    const float reach = castCornerRays(
        scene_, mesh_, x, corner.front, kCornerGatherSeed, IVec2(corner.key[0], corner.key[1]), n,
        rays, [&](const MeshedHit& y, Sampler& sampler) {
            sum += y.transmittance * solution.seenAt(y, sampler, rays);
        });
    return {sum / static_cast<float>(n), reach};
}

Color IndirectAtCorners::at(const ElementPoint& point, bool front) const {
    if (point.element < 0 || static_cast<size_t>(point.element) >= reach_.size())
        return Color(0.0f);
    const std::array<Color, 3> c = corners_.corners(point.element, front);
    const std::array<Vec3, 3> x = mesh_.corners(point.element);
    const Vec3 p = point.weights.x * x[0] + point.weights.y * x[1] + point.weights.z * x[2];
    const auto e = static_cast<size_t>(point.element);
    const Color mean = means_[e][front ? 0 : 1];
    Color L = mean;
    for (size_t k = 0; k < 3; ++k) {
        const float reach = std::max(reach_[e][(front ? 0 : 3) + k], kCreaseSize);
        const float d = glm::length(p - x[k]);
        const float w = d > reach ? reach / d : 1.0f;
        L += point.weights[static_cast<int>(k)] * w * (c[k] - mean);
    }
    return L;
}

void IndirectAtCorners::fillCovered(const Solution& solution, const std::vector<int>& leaves,
                                    const std::vector<CornerStates>& states) {
    tbb::parallel_for(size_t(0), leaves.size(), [&](size_t i) {
        const int e = leaves[i];
        for (const bool front : {true, false}) {
            const size_t o = front ? 0 : 3;
            std::array<float, 6>& reach = reach_[static_cast<size_t>(e)];
            Color sum(0.0f);
            float farthest = 0.0f;
            int exposed = 0;
            for (size_t k = 0; k < 3; ++k) {
                if (states[i][o + k] == CornerState::Exposed) {
                    sum += corners_.at(e, front, k);
                    farthest = std::max(farthest, reach[o + k]);
                    ++exposed;
                }
            }
            if (exposed == 3)
                continue;
            const Color shared =
                exposed > 0 ? sum / static_cast<float>(exposed) : solution.fallback(e, front);
            for (size_t k = 0; k < 3; ++k) {
                if (states[i][o + k] != CornerState::Exposed) {
                    corners_.at(e, front, k) = shared;
                    reach[o + k] = farthest;
                }
            }
        }
    });
}

}  // namespace penumbra
