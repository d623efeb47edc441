// Which parts of the element sides are exposed: sampled once per element, by level, with the
// points of the direct light.
#include "radiosity/element_exposure.h"

#include "radiosity/solve_progress.h"
#include "radiosity/solver_nodes.h"

#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <optional>
#include <tuple>

namespace penumbra {

namespace {

// Points per element whose exposed fraction is sampled (compute): at least this many, and
// at least one per smallest element's area, at most kMaxExposureSamples.
constexpr int kExposureSamples = 16;
constexpr int kMaxExposureSamples = 4096;

// Points a partly covered element keeps at least (compute), from which its links draw
// their shadow rays' ends (visibility), 16 per link by default. Every link of a receiver draws
// from the same points, so their quadrature error does not average out over its links as fresh
// points' did: against the dense solve of HierarchicalRadiosity.AgreesWithFullMatrixSolve
// (tests/radiosity/hierarchical_radiosity_test.cpp), whose ceiling leaves beside its lamp are a
// strip's worth exposed, the worst lit patch side differed by 1.00 % with 64, 1.02 % with 128 and
// 0.85 % with 256 (0.73 % with fresh points), the worst leaf side by 0.12, 0.10 and 0.087 of the
// mean (0.074). At most kMaxExposureSamples rounded up to a power of two.
constexpr int kCoverSamples = 256;
static_assert(std::bit_ceil(static_cast<uint32_t>(kMaxExposureSamples)) <=
              CoverSamples::kMaxPoints);

// A gap narrower than this fraction of the smallest element's edge (the square root of its area)
// covers the surface behind it (isCovered, element_sampling.h).
constexpr float kCoveringGap = 0.1f;

}  // namespace

ElementExposure::ElementExposure(const Scene& scene, const RadiosityMesh& mesh)
    : scene_(scene), mesh_(mesh), sealed_(scene), coincident_(mesh) {}

void ElementExposure::resize() {
    fractions_.resize(2 * mesh_.elementCount(), 1.0f);
}

// The exposed fractions (0 for a side facing a sealed interior, sealed_interiors.h). Every
// element is sampled (coverSamples, with the points of the direct light, computeDirect, so that
// the covered points are the same), also one whose parent's points found its side wholly exposed
// or wholly covered: at one point per smallest element, they miss a third of a smallest element
// under a block's edge one time in four, and a floor leaf a third under the block took the shadow
// rays from its covered points for occlusion (8 % dark in the furnace box). An element with a
// partly covered side keeps its points (coverSamples_), at least kCoverSamples of them. Then every
// parent's fraction becomes its children's mean, so that the children's exposed areas add up to
// their parent's and the push and pull keep the energy; a parent that becomes partly covered so
// gets points too.
uint64_t ElementExposure::compute(const std::vector<int>& elements, SolveProgress* progress,
                                  const std::function<bool(size_t done)>& stop, bool* stopped) {
    tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
    const auto samplesOf = [&](int e) {
        return static_cast<int>(std::clamp(std::ceil(mesh_.area(e) / mesh_.minElementArea(e)),
                                           static_cast<float>(kExposureSamples),
                                           static_cast<float>(kMaxExposureSamples)));
    };
    // A power of two, so that its aligned runs of 2^k points are stratified (visibility).
    const auto keptSamples = [&](int e, uint64_t& count) {
        const auto n = std::bit_ceil(static_cast<uint32_t>(std::max(samplesOf(e), kCoverSamples)));
        return coverSamples(scene_, mesh_, e, static_cast<int>(n), coveringGap(e), kPointSeed,
                            coincident_, count);
    };
    std::vector<std::optional<CoverSamples>> kept(elements.size());
    const bool completed = parallelForWithProgress(
        elements.size(), progress,
        [&](size_t i) {
            const int e = elements[i];
            CoverSamples c = coverSamples(scene_, mesh_, e, samplesOf(e), coveringGap(e),
                                          kPointSeed, coincident_, rays.local());
            const bool partly = c.partlyCovered();
            if (partly && c.points.size() < static_cast<size_t>(kCoverSamples))
                c = keptSamples(e, rays.local());
            for (const bool side : {true, false}) {
                const bool sealed = sealed_.faces(mesh_.sceneMesh(e), mesh_.sceneTriangle(e), side);
                fractions_[node(e, side)] = sealed ? 0.0f : c.exposedFraction(side);
            }
            if (partly)
                kept[i] = std::move(c);
        },
        stop);
    if (!completed) {
        if (stopped)
            *stopped = true;
        return rays.combine(std::plus<uint64_t>());
    }
    for (size_t i = 0; i < elements.size(); ++i) {
        if (kept[i])
            coverSamples_.insert_or_assign(elements[i], std::move(*kept[i]));
    }
    // Children have larger ids than their parents.
    std::vector<int> newlyPartly;
    for (size_t e = mesh_.elementCount(); e-- > 0;) {
        const int first = mesh_.firstChild(static_cast<int>(e));
        if (first < 0)
            continue;
        for (const bool side : {true, false}) {
            float sum = 0.0f;
            for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
                sum += fractions_[node(c, side)];
            fractions_[node(static_cast<int>(e), side)] = sum / RadiosityMesh::kChildren;
        }
        const int n = static_cast<int>(e);
        if ((partlyCovered(node(n, true)) || partlyCovered(node(n, false))) &&
            !coverSamples_.contains(n))
            newlyPartly.push_back(n);
    }
    kept.assign(newlyPartly.size(), std::nullopt);
    tbb::parallel_for(size_t(0), newlyPartly.size(),
                      [&](size_t i) { kept[i] = keptSamples(newlyPartly[i], rays.local()); });
    for (size_t i = 0; i < newlyPartly.size(); ++i)
        coverSamples_.insert_or_assign(newlyPartly[i], std::move(*kept[i]));
    return rays.combine(std::plus<uint64_t>());
}

bool ElementExposure::exposed(int n) const {
    return isCluster(n) || fractions_[static_cast<size_t>(n)] > 0.0f;
}

bool ElementExposure::partlyCovered(int n) const {
    return !isCluster(n) && fractions_[n] > 0.0f && fractions_[n] < 1.0f;
}

const CoverSamples* ElementExposure::coverSamplesOf(int n) const {
    if (!partlyCovered(n))
        return nullptr;
    const auto it = coverSamples_.find(element(n));
    return it == coverSamples_.end() ? nullptr : &it->second;
}

float ElementExposure::coveringGap(int e) const {
    return kCoveringGap * std::sqrt(mesh_.minElementArea(e));
}

bool ElementExposure::covered(int e, const ElementSample& x, const Vec3& n, uint64_t& rays) const {
    return hiddenByCoincident(coincident_, mesh_, e, glm::dot(n, x.n) > 0.0f, x) ||
           isCovered(scene_, mesh_, coincident_, x, n, coveringGap(e), rays);
}

Color ElementExposure::exposedMean(int n, const std::array<Color, 4>& values) const {
    const int first = mesh_.firstChild(element(n));
    Color sum(0.0f), plain(0.0f);
    float weight = 0.0f;
    for (int c = 0; c < RadiosityMesh::kChildren; ++c) {
        const float a = fractions_[node(first + c, front(n))];
        sum += a * values[c];
        weight += a;
        plain += values[c];
    }
    return weight > 0.0f ? sum / weight : plain / static_cast<float>(RadiosityMesh::kChildren);
}

// A wholly covered leaf side is seen by nobody, but it shares vertices with exposed leaves, whose
// nodal average (RadiosityMesh::setElementValues) it would darken (the ceiling around a lamp that
// hangs just under it, the floor around a block): it shows the mean over the exposed leaves
// below its nearest exposed ancestor instead.
std::function<Color(int, bool)> ElementExposure::shownValues(
    const std::function<Color(int, bool)>& value) const {
    std::array<std::vector<Color>, 2> mean;
    for (const bool side : {true, false}) {
        std::vector<Color>& m = mean[side ? 0 : 1];
        m.resize(mesh_.elementCount());
        // Children have larger ids than their parents.
        for (size_t i = m.size(); i-- > 0;) {
            const int e = static_cast<int>(i);
            const int first = mesh_.firstChild(e);
            if (first < 0) {
                m[i] = value(e, side);
                continue;
            }
            std::array<Color, 4> values;
            for (int c = 0; c < RadiosityMesh::kChildren; ++c)
                values[c] = m[static_cast<size_t>(first + c)];
            m[i] = exposedMean(node(e, side), values);
        }
    }
    return [this, mean = std::move(mean)](int e, bool side) {
        std::tie(e, side) = shownSide(e, side);
        while (!(fractions_[node(e, side)] > 0.0f) && mesh_.parent(e) >= 0)
            e = mesh_.parent(e);
        return mean[side ? 0 : 1][static_cast<size_t>(e)];
    };
}

std::pair<int, bool> ElementExposure::shownSide(int e, bool front) const {
    return shownLeafSide(scene_, mesh_, coincident_, e, front, [this](int leaf, bool side) {
        return fractions_[node(leaf, side)] > 0.0f;
    });
}

}  // namespace penumbra
