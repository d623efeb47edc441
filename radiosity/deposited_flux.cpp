#include "radiosity/deposited_flux.h"

namespace penumbra {

DepositedFlux::DepositedFlux(const RadiosityMesh& mesh, const std::vector<FluxDeposit>& deposits)
    : mesh_(mesh) {
    flux_.assign(2 * mesh_.elementCount(), Color(0.0f));
    deposits_.reserve(deposits.size());
    for (const FluxDeposit& d : deposits) {
        const ElementPoint at = mesh_.locate(d.mesh, d.triangle, d.barycentric);
        if (at.element < 0) {
            ++dropped_;
            continue;
        }
        const Located located{d, at.element, glm::dot(d.normal, mesh_.normal(at.element)) > 0.0f};
        // Every ancestor of the leaf holds the deposit too.
        for (int e = at.element; e >= 0; e = mesh_.parent(e))
            add(e, located);
        deposits_.push_back(located);
    }
}

void DepositedFlux::add(int element, const Located& located) {
    flux_[slot(element, located.front)] += located.deposit.power;
}

void DepositedFlux::update() {
    flux_.resize(2 * mesh_.elementCount(), Color(0.0f));
    for (Located& located : deposits_) {
        if (mesh_.isLeaf(located.leaf))
            continue;
        const FluxDeposit& d = located.deposit;
        const int leaf = mesh_.locate(d.mesh, d.triangle, d.barycentric).element;
        // The old leaf and its ancestors hold the deposit already; the elements below it do not.
        for (int e = leaf; e >= 0 && e != located.leaf; e = mesh_.parent(e))
            add(e, located);
        located.leaf = leaf;
    }
}

Color DepositedFlux::flux(int element, bool front) const {
    return flux_[slot(element, front)];
}

Color DepositedFlux::totalPower() const {
    Color total(0.0f);
    for (size_t p = 0; p < mesh_.patchCount(); ++p)
        total += flux(static_cast<int>(p), true) + flux(static_cast<int>(p), false);
    return total;
}

}  // namespace penumbra
