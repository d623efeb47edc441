// The hierarchical radiosity solution's extended transfer through specular surfaces (light paths
// D S+ D, which its links between diffuse surfaces cannot carry: the seed's extended form factors
// for mirror-like surfaces, estimated with photons). Each round shoots photons from the light the
// current solution reflects (radiosity/reflected_light_emitter.h), aimed at the specular meshes
// as the caustic photons are (caustics/photon_tracer.h, tracePhotonsFromSurfaces); those that pass
// a mirror or glass land on the diffuse surface behind and become the solution's transferred light
// (RadiositySolver::transferThroughSpecular), with which it is solved again: the fixed-point
// iteration T = transfer(solve(E + T)), each round one specular transfer deeper, stopped when a
// round changes the transferred flux by less than kTransferConvergence of the flux the solution
// reflects (the truncation of a Neumann series, as the gather sweeps' own). A mesh that does not
// spread the sharp glossy lobes (MeshingSettings::spreadSharpGlossy) has their reflection carried
// here too, as a mirror's (D G D and, from the lights, L G D: a polished floor's image of the
// lit room on the wall opposite; caustics/photon_tracer.h, throughSharpGlossy). Here rather than
// in radiosity/ because it joins the radiosity and caustics libraries.
#pragma once

#include "caustics/photon_tracer.h"
#include "core/deadline.h"
#include "radiosity/deposited_flux.h"

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

class RadiosityMesh;
class RadiositySolver;
class Scene;
class SolveProgress;

// A round's change in the transferred flux below this fraction of the reflected flux ends the
// rounds; at most kMaxSpecularTransfers of them.
constexpr double kTransferConvergence = 0.005;
constexpr int kMaxSpecularTransfers = 8;
// Under a deadline, the pilot's share of the first round's photons (SpecularTransferSettings).
constexpr uint64_t kPilotFraction = 16;
// The automatic photon count per round: kTransferPhotonsPerLeaf per leaf element of the solved
// mesh (each element's transferred light is its photons' flux over its area, whose noise falls
// with the photons per element), at least kBaseTransferPhotons.
constexpr uint64_t kBaseTransferPhotons = 200000;
constexpr uint64_t kTransferPhotonsPerLeaf = 16;
uint64_t automaticTransferPhotons(const RadiosityMesh& mesh);

struct SpecularTransferSettings {
    uint64_t photons = kBaseTransferPhotons;  // per round
    // Round r uses the photons' sample sequence from index r * photons on: the rounds are
    // independent, and the result the same for any thread count.
    uint32_t seed = 0;
    // With a deadline, a pilot of 1/kPilotFraction of the first round's photons is shot first,
    // and if the flux it carries through the specular surfaces is within kTransferConvergence
    // of the reflected flux, there is no transfer (on the grey-white room, at most 0.2 %: its
    // round cost a 16-s preview 1.2 s and moved its mean by 0.1 %); and no round after the first
    // is begun that would end past the deadline, each taken to last as long as the one before
    // (as the final gather's passes).
    Deadline deadline;
};

// Runs the rounds on a solved solution (nothing without a specular mesh), each with a progress
// bar unless `quiet`, the solver's gathers reported to `solveProgress`.
void transferThroughSpecular(const Scene& scene, const RadiosityMesh& mesh, RadiositySolver& solver,
                             const SpecularTransferSettings& settings, bool quiet,
                             SolveProgress& solveProgress);

// Photons as flux deposited where they landed (for a radiosity solver).
std::vector<FluxDeposit> asDeposits(std::span<const Photon> photons);

}  // namespace penumbra
