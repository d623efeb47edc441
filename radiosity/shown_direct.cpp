#include "radiosity/shown_direct.h"

#include "radiosity/element_sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <string>

namespace penumbra {

namespace {

// Where the interpolation is tested: the edge midpoints and the centroid.
constexpr std::array<Vec3, 4> kTestPoints = {Vec3(0.5f, 0.5f, 0), Vec3(0, 0.5f, 0.5f),
                                             Vec3(0.5f, 0, 0.5f), Vec3(1.0f / 3.0f)};

float longestEdge(const RadiosityMesh& mesh, int element) {
    const std::array<Vec3, 3> c = mesh.corners(element);
    return std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
}

}  // namespace

ShownDirect::ShownDirect(const Scene& scene, RadiosityMesh& mesh, const SideExposed& exposed)
    : scene_(scene), mesh_(mesh), exposed_(exposed), sources_(scene, mesh, exposed) {}

ShownDirect::Sample ShownDirect::sample(int element, const ElementSample& x, bool front,
                                        uint64_t& rays) const {
    if (solver_->covered(element, x, front, rays))
        return {{}, true};
    return {sources_.D(x, front ? x.n : -x.n, rays), false};
}

std::array<PointDirect::Parts, 3> ShownDirect::shownCorners(int leaf, size_t side) const {
    const CornerParts& c = parts_[static_cast<size_t>(leaf)];
    PointDirect::Parts exposed;
    int count = 0;
    for (size_t k = 0; k < 3; ++k) {
        if (!c[3 * side + k].covered) {
            exposed.punctual += c[3 * side + k].D.punctual;
            exposed.environment += c[3 * side + k].D.environment;
            exposed.emitters += c[3 * side + k].D.emitters;
            ++count;
        }
    }
    if (count > 0) {
        exposed.punctual /= static_cast<float>(count);
        exposed.environment /= static_cast<float>(count);
        exposed.emitters /= static_cast<float>(count);
    } else {
        exposed.emitters = solver_->exposedMean(leaf, side == 0);
    }
    std::array<PointDirect::Parts, 3> shown;
    for (size_t k = 0; k < 3; ++k)
        shown[k] = c[3 * side + k].covered ? exposed : c[3 * side + k].D;
    return shown;
}

void ShownDirect::evaluateCorners(const std::vector<int>& leaves, SolveProgress* progress) {
    std::atomic<uint64_t> rays{0};
    parallelForWithProgress(leaves.size(), progress, [&](size_t i) {
        const int e = leaves[i];
        const ElementSampler sampler(scene_, mesh_, e);
        uint64_t r = 0;
        CornerParts& c = parts_[static_cast<size_t>(e)];
        for (size_t side = 0; side < 2; ++side) {
            if (!exposed_(e, side == 0))
                continue;
            for (size_t k = 0; k < 3; ++k)
                c[k + 3 * side] = sample(e, sampler.insetCorner(k), side == 0, r);
        }
        rays += r;
    });
    rays_ += rays;
}

// The children's corners in the parent's values (RadiosityMesh::kChildCorners), the points being
// the parent's corners c0, c1, c2 and test points m01, m12, m20.
void ShownDirect::inheritCorners(int parent, int firstChild) {
    const CornerParts& c = parts_[static_cast<size_t>(parent)];
    const TestPoints& t = tests_[static_cast<size_t>(parent)];
    for (size_t side = 0; side < 2; ++side) {
        const size_t o = 3 * side, m = 4 * side;
        const std::array<Sample, 6> points = {c[o], c[o + 1], c[o + 2], t[m], t[m + 1], t[m + 2]};
        for (int k = 0; k < RadiosityMesh::kChildren; ++k) {
            CornerParts& child = parts_[static_cast<size_t>(firstChild + k)];
            for (size_t j = 0; j < 3; ++j)
                child[o + j] = points[static_cast<size_t>(RadiosityMesh::kChildCorners[k][j])];
        }
    }
}

std::vector<int> ShownDirect::toSplit(const std::vector<int>& leaves, SolveProgress* progress) {
    std::vector<float> wrong(leaves.size(), 0.0f);
    std::atomic<uint64_t> rays{0};
    parallelForWithProgress(leaves.size(), progress, [&](size_t i) {
        uint64_t r = 0;
        wrong[i] = wrongness(leaves[i], r);
        rays += r;
    });
    rays_ += rays;
    std::vector<std::pair<float, int>> out;
    for (size_t i = 0; i < leaves.size(); ++i) {
        if (!(wrong[i] > 1.0f))
            continue;
        if (maySplit(leaves[i]))
            out.emplace_back(wrong[i], leaves[i]);
        else
            unresolved_.push_back(leaves[i]);
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<int> split(out.size());
    for (size_t i = 0; i < out.size(); ++i)
        split[i] = out[i].second;
    return split;
}

bool ShownDirect::maySplit(int leaf) const {
    return mesh_.canSplit(leaf, kMinElementArea) &&
           longestEdge(mesh_, leaf) >
               kMinEdgePerDistance * sources_.nearestSource(mesh_.centroid(leaf));
}

Color ShownDirect::energyShift(int leaf, size_t side) const {
    const std::array<PointDirect::Parts, 3> c = shownCorners(leaf, side);
    const Color corners = (c[0].punctual + c[1].punctual + c[2].punctual) / 3.0f;
    return solver_->punctualMean(leaf, side == 0) - corners;
}

// Each channel of the corners' punctual light scaled to the element's mean, or shifted where the
// corners have none: a shift alone took corners below zero beside a hard shadow, where one corner
// is lit and the element's mean is much less than the corners'.
void ShownDirect::keepEnergy(int leaf, size_t side) {
    const std::array<PointDirect::Parts, 3> c = shownCorners(leaf, side);
    const Color corners = (c[0].punctual + c[1].punctual + c[2].punctual) / 3.0f;
    const Color mean = solver_->punctualMean(leaf, side == 0);
    for (size_t k = 0; k < 3; ++k) {
        Color punctual = c[k].punctual;
        for (int i = 0; i < 3; ++i)
            punctual[i] = corners[i] > 0.0f ? punctual[i] * (mean[i] / corners[i]) : mean[i];
        corners_.at(leaf, side == 0, k) = punctual + c[k].environment + c[k].emitters;
    }
}

// Every test point is evaluated, also past the first that fails: a leaf that is split hands them
// to its children as corners.
float ShownDirect::wrongness(int leaf, uint64_t& rays) {
    TestPoints& t = tests_[static_cast<size_t>(leaf)];
    float worst = 0.0f;
    const auto weigh = [&](const Color& error, const Color& a, const Color& b,
                           float tolerance = kTolerance, float floor = 0.0f) {
        const float scale = std::max({maxComponent(a), maxComponent(b), floor_, floor});
        if (scale > 0.0f)
            worst = std::max(worst, maxComponent(glm::abs(error)) / (tolerance * scale));
    };
    const ElementSampler sampler(scene_, mesh_, leaf);
    for (size_t side = 0; side < 2; ++side) {
        if (!exposed_(leaf, side == 0))
            continue;
        const std::array<PointDirect::Parts, 3> c = shownCorners(leaf, side);
        const Color mean = (c[0].total() + c[1].total() + c[2].total()) / 3.0f;
        const Color shift = energyShift(leaf, side);
        weigh(shift, mean, mean + shift);
        for (size_t k = 0; k < kTestPoints.size(); ++k) {
            const Vec3 at = insetWeights(kTestPoints[k]);
            Sample& s = t[4 * side + k];
            s = sample(leaf, sampler.at(at), side == 0, rays);
            if (s.covered)
                continue;
            const auto interpolate = [&](Color PointDirect::Parts::*part) {
                return at.x * (c[0].*part) + at.y * (c[1].*part) + at.z * (c[2].*part);
            };
            const Color exact = s.D.punctual + s.D.emitters;
            const Color linear = interpolate(&PointDirect::Parts::punctual) +
                                 interpolate(&PointDirect::Parts::emitters);
            weigh(exact - linear, exact, linear);
            const Color linearEnvironment = interpolate(&PointDirect::Parts::environment);
            weigh(s.D.environment - linearEnvironment, s.D.environment, linearEnvironment,
                  kEnvironmentTolerance, environmentFloor_);
        }
    }
    return worst;
}

void ShownDirect::refine(const Solver& solver, size_t maxLeaves, SolveProgress* progress) {
    if (sources_.empty())
        return;
    solver_ = &solver;
    parts_.resize(mesh_.elementCount());
    tests_.resize(mesh_.elementCount());
    const std::vector<int> leaves = mesh_.leafElements();
    if (progress)
        progress->beginStage("direct light at the corners", leaves.size());
    evaluateCorners(leaves, progress);
    float brightest = 0.0f, brightestEnvironment = 0.0f;
    for (const int e : leaves) {
        for (const Sample& s : parts_[static_cast<size_t>(e)]) {
            brightest = std::max(brightest, maxComponent(s.D.total()));
            brightestEnvironment = std::max(brightestEnvironment, maxComponent(s.D.environment));
        }
    }
    floor_ = kFloor * brightest;
    environmentFloor_ = kEnvironmentFloor * brightestEnvironment;
    std::vector<int> split = toSplit(leaves, nullptr);
    if (progress)
        progress->endStage(std::to_string(split.size()) + " leaves to split");
    for (int round = 1; !split.empty(); ++round) {
        if (solver.stop && solver.stop()) {
            stopped_ = true;
            unresolved_.insert(unresolved_.end(), split.begin(), split.end());
            break;
        }
        const size_t room = maxLeaves > mesh_.leafCount() ? maxLeaves - mesh_.leafCount() : 0;
        // A split adds three leaves.
        if (split.size() * 3 > room) {
            budgetReached_ = true;
            unresolved_.insert(unresolved_.end(), split.begin() + room / 3, split.end());
            split.resize(room / 3);
            if (split.empty())
                break;
        }
        std::vector<int> children;
        for (const int e : split) {
            const int first = solver.split(e, kMinElementArea);
            parts_.resize(mesh_.elementCount());
            tests_.resize(mesh_.elementCount());
            inheritCorners(e, first);
            for (int c = first; c < first + RadiosityMesh::kChildren; ++c)
                children.push_back(c);
        }
        leavesSplit_ += split.size();
        solver.settle();
        if (progress)
            progress->beginStage("direct light at the corners, split " + std::to_string(round),
                                 children.size());
        split = toSplit(children, progress);
        if (progress)
            progress->endStage(std::to_string(mesh_.leafCount()) + " leaves");
    }
    // The totals, shifted where the mesh could not follow the light.
    corners_.assign(mesh_.elementCount());
    const auto shownMean = solver_->shownMeans();
    for (const int e : mesh_.leafElements()) {
        for (size_t side = 0; side < 2; ++side) {
            const bool front = side == 0;
            if (!exposed_(e, front)) {
                // Shows the element mean the solution would show without corners (that of the
                // face it lies under, for a hidden coincident face), so that the vertex values
                // around it are not pulled down.
                const Color D = shownMean(e, front);
                for (size_t k = 0; k < 3; ++k)
                    corners_.at(e, front, k) = D;
                continue;
            }
            const std::array<PointDirect::Parts, 3> c = shownCorners(e, side);
            for (size_t k = 0; k < 3; ++k)
                corners_.at(e, front, k) = c[k].total();
        }
    }
    for (const int e : unresolved_) {
        for (size_t side = 0; side < 2; ++side) {
            if (exposed_(e, side == 0))
                keepEnergy(e, side);
        }
    }
    corners_.anchorTVertices(mesh_, exposed_);
    parts_ = {};
    tests_ = {};
    solver_ = nullptr;
}

Color ShownDirect::D(const ElementPoint& point, bool front) const {
    return corners_.interpolate(point, front);
}

std::array<Color, 3> ShownDirect::cornerD(int element, bool front) const {
    return corners_.corners(element, front);
}

}  // namespace penumbra
