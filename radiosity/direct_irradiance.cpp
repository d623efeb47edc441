// The punctual lights' and the environment's direct light and the deposited flux on the element
// sides.
#include "radiosity/direct_irradiance.h"

#include "core/scene.h"
#include "radiosity/element_sampling.h"
#include "radiosity/solver_nodes.h"

#include <tbb/parallel_for.h>

#include <atomic>

namespace penumbra {

DirectIrradiance::DirectIrradiance(const Scene& scene, const RadiosityMesh& mesh,
                                   const ElementExposure& exposure, int samples,
                                   const std::vector<FluxDeposit>& deposits)
    : scene_(scene), mesh_(mesh), exposure_(exposure), samples_(samples) {
    if (!deposits.empty())
        deposits_ = std::make_unique<DepositedFlux>(mesh_, deposits);
}

void DirectIrradiance::resize() {
    const size_t nodes = 2 * mesh_.elementCount();
    D_.resize(nodes, Color(0.0f));
    Denvironment_.resize(nodes, Color(0.0f));
    Dspread_.resize(nodes, 0.0f);
    if (transferred_)
        Dtransferred_.resize(nodes, Color(0.0f));
}

void DirectIrradiance::inherit(int childNode, int parentNode) {
    const auto child = static_cast<size_t>(childNode), parent = static_cast<size_t>(parentNode);
    D_[child] = D_[parent];
    Denvironment_[child] = Denvironment_[parent];
    Dspread_[child] = Dspread_[parent];
    if (transferred_)
        Dtransferred_[child] = Dtransferred_[parent];
}

void DirectIrradiance::updateDeposits() {
    if (deposits_)
        deposits_->update();
}

// The mean irradiance over the side's exposed part, divided by pi, of the flux deposited on it:
// photons land on the exposed part only.
Color DirectIrradiance::depositedD(const DepositedFlux& flux, int element, bool front) const {
    const float exposed = exposure_.fraction(node(element, front));
    const Color D = flux.flux(element, front) / (kPi * mesh_.area(element));
    return exposed > 0.0f ? D / exposed : D;
}

Color DirectIrradiance::depositedSources(int n) const {
    return deposits_ ? depositedD(*deposits_, element(n), front(n)) : Color(0.0f);
}

void DirectIrradiance::setTransferred(const std::vector<FluxDeposit>& deposits) {
    transferred_ = std::make_unique<DepositedFlux>(mesh_, deposits);
    Dtransferred_.assign(D_.size(), Color(0.0f));
    tbb::parallel_for(size_t(0), mesh_.elementCount(), [&](size_t i) {
        const int e = static_cast<int>(i);
        for (const bool front : {true, false})
            Dtransferred_[static_cast<size_t>(node(e, front))] =
                depositedD(*transferred_, e, front);
    });
}

// For each element: the irradiance of every delta light (point, spot, directional) at n
// stratified points with one shadow ray each, divided by pi, on the side facing the light
// (punctualDirect, element_sampling.h); its mean is the element's D and its spread (max - min over
// the points) what LinkRefiner::refineDirect() weighs. rho D is the reflected
// radiance of the Lambertian element: the punctual lights "shoot" into the elements before the
// gather starts (as the sources of the first step of progressive radiosity, Cohen, Chen, Wallace
// and Greenberg 1988). The deposited flux (the caustic photons', deposited_flux.h) adds its mean
// irradiance over the element, Phi / A, divided by pi, to D; it leaves the spread alone, so that
// photon noise does not drive refineDirect().
uint64_t DirectIrradiance::compute(const std::vector<int>& elements, SolveProgress* progress,
                                   const std::function<Pace(size_t done)>& pace, bool* stopped) {
    const std::vector<const Light*> lights = punctualLights(scene_);
    const bool sources = !lights.empty() || scene_.environment();
    if ((!sources && !deposits_) || elements.empty())
        return 0;
    if (deposits_)
        deposits_->update();
    // Read by the chunks' tasks, written only between chunks (parallelForWithProgress's stop).
    int n = samples_;
    const std::function<bool(size_t)> stop = [&](size_t done) {
        const Pace p = pace ? pace(done) : Pace::Full;
        if (p == Pace::Hurry)
            n = 1;
        return p == Pace::Stop;
    };
    std::atomic<uint64_t> rays{0};
    const bool completed = parallelForWithProgress(
        elements.size(), progress,
        [&](size_t i) {
            const int e = elements[i];
            const PunctualDirect direct =
                !sources ? PunctualDirect{}
                         : punctualDirect(scene_, mesh_, e, lights, n, ElementExposure::kPointSeed,
                                          &exposure_.coincident());
            rays += direct.rays;
            for (int side = 0; side < 2; ++side) {
                const int nd = node(e, side == 0);
                // The mean over the exposed part: the covered points' shadow rays are blocked.
                const float exposed = exposure_.fraction(nd);
                D_[nd] = exposed > 0.0f ? direct.D[side] / exposed : direct.D[side];
                Denvironment_[nd] =
                    exposed > 0.0f ? direct.environment[side] / exposed : direct.environment[side];
                if (deposits_)
                    D_[nd] += depositedD(*deposits_, e, side == 0);
                Dspread_[nd] = direct.spread[side];
            }
        },
        stop);
    if (stopped)
        *stopped = !completed;
    return rays;
}

}  // namespace penumbra
