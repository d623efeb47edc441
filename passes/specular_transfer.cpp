#include "passes/specular_transfer.h"

#include "core/progress.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "radiosity/reflected_light_emitter.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace penumbra {

uint64_t automaticTransferPhotons(const RadiosityMesh& mesh) {
    return std::max<uint64_t>(kBaseTransferPhotons, kTransferPhotonsPerLeaf * mesh.leafCount());
}

std::vector<FluxDeposit> asDeposits(std::span<const Photon> photons) {
    std::vector<FluxDeposit> deposits;
    deposits.reserve(photons.size());
    for (const Photon& photon : photons)
        deposits.push_back(
            {photon.mesh, photon.triangle, photon.barycentric, photon.n, photon.power});
    return deposits;
}

void transferThroughSpecular(const Scene& scene, const RadiosityMesh& mesh, RadiositySolver& solver,
                             const SpecularTransferSettings& settings, bool quiet,
                             SolveProgress& solveProgress) {
    const bool sharpGlossy = !mesh.spreadsSharpGlossy();
    // The lights' own light through sharp glossy surfaces (L S* G S* D, G sharp; through delta
    // lobes alone it is the caustic photons'): the solution does not change it, so it is shot
    // once, after the rounds' sample indices, and given to every round.
    std::vector<FluxDeposit> fromLights;
    if (sharpGlossy) {
        PhotonTracerSettings lights;
        lights.photons = settings.photons;
        lights.seed = settings.seed;
        lights.firstIndex = static_cast<uint64_t>(kMaxSpecularTransfers) * settings.photons;
        lights.throughSharpGlossy = lights.onlyThroughSharpGlossy = true;
        Progress progress("radiosity: lights through sharp glossy surfaces", settings.photons,
                          quiet);
        fromLights = asDeposits(tracePhotons(scene, lights, &progress).photons);
    }
    double previous = 0.0;
    for (int round = 0; round < kMaxSpecularTransfers; ++round) {
        const auto roundStart = std::chrono::steady_clock::now();
        const ReflectedLightEmitter emitter(scene, mesh, solver);
        const SurfaceEmitter sample = [&](float uChoice, Vec2 u) -> std::optional<SurfaceEmission> {
            const auto point = emitter.sample(uChoice, u);
            if (!point)
                return std::nullopt;
            return SurfaceEmission{point->p, point->pError, point->n, point->L, point->pdf};
        };
        PhotonTracerSettings photons;
        photons.photons = settings.photons;
        photons.seed = settings.seed;
        photons.firstIndex = static_cast<uint64_t>(round) * settings.photons;
        photons.throughSharpGlossy = sharpGlossy;
        if (round == 0 && settings.deadline) {
            // Under a time limit, a pilot of the first photons first: a transfer whose first
            // round would carry less than the rounds' own tolerance is not worth its time.
            PhotonTracerSettings pilot = photons;
            pilot.photons = std::max<uint64_t>(settings.photons / kPilotFraction, 1);
            const PhotonTraceResult piloted =
                tracePhotonsFromSurfaces(scene, sample, emitter.power(), pilot, nullptr);
            if (piloted.specularMeshes == 0 ||
                luminance(piloted.storedPower) <=
                    kTransferConvergence * luminance(emitter.power())) {
                if (!fromLights.empty())
                    solver.transferThroughSpecular(fromLights, &solveProgress);
                return;
            }
        }
        PhotonTraceResult traced;
        {
            Progress progress("radiosity: specular transfer " + std::to_string(round + 1),
                              settings.photons, quiet);
            traced = tracePhotonsFromSurfaces(scene, sample, emitter.power(), photons, &progress);
        }
        if (traced.specularMeshes == 0)
            return;
        std::vector<FluxDeposit> deposits = asDeposits(traced.photons);
        deposits.insert(deposits.end(), fromLights.begin(), fromLights.end());
        solver.transferThroughSpecular(deposits, &solveProgress);
        const double transferred = luminance(traced.storedPower);
        const double change = std::abs(transferred - previous);
        previous = transferred;
        if (change <= kTransferConvergence * luminance(emitter.power()))
            return;
        if (nextStepWouldOverrun(std::chrono::steady_clock::now() - roundStart, settings.deadline))
            return;
    }
}

}  // namespace penumbra
