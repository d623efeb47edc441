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
        const bool front = glm::dot(d.normal, mesh_.normal(at.element)) > 0.0f;
        const Located located{at.element, front, d.mesh, d.triangle, d.barycentric, d.power};
        // Every ancestor of the leaf holds the deposit too.
        for (int e = at.element; e >= 0; e = mesh_.parent(e))
            add(e, located);
        deposits_.push_back(located);
        total_ += d.power;
    }
}

void DepositedFlux::add(int element, const Located& deposit) {
    flux_[slot(element, deposit.front)] += deposit.power;
}

void DepositedFlux::update() {
    flux_.resize(2 * mesh_.elementCount(), Color(0.0f));
    for (Located& d : deposits_) {
        if (mesh_.isLeaf(d.leaf))
            continue;
        const int leaf = mesh_.locate(d.mesh, d.triangle, d.barycentric).element;
        // The old leaf and its ancestors hold the deposit already; the elements below it do not.
        for (int e = leaf; e >= 0 && e != d.leaf; e = mesh_.parent(e))
            add(e, d);
        d.leaf = leaf;
    }
}

Color DepositedFlux::flux(int element, bool front) const {
    return flux_[slot(element, front)];
}

}  // namespace penumbra
