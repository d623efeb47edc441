// The light the hierarchical solver (radiosity_solver.h) takes as given on every element side
// before it gathers: D_i, the irradiance of the punctual lights (point, spot, directional), of the
// environment (environment_direct.h) and of the flux deposited by paths the solver does not
// follow (the caustic photons, deposited_flux.h), divided by pi (cd/m²), the mean over the side's
// exposed part (element_exposure.h).
//
// Two kinds of deposited flux: the sources' (the caustic photons, L S+ D), part of the first
// reflection of the sources that the two-pass methods trace themselves, and the transferred
// (the solution's own reflected light carried through specular surfaces, D S+ D:
// setTransferred()), part of the indirect light. D sums both; computeDirectPart shows only the
// sources' (show()).
#pragma once

#include "core/math.h"
#include "radiosity/deposited_flux.h"
#include "radiosity/element_exposure.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/solve_progress.h"

#include <cstdint>
#include <functional>
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
    // Moves the caustic photons' deposits down to the leaves split since the last call
    // (DepositedFlux::update), as compute() does first: for splits whose children keep their
    // parent's D (the refinement at creases), so that depositedSources() reads them.
    void updateDeposits();
    // How compute() goes on with the elements left: at full samples, with one point each (a
    // solve short of time: D unbiased but noisier, its spread unknown and taken as 0, so that
    // it splits nothing), or not at all.
    enum class Pace { Full, Hurry, Stop };
    // D and its spread for both sides of `elements`. With `progress`, advances its current stage
    // by one per element. Returns the shadow rays it cast. `pace`, when given, is asked between
    // chunks of elements with the number done: once it says Hurry the rest take one point, once
    // it says Stop the rest are left as they were and `*stopped` (if given) is set.
    uint64_t compute(const std::vector<int>& elements, SolveProgress* progress = nullptr,
                     const std::function<Pace(size_t done)>& pace = nullptr,
                     bool* stopped = nullptr);

    // What D() shows: everything (the default), the sources' part only, or nothing; the
    // solver's first reflection of the emission gathers with less for a sweep.
    enum class Part { All, Sources, None };
    void show(Part part) { shown_ = part; }

    Color D(int node) const {
        const auto n = static_cast<size_t>(node);
        switch (shown_) {
            case Part::All:
                return transferred_ ? D_[n] + Dtransferred_[n] : D_[n];
            case Part::Sources:
                return D_[n];
            case Part::None:
                break;
        }
        return Color(0.0f);
    }
    // The sources' part of D, whatever show() says: D less the transferred flux.
    Color sources(int node) const { return D_[static_cast<size_t>(node)]; }
    // The sources' deposited flux's part of D (the caustic photons'): zero without deposits.
    Color depositedSources(int node) const;
    // The punctual lights' part of D, whatever show() says.
    Color punctual(int node) const {
        const auto n = static_cast<size_t>(node);
        return glm::max(D_[n] - Denvironment_[n] - depositedSources(node), Color(0.0f));
    }
    // The environment's part of D.
    Color environment(int node) const { return Denvironment_[static_cast<size_t>(node)]; }
    // The spread of max(D) of the punctual lights over the element's sample points.
    float spread(int node) const { return Dspread_[static_cast<size_t>(node)]; }
    // Null without deposits.
    const DepositedFlux* deposits() const { return deposits_.get(); }

    // Replaces the transferred flux (the light the solution's reflection sent through specular
    // surfaces onto the elements) with `deposits`, on every element side of the mesh as it is.
    void setTransferred(const std::vector<FluxDeposit>& deposits);
    // Null before setTransferred().
    const DepositedFlux* transferred() const { return transferred_.get(); }
    // The transferred flux's part of D: zero before setTransferred().
    Color transferredD(int node) const {
        return transferred_ ? Dtransferred_[static_cast<size_t>(node)] : Color(0.0f);
    }

  private:
    Color depositedD(const DepositedFlux& flux, int element, bool front) const;

    const Scene& scene_;
    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    int samples_;
    // D's two parts: the sources' is in D_ (null deposits_ without caustic photons), the
    // transferred flux's in Dtransferred_ (null transferred_ before setTransferred()).
    std::unique_ptr<DepositedFlux> deposits_;
    std::unique_ptr<DepositedFlux> transferred_;
    std::vector<Color> D_;
    std::vector<Color> Denvironment_;  // the environment's part of D_
    std::vector<Color> Dtransferred_;
    std::vector<float> Dspread_;
    Part shown_ = Part::All;
};

}  // namespace penumbra
