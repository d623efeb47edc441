// The final gather of the hierarchical solver (radiosity_solver.h, "Final gather";
// RadiositySettings::finalGatherRays): rays from every leaf side gather its indirect light from the
// solution, and shadow rays towards the emitters its first reflection of their light; each patch
// side's mean difference from what the links gathered corrects the solution (RadianceHierarchy's
// correction), which the solver's gather sweeps then carry through every bounce.
#pragma once

#include "core/math.h"
#include "core/sampling.h"
#include "radiosity/direct_irradiance.h"
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
    // every leaf side the change of its patch side's. The `first` pass of a correction (after
    // RadianceHierarchy::clearCorrection) also gathers the emitters' first reflection, which the
    // passes after it reuse. Advances `progress`, if any, by one per leaf. Returns the change's
    // area-weighted L1 norm relative to the gathered light's.
    double pass(const std::vector<int>& leaves, bool first, SolveProgress* progress);
    uint64_t rays() const { return rays_; }  // all passes'

  private:
    std::vector<Color> gatherIndirect(const std::vector<int>& leaves, bool withEmitters,
                                      SolveProgress* progress);
    void tableEmitters();
    float emitterPdf(int entry, const Vec3& x, const Vec3& z, const Vec3& nz) const;
    Color emissionSeen(const ElementSample& x, const Vec3& normal, const Vec3& w,
                       const MeshedHit& y) const;
    Color emittersIrradiance(const ElementSample& x, const Vec3& normal, Sampler& sampler,
                             uint64_t& rays) const;

    const Scene& scene_;
    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    const DirectIrradiance& irradiance_;
    RadianceHierarchy& radiance_;
    GatheredRadiance gathered_;
    // The emitting patch sides that are exposed (a face modelled twice emits once), by power:
    // their nodes, an alias table over them and each node's entry (-1 for none).
    std::vector<int> emitterNodes_;
    AliasTable emitterTable_;
    std::vector<int> emitterEntry_;
    int raysPerSide_;
    // Per node, the first reflection of the emitters' light that the first pass gathered (the
    // same rays in every pass); zero where none was gathered.
    std::vector<Color> emittersReflected_;
    uint64_t rays_ = 0;
};

}  // namespace penumbra
