// One gather sweep of the hierarchical solver (radiosity_solver.h), for the log and for tests of
// convergence.
#pragma once

namespace penumbra {

struct RadiosityIteration {
    int round = 0;          // 0 = before any refinement, then one per refinement round
    double change = 0.0;    // ||L_k - L_{k-1}|| / ||L_k||, area-weighted L1 over leaf sides
    double errorBound = 0;  // estimated ||L_k - L*|| / ||L_k|| (infinity until it can be estimated)
};

}  // namespace penumbra
