#include "raytrace/path_tracer.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "raytrace/direct_light.h"
#include "raytrace/tracing_steps.h"

namespace penumbra {

namespace {

// Paths always have at least this probability of ending at each roulette test, so that a
// path cannot run forever even in a closed box of perfect mirrors; the survivors are
// reweighted by 1 / (1 - q), which keeps the estimator unbiased. It must stay below 1 - rho^2:
// where the throughput stays near 1 (albedo rho), the weights grow as (rho / (1 - q))^k while
// paths survive with (1 - q)^k, so the variance sum of (rho^2 / (1 - q))^k diverges otherwise
// (0.05 gave a 0.99 furnace infinite variance: 89 +- 22 for 100, tests/cli/stress_test.cpp).
constexpr float kMinTerminationProbability = 1e-3f;
// Roulette starts after this many scattering events (the first bounces carry most variance).
constexpr int kRouletteStartDepth = 3;

}  // namespace

float rouletteTerminationProbability(int depth, const Color& beta) {
    if (depth < kRouletteStartDepth)
        return 0.0f;
    return glm::max(kMinTerminationProbability, 1.0f - maxComponent(beta));
}

std::string pathTracerLightPaths(const PathTracerSettings& settings) {
    // Without reuse: every path, less the caustic ones (paths with no D: L S* E; one D with no S
    // before it: L D S* E; two or more D: L (D|S)* D S* D S* E). With reuse: what the first
    // diffuse vertex's next-event estimation and BSDF samples find, and at the second diffuse
    // vertex, seen through specular chains, the light arriving there: the radiosity solution's
    // L D+, the light of specular chains from the lights (L S+ D: the caustic map's, or found by
    // tracing), and the same again at the diffuse vertex behind each specular chain the reuse
    // vertex sees ((S+ D)*). With no specular surface in the scene the last two are empty. A
    // solution that took the caustic photons holds L S+ D+ as well: L S* D+ arrives.
    if (!settings.reuseRadiosity)
        return settings.excludeCaustics ? "L S* E | L D S* E | L (D|S)* D S* D S* E" : "L(D|S)*E";
    return std::string(settings.excludeCaustics ? "L S* E | L D S* E | "
                                                : "L S* E | L S* D S* E | ") +
           (settings.causticsInRadiosity ? "L S* D+" : "(L D+ | L S+ D)") + " (S+ D)* S* D S* E";
}

PathTracer::PathTracer(const Scene& scene, const PathTracerSettings& settings,
                       const ReusedSolution* radiosity, const ReusedCaustics* causticMap)
    : scene_(scene), settings_(settings), radiosity_(radiosity), causticMap_(causticMap) {}

PathRadiance PathTracer::Li(Ray ray, Sampler& sampler, FirstHit* firstHit,
                            PathCounters& counters) const {
    PathRadiance L;
    Color beta(1.0f);
    // The part of beta whose light no radiosity solution holds yet: all of it, but right after a
    // reuse vertex left through a non-delta lobe, where the solution holds what that vertex's
    // Lambertian layer gathers and only its glossy lobes' share goes on (see below). Emission,
    // next-event estimation, the reuse terms and non-delta bounces take this part; a delta bounce
    // carries all of beta, as the solution holds no light that arrives through specular surfaces.
    Color betaUnheld(1.0f);
    // Product of eta^2 over refractions: beta carries the 1/eta^2 radiance scaling of each
    // refraction, which this factor undoes for the roulette decision only (pbrt-v4, 14.1.3).
    float etaScale = 1.0f;
    int depth = 0;
    const Vec3 cameraOrigin = ray.o;
    bool lastDelta = true;  // the camera counts as a delta vertex for emission
    float lastBsdfPdf = 0.0f;
    LightSampleContext lastCtx;
    // Vertices left through a non-delta lobe so far, and whether a specular vertex followed the
    // last of them: the path classes of the header's comment.
    int diffuseVertices = 0;
    bool specularAfterDiffuse = false;
    bool firstVertexSpecular = false;  // the lobe the first vertex was left through was a delta

    while (true) {
        ++counters.rays;
        const std::optional<SurfaceHit> hit = scene_.intersect(ray);
        if (!hit)
            break;  // no infinite lights yet: the world is black
        const Color attenuation = volumeAttenuation(scene_, *hit, ray.d);
        beta *= attenuation;
        betaUnheld *= attenuation;
        const Vec3 wo = -ray.d;
        const bool unheld = maxComponent(betaUnheld) > 0.0f;

        // Emission reached by the previous BSDF sample, MIS-weighted against next-event
        // estimation at the previous vertex (Veach 1997, Eq. 9.13).
        const Color Le = scene_.emitted(*hit, wo);
        const bool causticPath = diffuseVertices == 1 && specularAfterDiffuse;
        // Light reaching a reuse vertex (every diffuse vertex after the first) through specular
        // vertices is the caustic map's, when the reuse vertex took it.
        const bool causticAtReuse = diffuseVertices >= 2 && specularAfterDiffuse &&
                                    settings_.causticsAtReuse && causticMap_;
        if (maxComponent(Le) > 0.0f && unheld && !(causticPath && settings_.excludeCaustics) &&
            !causticAtReuse) {
            const float weight =
                lastDelta ? 1.0f : emissionMisWeight(scene_, lastCtx, ray.d, *hit, lastBsdfPdf);
            L[pathComponent(depth, firstVertexSpecular)] += betaUnheld * Le * weight;
        }

        const Bsdf bsdf = scene_.bsdf(*hit);

        // Straight-through transparency: depth and the MIS state stay as they were.
        const StraightThrough straight = chooseStraightThrough(scene_, *hit, bsdf, wo, sampler);
        beta *= straight.weight;
        betaUnheld *= straight.weight;
        if (straight.passes) {
            ray = Scene::spawnRay(*hit, ray.d);
            continue;
        }
        recordFirstHit(scene_, *hit, bsdf, cameraOrigin, firstHit);

        if (settings_.maxDepth >= 0 && depth >= settings_.maxDepth)
            break;

        // A second diffuse vertex under radiosity reuse. The solution reflects what arrives here
        // from the lights and diffuse surfaces with the whole non-delta reflectance, the rough
        // glossy lobes spread as Lambertian: the Lambertian layer's share of it stands for
        // everything that layer would gather (matteShare), and the glossy lobes go on as at any
        // vertex, with next-event estimation and a bounce weighed by fGlossy alone. Every
        // direction of a non-delta bounce here is drawn from the whole BSDF, so f / pdf splits
        // exactly into the Lambertian part, which only delta lobes carry on (light through
        // specular surfaces), and the glossy part, which goes on in full (betaUnheld).
        const bool reuseHere =
            settings_.reuseRadiosity && diffuseVertices >= 1 && bsdf.hasNonDeltaLobe();
        // Light reflected here reaches the eye over this vertex and the ones before it.
        const PathComponent reflectedHere = pathComponent(depth + 1, firstVertexSpecular);
        if (unheld && reuseHere && radiosity_) {
            L[reflectedHere] += betaUnheld * matteShare(bsdf) *
                                radiosity_->reflected(*hit, glm::dot(wo, hit->ng) > 0.0f);
        }
        if (unheld && reuseHere && settings_.causticsAtReuse && causticMap_) {
            L[reflectedHere] += betaUnheld * causticMap_->radiance(*hit, bsdf, wo,
                                                                   settings_.causticsInRadiosity
                                                                       ? ReflectingLobes::Glossy
                                                                       : ReflectingLobes::All);
        }
        const bool glossyAtReuse = reuseHere && (bsdf.lobes() & kLobeGlossy) != 0;
        if (unheld && bsdf.hasNonDeltaLobe() && (!reuseHere || glossyAtReuse)) {
            L[reflectedHere] +=
                betaUnheld *
                sampleDirectLight(scene_, *hit, bsdf, wo, sampler, counters,
                                  reuseHere ? ReflectingLobes::Glossy : ReflectingLobes::All);
        }

        const float uLobe = sampler.get1D();
        const Vec2 uDirection = sampler.get2D();
        const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, uDirection);
        if (!bs || !(bs->pdf > 0.0f))
            break;
        const float cosOverPdf = std::abs(glm::dot(bs->wi, bsdf.shadingNormal())) / bs->pdf;
        if (bs->isDelta()) {
            beta *= bs->f * cosOverPdf;
            betaUnheld = beta;
        } else {
            // Only the unheld part goes on through a non-delta lobe: the solution at the reuse
            // vertex before this one holds the rest.
            const Color base = betaUnheld;
            beta = base * bs->f * cosOverPdf;
            betaUnheld = reuseHere ? base * bsdf.fGlossy(wo, bs->wi) * cosOverPdf : beta;
            if (reuseHere && !settings_.specularAtReuse && !(maxComponent(betaUnheld) > 0.0f))
                break;  // the radiosity term above holds this bounce, and no surface is specular
        }
        if (depth == 0)
            firstVertexSpecular = bs->isDelta();
        if (bs->isDelta()) {
            specularAfterDiffuse = diffuseVertices > 0;
        } else {
            ++diffuseVertices;
            specularAfterDiffuse = false;
        }
        if (maxComponent(beta) <= 0.0f)
            break;
        if (bs->lobe & kLobeTransmission)
            etaScale *= sqr(bs->eta);
        lastDelta = bs->isDelta();
        lastBsdfPdf = bs->pdf;
        lastCtx = LightSampleContext{hit->p, hit->pError, hit->ng};
        ray = Scene::spawnRay(*hit, bs->wi);
        ++depth;

        // Russian roulette, on the throughput without eta scaling.
        const float q = rouletteTerminationProbability(depth, beta * etaScale);
        if (q > 0.0f) {
            if (sampler.get1D() < q)
                break;
            beta /= 1.0f - q;
            betaUnheld /= 1.0f - q;
        }
    }
    return L;
}

}  // namespace penumbra
