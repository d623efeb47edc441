// The gather sweeps of the hierarchical solver (radiosity_solver.h) until its solution has
// converged: the a posteriori error bound of a contraction from the sweeps' changes, the guard
// against a diverging gather (gather_divergence.h), and the record of every sweep.
#pragma once

#include "radiosity/link_hierarchy.h"
#include "radiosity/radiance_hierarchy.h"
#include "radiosity/radiosity_iteration.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/solve_progress.h"

#include <string>
#include <vector>

namespace penumbra {

class Scene;

class GatherIteration {
  public:
    // All must outlive it. `maxIterations`: sweeps over all runs together.
    GatherIteration(const Scene& scene, const RadiosityMesh& mesh, LinkHierarchy& links,
                    RadianceHierarchy& radiance, int maxIterations);

    // Sweeps until the estimated relative error is below `threshold` or the sweeps run out,
    // after setting the child weights of the links whose ends were split. Reports itself to
    // `progress`, if any, as the stage `stage`. Throws SceneError naming the mesh and place of
    // the brightest leaf if the gather diverges.
    void run(double threshold, int round, const std::string& stage, SolveProgress* progress);

    // Whether the last run converged.
    bool converged() const { return converged_; }
    const std::vector<RadiosityIteration>& iterations() const { return iterations_; }

  private:
    [[noreturn]] void throwDivergence(const std::string& stage, double growth) const;

    const Scene& scene_;
    const RadiosityMesh& mesh_;
    LinkHierarchy& links_;
    RadianceHierarchy& radiance_;
    int maxIterations_;
    std::vector<RadiosityIteration> iterations_;
    bool converged_ = false;
    // The largest contraction factor run() has measured so far (-1 before any), which the
    // gathers after a refinement take until they measure their own.
    double contraction_ = -1.0;
};

}  // namespace penumbra
