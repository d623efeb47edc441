// The gather iteration's stopping rule and its guard against divergence.
#include "radiosity/gather_iteration.h"

#include "core/errors.h"
#include "core/scene.h"
#include "radiosity/gather_divergence.h"
#include "radiosity/solver_nodes.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

namespace penumbra {

namespace {

// Relative change of a sweep below which it is rounding (run): a tenth of float's epsilon, as the
// area-weighted L1 change of one element's last bit is smaller still.
constexpr double kRoundingChange = 0.1 * std::numeric_limits<float>::epsilon();

// Units of a gather stage's progress (run): the fraction of the way to the threshold.
constexpr uint64_t kGatherProgressUnits = 1000;

}  // namespace

GatherIteration::GatherIteration(const Scene& scene, const RadiosityMesh& mesh,
                                 LinkHierarchy& links, RadianceHierarchy& radiance,
                                 int maxIterations)
    : scene_(scene),
      mesh_(mesh),
      links_(links),
      radiance_(radiance),
      maxIterations_(maxIterations) {}

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
void GatherIteration::run(double threshold, int round, const std::string& stage,
                          SolveProgress* progress) {
    if (progress)
        progress->beginStage(stage, kGatherProgressUnits);
    links_.updateChildWeights();
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
            if (progress)
                progress->advance(units - reported);
            reported = units;
        }
    };
    while (iterations_.size() < static_cast<size_t>(maxIterations_)) {
        RadiosityIteration it;
        it.round = round;
        const ChangeSums sums = radiance_.sweep();
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
    if (progress)
        progress->endStage(summary.str());
}

// A diverging gather comes from the scene: some receiver's rho times the sum of its form factors
// exceeds 1, which closed geometry cannot do unless surfaces are counted twice. Coincident faces
// in one plane are counted once (coincident_faces.h; they caused this in the modern hall);
// whatever else still does it, the error names the scene mesh and the place where the radiance
// grew most, the brightest leaf.
void GatherIteration::throwDivergence(const std::string& stage, double growth) const {
    int brightest = -1;
    float most = -1.0f;
    for (size_t n = 0; n < radiance_.nodeCount(); ++n) {
        const int e = element(static_cast<int>(n));
        const Color& L = radiance_.L(static_cast<int>(n));
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

}  // namespace penumbra
