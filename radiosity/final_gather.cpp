// The final gather's rays and the correction they make.
#include "radiosity/final_gather.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/coincident_faces.h"
#include "radiosity/element_sampling.h"
#include "radiosity/solver_nodes.h"

#include <tbb/combinable.h>

#include <cmath>
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
      irradiance_(irradiance),
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
// part. The first reflection of the emitters' light is gathered at the same points and by the
// same rays, combined with next-event estimation as the path tracer does (a small lamp seen by a
// few cosine rays alone would make it far noisier; a large emitter close by, by next-event
// estimation alone): one emitting patch side drawn per point by power and a point z_k uniformly
// on it, hidden if a coincident face covers it there (coincident_faces.h: a face modelled twice
// emits once, as in the links), with solid-angle density p_l, and the ray's emission seen (of the
// side shown where it lands), with density p_c = cos / pi, weighed by the power heuristic (Veach
// 1997, Eq. 9.13),
//     G_e = rho / N sum_k [w_l V_k Le(z_k) cos(theta_k) / (pi p_l(z_k)) + w_c T_k Le(y_k)],
// Le the patch side's (its mean over the patch, as the links take it).
// The links carried that light with the same cluster errors as the rest: in a closed room whose
// every side emits (tests/radiosity/final_gather_test.cpp), where the first reflection is rho Le
// everywhere, theirs was 10 % high on average and up to 37 % off on a patch side; gathered, it is
// within the noise. The punctual lights' and the environment's light (D, direct_irradiance.h) are
// sampled per element already and stay as they are.
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
double FinalGather::pass(const std::vector<int>& leaves, bool first, SolveProgress* progress) {
    if (first)
        tableEmitters();
    const std::vector<Color> gathered = gatherIndirect(leaves, first, progress);
    // The change of each patch side's correction: the exposed-area mean of G + G_e less the
    // reflected light the links give its leaves besides D's, rho D; and, in the first pass, of
    // its part in the first reflection, G_e less the links' first reflection of the emission
    // (elementDirect less rho D's sources' part), which the correction then holds.
    const size_t nodes = radiance_.nodeCount();
    std::vector<Color> patchDelta(2 * mesh_.patchCount(), Color(0.0f));
    std::vector<Color> patchDirect(2 * mesh_.patchCount(), Color(0.0f));
    std::vector<double> patchArea(2 * mesh_.patchCount(), 0.0);
    for (size_t nd = 0; nd < nodes; ++nd) {
        if (!(gathered[nd].r >= 0.0f))
            continue;
        const int n = static_cast<int>(nd);
        const int e = element(n);
        const auto a = static_cast<float>(mesh_.area(e) * exposure_.fraction(n));
        const int root = node(mesh_.patch(e), front(n));
        const Color& rho = mesh_.rho(e);
        const Color& Ge = emittersReflected_[nd];
        patchDelta[root] += a * (gathered[nd] + Ge -
                                 (radiance_.L(n) - radiance_.emission(n) - rho * irradiance_.D(n)));
        if (first)
            patchDirect[root] +=
                a * (Ge - (radiance_.elementDirect(e, front(n)) - rho * irradiance_.sources(n)));
        patchArea[root] += a;
    }
    // Area-weighted L1 norms of the change and of the gathered light, over leaf sides.
    double change = 0.0, norm = 0.0;
    for (size_t nd = 0; nd < nodes; ++nd) {
        if (!(gathered[nd].r >= 0.0f))
            continue;
        const int n = static_cast<int>(nd);
        const int root = node(mesh_.patch(element(n)), front(n));
        const auto area = static_cast<float>(patchArea[root]);
        const Color delta = patchDelta[root] / area;
        radiance_.addCorrection(n, delta, patchDirect[root] / area);
        const double a = mesh_.area(element(n)) * exposure_.fraction(n);
        change += a * channelSum(glm::abs(delta));
        norm += a * channelSum(gathered[nd] + emittersReflected_[nd]);
    }
    return norm > 0.0 ? change / norm : 0.0;
}

// The emitting patch sides for next-event estimation, weighted by their exposed flux.
void FinalGather::tableEmitters() {
    emitterNodes_.clear();
    emitterEntry_.assign(2 * mesh_.patchCount(), -1);
    std::vector<float> weights;
    for (size_t p = 0; p < mesh_.patchCount(); ++p) {
        for (const bool side : {true, false}) {
            const int n = node(static_cast<int>(p), side);
            const float flux = luminance(radiance_.emission(n)) * mesh_.area(static_cast<int>(p)) *
                               exposure_.fraction(n);
            if (!(flux > 0.0f))
                continue;
            emitterEntry_[static_cast<size_t>(n)] = static_cast<int>(emitterNodes_.size());
            emitterNodes_.push_back(n);
            weights.push_back(flux);
        }
    }
    emitterTable_ = weights.empty() ? AliasTable() : AliasTable(weights);
}

