// The hierarchical solver's guard against a diverging gather (GatherIteration::run). The
// iteration is a contraction in the area-weighted L1 norm when every receiver's rho times the sum
// of its form factors is below 1 (by reciprocity, A_i F_ij = A_j F_ji, the norm of rho F is the
// largest such sum), so its absolute changes fall sweep after sweep; the first sweeps of a round
// may still grow a little while light spreads into new leaves. A scene whose receivers see more
// than their whole hemisphere (a surface counted twice) breaks that, and the solver must say so
// rather than sweep max_iterations times to an infinite answer.
#pragma once

#include <cstddef>
#include <vector>

namespace penumbra {

// A gather whose absolute change grew this many sweeps in a row, and by kDivergenceGrowth in all,
// diverges.
constexpr size_t kDivergenceSweeps = 20;
constexpr double kDivergenceGrowth = 2.0;

// Whether the last kDivergenceSweeps of the sweeps' absolute changes each grew, and grew
// kDivergenceGrowth-fold in all.
inline bool gatherDiverges(const std::vector<double>& absoluteChanges) {
    const size_t n = absoluteChanges.size();
    if (n <= kDivergenceSweeps)
        return false;
    for (size_t k = n - kDivergenceSweeps; k < n; ++k) {
        if (!(absoluteChanges[k] > absoluteChanges[k - 1]))
            return false;
    }
    return absoluteChanges.back() > kDivergenceGrowth * absoluteChanges[n - 1 - kDivergenceSweeps];
}

}  // namespace penumbra
