// The final gather's rays and the correction they make.
#include "radiosity/final_gather.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/element_sampling.h"
#include "radiosity/solver_nodes.h"

#include <tbb/combinable.h>

#include <optional>

namespace penumbra {

namespace {

// The final gather's sampler seed, apart from those of the links' visibility (link_transfer.cpp)
// and of the element points (ElementExposure::kPointSeed), so that they never share a sequence.
constexpr uint32_t kFinalGatherSeed = 0xc2b2ae35u;

}  // namespace

FinalGather::FinalGather(const Scene& scene, const RadiosityMesh& mesh,
                         const ElementExposure& exposure, const DirectIrradiance& irradiance,
                         RadianceHierarchy& radiance, int raysPerSide)
    : scene_(scene),
      mesh_(mesh),
      exposure_(exposure),
      radiance_(radiance),
      gathered_(scene, mesh, exposure, irradiance, radiance),
      raysPerSide_(raysPerSide) {}

// The final gather: a Monte Carlo gather of each leaf side's indirect light from the solution, as
// Rushmeier, Patterson and Veerasamy 1993 ("Geometric Simplification for Indirect Illumination
// Calculations", Graphics Interface '93) gather from a coarse radiosity solution. The links'
// transfer errs where clusters stand for many patches (a receiving cluster gives all its patches
// one visible fraction: docs/radiosity.md, "Where the rest of the walls' deficit lies"); rays
// see the solution itself. With x_k stratified over the side's exposed part and w_k
// cosine-distributed about its normal,
//     G = rho / N sum_k T_k L_r(y_k),
// y_k the first surface the mesh holds along the ray (meshed_hit.h, through thin glass of
// transmittance T_k) and L_r the reflected radiance the surface there sends back along the ray
// (GatheredRadiance::seen: its leaf side's, the glossy lobes followed), is an
// unbiased estimate of the light the side reflects of the others' reflected light, its indirect
// part (the first reflection of the sources, elementDirect, stays the links': an emitter seen by a
// few cosine rays would make G far noisier).
//
// One gather only corrects the last bounce; its light keeps the links' error one bounce back.
// So the gather drives a defect correction (iterative refinement with the links' operator as the
// approximate inverse): with T_h the links' transfer and T the gather's, the solution of
//     L = Le + rho D + T_h L + C,   C = (T - T_h) L
// solves L = Le + rho D + T L. Each pass adds to every leaf side's correction C (RadianceHierarchy,
// added in leafRadiance) the difference between G and its current indirect light, then the gather
// sweeps converge with the links (GatherIteration::run). The error falls by the norm of
// (I - T_h)^-1 (T - T_h) per pass, small where the links are nearly right: the relative change of
// the correction was 2.2 % then 0.1 % on the modern hall, 1.3 % then 0.05 % on the Cornell box.
// The rays are the same in every pass (the same sampler seeds), so that the passes converge to the
// fixed point of one estimator rather than wander with new noise.
//
// The difference is taken as its mean over the patch side's exposed area, not per leaf: per leaf,
// 64 rays showed as blotches on the Cornell box's walls; the links' error it corrects (a cluster's
// one visible fraction, a far link's form factor) varies slowly over a patch. Measured on the
// modern hall (variant C of docs/radiosity.md, "How the accuracy was measured"), per patch keeps
// about three quarters of what per leaf gains: walls 0.954 -> 0.960 (0.961 per leaf) of the path
// tracer.
double FinalGather::pass(const std::vector<int>& leaves, SolveProgress* progress) {
    const std::vector<Color> gathered = gatherIndirect(leaves, progress);
    // The change of each patch side's correction: the exposed-area mean of G less the
    // indirect light over its leaves.
    const size_t nodes = radiance_.nodeCount();
    std::vector<Color> patchDelta(2 * mesh_.patchCount(), Color(0.0f));
    std::vector<double> patchArea(2 * mesh_.patchCount(), 0.0);
    for (size_t nd = 0; nd < nodes; ++nd) {
        if (!(gathered[nd].r >= 0.0f))
            continue;
        const int n = static_cast<int>(nd);
        const double area = mesh_.area(element(n)) * exposure_.fraction(n);
        const int root = node(mesh_.patch(element(n)), front(n));
        patchDelta[root] += static_cast<float>(area) *
                            (gathered[nd] - (radiance_.L(n) - radiance_.emission(n) -
                                             radiance_.elementDirect(element(n), front(n))));
        patchArea[root] += area;
    }
    // Area-weighted L1 norms of the change and of the gathered light, over leaf sides.
    double change = 0.0, norm = 0.0;
    for (size_t nd = 0; nd < nodes; ++nd) {
        if (!(gathered[nd].r >= 0.0f))
            continue;
        const int n = static_cast<int>(nd);
        const int root = node(mesh_.patch(element(n)), front(n));
        const Color delta = patchDelta[root] / static_cast<float>(patchArea[root]);
        radiance_.addCorrection(n, delta);
        const double area = mesh_.area(element(n)) * exposure_.fraction(n);
        change += area * channelSum(glm::abs(delta));
        norm += area * channelSum(gathered[nd]);
    }
    return norm > 0.0 ? change / norm : 0.0;
}

// G of pass() for every exposed side of `leaves` that reflects, per node; -1 elsewhere.
std::vector<Color> FinalGather::gatherIndirect(const std::vector<int>& leaves,
                                               SolveProgress* progress) {
    const auto n = static_cast<uint32_t>(raysPerSide_);
    std::vector<Color> gathered(radiance_.nodeCount(), Color(-1.0f));
    tbb::combinable<uint64_t> rays([] { return uint64_t(0); });
    parallelForWithProgress(leaves.size(), progress, [&](size_t i) {
        const int e = leaves[i];
        const Color rho = mesh_.rho(e);
        if (!(maxComponent(rho) > 0.0f))
            return;
        uint64_t& count = rays.local();
        for (const bool side : {true, false}) {
            const int nd = node(e, side);
            if (!exposure_.exposed(nd))
                continue;
            Sampler sampler(kFinalGatherSeed);
            Color sum(0.0f);
            uint32_t used = 0;
            for (uint32_t k = 0; k < n; ++k) {
                sampler.startPixelSample(IVec2(e, side ? 0 : 1), k);
                const ElementSample x = sampleElement(scene_, mesh_, e, sampler.get2D());
                const Vec3 normal = side ? x.n : -x.n;
                if (exposure_.partlyCovered(nd) && exposure_.covered(e, x, normal, count))
                    continue;
                const Vec3 w =
                    Frame::fromNormal(normal).toWorld(sampleCosineHemisphere(sampler.get2D()));
                ++used;
                const std::optional<MeshedHit> y = firstMeshedHit(
                    scene_, mesh_, Ray{offsetRayOrigin(x.p, x.pError, x.n, w), w}, count);
                if (y)
                    sum += y->transmittance * gathered_.seen(*y, sampler, count);
            }
            if (used > 0)
                gathered[static_cast<size_t>(nd)] = rho * sum / static_cast<float>(used);
        }
    });
    rays_ += rays.combine(std::plus<uint64_t>());
    return gathered;
}

}  // namespace penumbra
