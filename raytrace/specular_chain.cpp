#include "raytrace/specular_chain.h"

#include "core/sampler.h"
#include "core/surface_crossing.h"
#include "raytrace/linear_fog.h"
#include "raytrace/single_scattering.h"
#include "raytrace/tracing_steps.h"

namespace penumbra {

PathRadiance traceSpecularChain(const Scene& scene, Ray ray, Sampler& sampler, FirstHit* firstHit,
                                PathCounters& counters, const SpecularChainSettings& settings,
                                const DiffuseVertexTerm& atDiffuseVertex) {
    PathRadiance L;
    Color beta(1.0f);
    const Vec3 cameraOrigin = ray.o;
    int specularDepth = 0;
    const Medium* medium = settings.mediumSteps > 0 ? scene.medium() : nullptr;
    while (true) {
        ++counters.rays;
        const std::optional<SurfaceHit> hit = scene.intersect(ray);
        // The medium along the segment: its single scattering and emission, then its
        // transmittance on what lies behind.
        const std::optional<Medium::Span> span = medium && !(hit && insideSolid(scene, *hit, ray.d))
                                                     ? medium->span(ray, hit ? hit->t : INFINITY)
                                                     : std::nullopt;
        if (span && settings.linearFogAmbient) {
            const LinearFog fog = linearFog(*medium, ray, *span, *settings.linearFogAmbient);
            L[specularDepth == 0 ? PathComponent::Indirect : PathComponent::Specular] +=
                beta * fog.radiance;
            beta *= fog.transmittance;
        } else if (span) {
            L[pathComponent(specularDepth + 1, specularDepth > 0)] +=
                beta * marchSingleScattering(scene, *medium, ray, *span, settings.mediumSteps,
                                             sampler, counters);
            if (settings.countEmission)
                L[pathComponent(specularDepth, true)] += beta * medium->emitted(ray, *span);
            beta *= medium->transmittance(ray, span->t0, span->t1);
        }
        if (!hit) {
            // The environment, seen directly or through the delta vertices.
            if (settings.countEmission)
                L[pathComponent(specularDepth, true)] += beta * scene.escaped(ray.d);
            break;
        }
        beta *= volumeAttenuation(scene, *hit, ray.d);
        const Vec3 wo = -ray.d;
        if (settings.countEmission)
            L[pathComponent(specularDepth, true)] += beta * scene.emitted(*hit, wo);

        const Bsdf bsdf = scene.bsdf(*hit);
        const StraightThrough straight = chooseStraightThrough(scene, *hit, bsdf, wo, sampler);
        beta *= straight.weight;
        if (straight.passes) {
            ray = Scene::spawnRay(*hit, ray.d);
            continue;
        }
        recordFirstHit(scene, *hit, bsdf, cameraOrigin, firstHit);

        if (bsdf.hasNonDeltaLobe()) {
            PathRadiance term = atDiffuseVertex(*hit, bsdf, wo, sampler, counters);
            term *= beta;
            for (size_t c = 0; c < kPathComponentCount; ++c) {
                const PathComponent seen =
                    specularDepth == 0 ? PathComponent(c) : PathComponent::Specular;
                L[seen] += term.components[c];
            }
        }
        if (specularDepth >= settings.maxSpecularDepth)
            break;
        const float uLobe = sampler.get1D();
        const Vec2 uDirection = sampler.get2D();
        const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, uDirection);
        if (!bs || !bs->isDelta() || !(bs->pdf > 0.0f))
            break;
        beta *= bs->f * (std::abs(glm::dot(bs->wi, bsdf.shadingNormal())) / bs->pdf);
        if (maxComponent(beta) <= 0.0f)
            break;
        ray = Scene::spawnRay(*hit, bs->wi);
        ++specularDepth;
    }
    return L;
}

}  // namespace penumbra
