#include "radiosity/crease_refinement.h"

#include "core/scene.h"
#include "radiosity/corner_rays.h"
#include "radiosity/element_sampling.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace penumbra {

namespace {

// The probes' sampler seed, apart from the corner gather's, the final gather's and the links'.
constexpr uint32_t kProbeSeed = 0x5bd1e995u;

// The children of a split are at least this large: leaves of kCreaseSize.
constexpr float kMinChildArea = 0.5f * kCreaseSize * kCreaseSize;

struct Probe {
    CornerKey key;
    int leaf = 0;
    bool front = true;
    size_t k = 0;
};

}  // namespace

CreaseRefinement CreaseRefinement::run(const Scene& scene, const RadiosityMesh& mesh,
                                       const Solver& solver, size_t maxLeaves,
                                       SolveProgress* progress) {
    CreaseRefinement result;
    std::map<CornerKey, float> reach;  // of every corner probed so far (one probe per key)
    // Whether a leaf is probed at all: it reflects, and may be split.
    const auto probed = [&](int e) {
        return maxComponent(mesh.rho(e)) > 0.0f && mesh.canSplit(e, kMinChildArea);
    };
    std::vector<int> candidates = mesh.leafElements();
    for (int round = 1; !candidates.empty() && !(solver.stop && solver.stop()); ++round) {
        std::vector<Probe> probes;
        for (const int e : candidates) {
            if (!probed(e))
                continue;
            for (const bool front : {true, false}) {
                if (!solver.shown(e, front))
                    continue;
                for (size_t k = 0; k < 3; ++k) {
                    const CornerKey key = cornerKey(mesh, e, front, k);
                    if (!reach.contains(key))
                        probes.push_back({key, e, front, k});
                }
            }
        }
        // One probe per corner, from its lowest leaf: the same whatever the threads.
        std::sort(probes.begin(), probes.end(), [](const Probe& a, const Probe& b) {
            return std::tie(a.key, a.leaf) < std::tie(b.key, b.leaf);
        });
        probes.erase(std::unique(probes.begin(), probes.end(),
                                 [](const Probe& a, const Probe& b) { return a.key == b.key; }),
                     probes.end());
        const std::string stage = "refinement at creases, round " + std::to_string(round);
        if (progress)
            progress->beginStage(stage, probes.size());
        std::vector<float> found(probes.size());
        std::atomic<uint64_t> rays{0};
        parallelForWithProgress(probes.size(), progress, [&](size_t i) {
            const Probe& p = probes[i];
            const ElementSample x = ElementSampler(scene, mesh, p.leaf).insetCorner(p.k);
            uint64_t count = 0;
            found[i] =
                castCornerRays(scene, mesh, x, p.front, kProbeSeed, IVec2(p.key[0], p.key[1]),
                               kProbeRays, count, [](const MeshedHit&, Sampler&) {});
            rays += count;
        });
        result.rays += rays;
        for (size_t i = 0; i < probes.size(); ++i)
            reach.emplace(probes[i].key, found[i]);

        // The candidates split this round, with the smallest part of their size a corner reaches.
        std::vector<std::pair<float, int>> split;
        for (const int e : candidates) {
            if (!probed(e))
                continue;
            float least = std::numeric_limits<float>::infinity();
            for (const bool front : {true, false})
                if (solver.shown(e, front))
                    for (size_t k = 0; k < 3; ++k)
                        least = std::min(least, reach.at(cornerKey(mesh, e, front, k)));
            const float perSize = least / std::sqrt(2.0f * mesh.area(e));
            if (perSize < kReachPerSize)
                split.emplace_back(perSize, e);
        }
        // A split adds three leaves.
        const size_t room = maxLeaves > mesh.leafCount() ? (maxLeaves - mesh.leafCount()) / 3 : 0;
        if (split.size() > room) {
            std::sort(split.begin(), split.end());
            split.resize(room);
            result.budgetReached = true;
        }
        candidates.clear();
        for (const auto& [perSize, e] : split) {
            const int first = solver.split(e, kMinChildArea);
            for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
                candidates.push_back(c);
        }
        if (!split.empty())
            solver.settle();
        result.leavesSplit += split.size();
        if (progress)
            progress->endStage(std::to_string(split.size()) + " leaves split");
        if (result.budgetReached)
            break;
    }
    return result;
}

}  // namespace penumbra