// The solid-angle density, seen from x, with which next-event estimation draws the point z of
// the table's entry (its side's normal nz).
float FinalGather::emitterPdf(int entry, const Vec3& x, const Vec3& z, const Vec3& nz) const {
    const Vec3 d = x - z;
    const float r2 = glm::dot(d, d);
    const float cosine = glm::dot(nz, d) / std::sqrt(r2);
    if (!(cosine > 0.0f))
        return 0.0f;
    const int patch = element(emitterNodes_[static_cast<size_t>(entry)]);
    return emitterTable_.pmf(static_cast<uint32_t>(entry)) * r2 / (mesh_.area(patch) * cosine);
}

// The emission a gather ray in direction w meets at y, weighted against the next-event
// estimate of the same light (G_e above).
Color FinalGather::emissionSeen(const ElementSample& x, const Vec3& normal, const Vec3& w,
                                const MeshedHit& y) const {
    if (emitterNodes_.empty())
        return Color(0.0f);
    const auto [e, side] =
        leafSideSeenAt(scene_, mesh_, exposure_.coincident(), y.point.element, y.front, y.hit.p);
    const int n = node(mesh_.patch(e), side);
    const int entry = emitterEntry_[static_cast<size_t>(n)];
    if (entry < 0)
        return Color(0.0f);
    const Vec3 nz = side ? mesh_.normal(e) : -mesh_.normal(e);
    const float lightPdf = emitterPdf(entry, x.p, y.hit.p, nz);
    return y.transmittance * radiance_.emission(n) *
           powerHeuristic(glm::dot(normal, w) * kInvPi, lightPdf);
}

// The irradiance divided by pi (cd/m²) that the emitters give x on the side of `normal`, one
// next-event sample weighted against the gather ray's (G_e above).
Color FinalGather::emittersIrradiance(const ElementSample& x, const Vec3& normal, Sampler& sampler,
                                      uint64_t& rays) const {
    const float uEntry = sampler.get1D();
    const Vec2 uPoint = sampler.get2D();
    if (emitterTable_.empty())
        return Color(0.0f);
    const auto entry = static_cast<int>(emitterTable_.sample(uEntry));
    const int n = emitterNodes_[static_cast<size_t>(entry)];
    const int patch = element(n);
    const ElementSample z = sampleElement(scene_, mesh_, patch, uPoint);
    const Vec3 nz = front(n) ? z.n : -z.n;
    const Vec3 d = z.p - x.p;
    const float r = glm::length(d);
    const float cosine = glm::dot(normal, d) / r;
    const float lightPdf = emitterPdf(entry, x.p, z.p, nz);
    if (!(cosine > 0.0f) || !(lightPdf > 0.0f))
        return Color(0.0f);
    if (exposure_.partlyCovered(n) && exposure_.covered(patch, z, nz, rays))
        return Color(0.0f);
    ++rays;
    Color T = scene_.surfaceTransmittance(x.p, x.pError, normal, z.p, z.pError, nz);
    if (maxComponent(T) > 0.0f)
        T *= scene_.mediumTransmittance(x.p, z.p);
    return T * radiance_.emission(n) *
           (cosine / (kPi * lightPdf) * powerHeuristic(lightPdf, cosine * kInvPi));
}

// G of pass() for every exposed side of `leaves` that reflects, per node; -1 elsewhere. With
// `withEmitters`, G_e too (emittersReflected_).
std::vector<Color> FinalGather::gatherIndirect(const std::vector<int>& leaves, bool withEmitters,
                                               SolveProgress* progress) {
    const auto n = static_cast<uint32_t>(raysPerSide_);
    std::vector<Color> gathered(radiance_.nodeCount(), Color(-1.0f));
    if (withEmitters)
        emittersReflected_.assign(radiance_.nodeCount(), Color(0.0f));
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
            Color sum(0.0f), emitted(0.0f);
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
                if (y) {
                    sum += y->transmittance * gathered_.seen(*y, sampler, count);
                    if (withEmitters)
                        emitted += emissionSeen(x, normal, w, *y);
                }
                if (withEmitters)
                    emitted += emittersIrradiance(x, normal, sampler, count);
            }
            if (used > 0) {
                gathered[static_cast<size_t>(nd)] = rho * sum / static_cast<float>(used);
                if (withEmitters)
                    emittersReflected_[static_cast<size_t>(nd)] =
                        rho * emitted / static_cast<float>(used);
            }
        }
    });
    rays_ += rays.combine(std::plus<uint64_t>());
    return gathered;
}

}  // namespace penumbra
