#include "tests/support/full_matrix_solve.h"

#include "radiosity/link_transfer.h"
#include "radiosity/solver_nodes.h"

#include <tbb/parallel_for.h>

#include <cstdint>
#include <utility>

namespace penumbra::test {

namespace {

// Sum of the three channels, the norm of the convergence test per element, as the solver's.
double channelSum(const Color& c) {
    return static_cast<double>(c.r) + c.g + c.b;
}

}  // namespace

std::vector<Color> solveFullMatrix(const RadiositySolver& solver, const RadiosityMesh& mesh) {
    const LinkTransfer& transfer = solver.linkTransfer();
    std::vector<int> nodes;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        if (mesh.isLeaf(static_cast<int>(e))) {
            nodes.push_back(node(static_cast<int>(e), true));
            nodes.push_back(node(static_cast<int>(e), false));
        }
    }
    // Rows of K_ij = F_ij V_ij over all pairs of leaf sides that can see each other.
    std::vector<std::vector<std::pair<size_t, Color>>> rows(nodes.size());
    tbb::parallel_for(size_t(0), nodes.size(), [&](size_t i) {
        for (size_t j = 0; j < nodes.size(); ++j) {
            if (!transfer.mayInteract(nodes[i], nodes[j]))
                continue;
            uint64_t rays = 0;
            const float F = transfer.exposedFormFactor(nodes[i], nodes[j],
                                                       transfer.formFactor(nodes[i], nodes[j]));
            if (F <= 0.0f)
                continue;
            const Color K = F * transfer.visibility(nodes[i], nodes[j], rays, false);
            if (maxComponent(K) > 0.0f)
                rows[i].emplace_back(j, K);
        }
    });
    // Gauss-Seidel on L_i = Le_i + rho_i (D_i + sum_j K_ij L_j) (Cohen and Wallace 1993,
    // chapter 5), from L = Le + rho D.
    std::vector<Color> x(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i)
        x[i] = solver.leafRadiance(nodes[i], Color(0.0f));
    for (int sweep = 0; sweep < 1000000; ++sweep) {
        double change = 0.0, norm = 0.0;
        for (size_t i = 0; i < nodes.size(); ++i) {
            Color H(0.0f);
            for (const auto& [j, K] : rows[i])
                H += K * x[j];
            const int n = nodes[i];
            const Color L = solver.leafRadiance(n, H);
            const double area = mesh.area(element(n));
            change += area * channelSum(glm::abs(L - x[i]));
            norm += area * channelSum(L);
            x[i] = L;
        }
        if (!(change > 1e-9 * norm))
            break;
    }
    std::vector<Color> result(2 * mesh.elementCount(), Color(0.0f));
    for (size_t i = 0; i < nodes.size(); ++i)
        result[nodes[i]] = x[i];
    return result;
}

}  // namespace penumbra::test
