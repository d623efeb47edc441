#include "raytrace/distribution_tracer.h"

#include "core/sampler.h"
#include "radiosity/radiosity_solution.h"
#include "raytrace/direct_light.h"
#include "raytrace/tracing_steps.h"

namespace penumbra {

std::string distributionLightPaths() {
    return "L S* E | L D S* E | L D D+ S* E";
}

DistributionTracer::DistributionTracer(const Scene& scene, const DistributionSettings& settings,
                                       const RadiositySolution* indirect)
    : scene_(scene), settings_(settings), indirect_(indirect) {}

Color DistributionTracer::Li(Ray ray, Sampler& sampler, FirstHit* firstHit,
                             PathCounters& counters) const {
    Color L(0.0f);
    Color beta(1.0f);
    const Vec3 cameraOrigin = ray.o;
    int specularDepth = 0;
    while (true) {
        ++counters.rays;
        const std::optional<SurfaceHit> hit = scene_.intersect(ray);
        if (!hit)
            break;
        beta *= volumeAttenuation(scene_, *hit, ray.d);
        const Vec3 wo = -ray.d;
        // Seen from the eye or through specular vertices only: nothing else reaches it.
        L += beta * scene_.emitted(*hit, wo);

        const Bsdf bsdf = scene_.bsdf(*hit);
        const StraightThrough straight = chooseStraightThrough(scene_, *hit, bsdf, wo, sampler);
        beta *= straight.weight;
        if (straight.passes) {
            ray = Scene::spawnRay(*hit, ray.d);
            continue;
        }
        recordFirstHit(scene_, *hit, bsdf, cameraOrigin, firstHit);

        if (bsdf.hasNonDeltaLobe()) {
            // No BSDF sample of a non-delta lobe is traced, so the light sample stands alone.
            L += beta * sampleDirectLight(scene_, *hit, bsdf, wo, sampler, counters,
                                          DirectLightWeight::LightOnly);
            if (indirect_) {
                L += beta * indirect_->indirectRadiance(hit->mesh, hit->triangle, hit->barycentric,
                                                        glm::dot(wo, hit->ng) > 0.0f);
            }
        }
        if (specularDepth >= settings_.maxSpecularDepth)
            break;
        const float uLobe = sampler.get1D();
        const Vec2 uDirection = sampler.get2D();
        const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, uDirection);
        // A non-delta lobe chosen: its share is the two terms above.
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
