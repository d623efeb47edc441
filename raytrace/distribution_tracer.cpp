#include "raytrace/distribution_tracer.h"

#include "core/sampler.h"
#include "raytrace/direct_light.h"
#include "raytrace/specular_chain.h"

namespace penumbra {

std::string distributionLightPaths(bool causticsInRadiosity, bool specularTransfer) {
    // The ambient term is the solution's indirect part: what it holds, less the first
    // reflection of the sources, i.e. its paths with two D vertices or more.
    const std::string start = causticsInRadiosity ? "L S* D" : "L D";
    return "L S* E | L D S* E | " + start + (specularTransfer ? " (S* D)+" : " D+") + " S* E";
}

DistributionTracer::DistributionTracer(const Scene& scene, const DistributionSettings& settings,
                                       const ReusedSolution* indirect)
    : scene_(scene), settings_(settings), indirect_(indirect) {}

Color DistributionTracer::glossyIndirect(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                                         Sampler& sampler, PathCounters& counters) const {
    const float uLobe = sampler.get1D();
    const Vec2 u = sampler.get2D();
    const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, u);
    if (!bs || bs->isDelta() || !(bs->pdf > 0.0f))
        return Color(0.0f);
    // fGlossy over the mixture's pdf: an unbiased estimate of the glossy lobes' integral,
    // whichever of the BSDF's strategies drew the direction.
    const Color f = bsdf.fGlossy(wo, bs->wi);
    if (!(maxComponent(f) > 0.0f))
        return Color(0.0f);
    // Through mirrors and glass to the next diffuse surface, as from the eye: a polished floor
    // shows what lies behind a glass balustrade. Emission is left out: what the sample meets
    // first, estimateDirectLight's BSDF sample counts; behind a specular vertex (L S+ D E), the
    // caustic pass.
    const SpecularChainSettings chain{.maxSpecularDepth = settings_.maxSpecularDepth,
                                      .countEmission = false};
    const PathRadiance Lnext = traceSpecularChain(
        scene_, Scene::spawnRay(hit, bs->wi), sampler, nullptr, counters, chain,
        [this](const SurfaceHit& next, const Bsdf&, const Vec3& nextWo, Sampler&, PathCounters&) {
            PathRadiance reflected;
            reflected[PathComponent::Indirect] =
                indirect_->reflected(next, glm::dot(nextWo, next.ng) > 0.0f);
            return reflected;
        });
    return f * Lnext.total() * (std::abs(glm::dot(bs->wi, bsdf.shadingNormal())) / bs->pdf);
}

PathRadiance DistributionTracer::Li(Ray ray, Sampler& sampler, FirstHit* firstHit,
                                    PathCounters& counters) const {
    const bool linearFog =
        settings_.mediumPreview == DistributionSettings::MediumPreview::LinearFog;
    const SpecularChainSettings chain{
        .maxSpecularDepth = settings_.maxSpecularDepth,
        .countEmission = true,
        .mediumSteps = settings_.mediumSteps,
        .linearFogAmbient = linearFog ? std::optional(settings_.ambient) : std::nullopt};
    return traceSpecularChain(
        scene_, ray, sampler, firstHit, counters, chain,
        [this](const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo, Sampler& vertexSampler,
               PathCounters& vertexCounters) {
            PathRadiance L;
            L[PathComponent::Direct] =
                estimateDirectLight(scene_, hit, bsdf, wo, vertexSampler, vertexCounters);
            if (indirect_) {
                L[PathComponent::Indirect] += matteShare(bsdf, wo, *indirect_) *
                                              indirect_->indirect(hit, glm::dot(wo, hit.ng) > 0.0f);
                if (bsdf.lobes() & kLobeGlossy) {
                    L[PathComponent::Indirect] +=
                        glossyIndirect(hit, bsdf, wo, vertexSampler, vertexCounters);
                }
            }
            if (maxComponent(settings_.ambient) > 0.0f)
                L[PathComponent::Indirect] += bsdf.diffuseGlossyReflectance() * settings_.ambient;
            return L;
        });
}

}  // namespace penumbra
