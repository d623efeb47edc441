// The final gather of the hierarchical solver (radiosity_solver.h, "Final gather";
// RadiositySettings::finalGatherRays): rays from every leaf side gather its indirect light from the
// solution, and each patch side's mean difference from what the links gathered corrects the
// solution (RadianceHierarchy's correction), which the solver's gather sweeps then carry through
// every bounce.
#pragma once

#include "core/math.h"
#include "radiosity/element_exposure.h"
#include "radiosity/gathered_radiance.h"
#include "radiosity/meshed_hit.h"
#include "radiosity/radiance_hierarchy.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/solve_progress.h"

#include <cstdint>
#include <vector>

namespace penumbra {

class Scene;

class FinalGather {
  public:
    // All must outlive it. `raysPerSide`: rays per leaf side, cosine-distributed from stratified
    // points of it.
    FinalGather(const Scene& scene, const RadiosityMesh& mesh, const ElementExposure& exposure,
                const DirectIrradiance& irradiance, RadianceHierarchy& radiance, int raysPerSide);

    // One pass of the defect correction over `leaves`: gathers, then adds to the correction of
    // every leaf side the change of its patch side's. Advances `progress`, if any, by one per
    // leaf. Returns the change's area-weighted L1 norm relative to the gathered light's.
    double pass(const std::vector<int>& leaves, SolveProgress* progress);
    uint64_t rays() const { return rays_; }  // all passes'

  private:
    std::vector<Color> gatherIndirect(const std::vector<int>& leaves, SolveProgress* progress);

    const Scene& scene_;
    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    RadianceHierarchy& radiance_;
    GatheredRadiance gathered_;
    int raysPerSide_;
    uint64_t rays_ = 0;
};

}  // namespace penumbra
