// The light the hierarchical solver (radiosity_solver.h) takes as given on every element side
// before it gathers: D_i, the irradiance of the punctual lights (point, spot, directional) and of
// the flux deposited by paths the solver does not follow (the caustic photons, deposited_flux.h),
// divided by pi (cd/m²), the mean over the side's exposed part (element_exposure.h).
#pragma once

#include "core/math.h"
#include "radiosity/deposited_flux.h"
#include "radiosity/element_exposure.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/solve_progress.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace penumbra {

class Scene;

// Indexed by the solver's nodes (solver_nodes.h) of element sides.
class DirectIrradiance {
  public:
    // All must outlive it; the mesh may be refined meanwhile (resize()). `samples`: points per
    // element, one shadow ray each per light.
    DirectIrradiance(const Scene& scene, const RadiosityMesh& mesh, const ElementExposure& exposure,
                     int samples, const std::vector<FluxDeposit>& deposits);

    // Makes room for the mesh's new elements.
    void resize();
    // A new child's side starts from its parent's until compute() samples its own.
    void inherit(int childNode, int parentNode);
    // D and its spread for both sides of `elements`. With `progress`, advances its current stage
    // by one per element. Returns the shadow rays it cast.
    uint64_t compute(const std::vector<int>& elements, SolveProgress* progress = nullptr);

    const Color& D(int node) const { return D_[static_cast<size_t>(node)]; }
    // The spread of max(D) of the punctual lights over the element's sample points.
    float spread(int node) const { return Dspread_[static_cast<size_t>(node)]; }
    // Exchanges D with `values`, one per node: the solver's first reflection of the emission
    // gathers without it for a sweep.
    void swap(std::vector<Color>& values) { D_.swap(values); }
    // Null without deposits.
    const DepositedFlux* deposits() const { return deposits_.get(); }

  private:
    const Scene& scene_;
    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    int samples_;
    std::unique_ptr<DepositedFlux> deposits_;  // null without deposits
    std::vector<Color> D_;
    std::vector<float> Dspread_;
};

}  // namespace penumbra
