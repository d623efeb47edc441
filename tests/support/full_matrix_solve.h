// The dense reference of the hierarchical solver's tests and benchmark: the solver's equation over
// all pairs of leaf sides of its current mesh, with a dense matrix.
#pragma once

#include "core/math.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"

#include <vector>

namespace penumbra::test {

// The radiosity equation L_i = Le_i + rho_i (D_i + sum_j F_ij V_ij L_j) of `solver`
// (radiosity_solver.h) over all pairs of leaf sides of `mesh`, the mesh the solver refined, with a
// dense matrix (Gauss-Seidel until the relative change is below 1e-9), with form factors and
// visibility computed as for links. Returns the radiance per node (element side, index
// 2 * element + (front ? 0 : 1)), zero for non-leaves. Cost O(leaves^2).
std::vector<Color> solveFullMatrix(const RadiositySolver& solver, const RadiosityMesh& mesh);

}  // namespace penumbra::test
