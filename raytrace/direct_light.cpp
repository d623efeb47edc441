#include "raytrace/direct_light.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "core/surface_crossing.h"
#include "raytrace/path_tracer.h"

namespace penumbra {

Color sampleDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                        Sampler& sampler, PathCounters& counters, ReflectingLobes lobes) {
    const float uLight = sampler.get1D();
    const Vec2 uPoint = sampler.get2D();
    const auto choice = scene.lightSampler().sample(uLight);
    if (!choice)
        return Color(0.0f);
    const Light& light = *scene.lights()[choice->light];
    const LightSampleContext ctx{hit.p, hit.pError, hit.ng};
    const std::optional<LightLiSample> ls = light.sampleLi(ctx, uPoint);
    if (!ls || !(ls->pdf > 0.0f))
        return Color(0.0f);

    const Color f = bsdf.f(wo, ls->wi, lobes) * std::abs(glm::dot(ls->wi, bsdf.shadingNormal()));
    if (maxComponent(f) <= 0.0f)
        return Color(0.0f);
    ++counters.rays;
    const Color Tr =
        scene.transmittance(hit.p, hit.pError, hit.ng, ls->pLight, ls->pLightError, ls->nLight);
    if (maxComponent(Tr) <= 0.0f)
        return Color(0.0f);

    const float lightPdf = choice->pmf * ls->pdf;
    const float weight = light.isDelta() ? 1.0f : powerHeuristic(lightPdf, bsdf.pdf(wo, ls->wi));
    return f * ls->L * Tr * (weight / lightPdf);
}

float emissionMisWeight(const Scene& scene, const LightSampleContext& ctx, const Vec3& wi,
                        const SurfaceHit& lightHit, float bsdfPdf) {
    const int lightIndex = scene.lightIndex(lightHit);
    if (lightIndex < 0)
        return 1.0f;
    const float lightPdf =
        scene.lightSampler().pmf(lightIndex) * scene.lights()[lightIndex]->pdfLi(ctx, wi, lightHit);
    return powerHeuristic(bsdfPdf, lightPdf);
}

Color estimateDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                          const Vec3& wo, Sampler& sampler, PathCounters& counters) {
    const Color fromLight = sampleDirectLight(scene, hit, bsdf, wo, sampler, counters);
    const float uLobe = sampler.get1D();
    const Vec2 uDirection = sampler.get2D();
    const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, uDirection);
    // A delta lobe is the caller's to follow (the specular chain).
    if (!bs || bs->isDelta() || !(bs->pdf > 0.0f))
        return fromLight;
    Color beta = bs->f * (std::abs(glm::dot(bs->wi, bsdf.shadingNormal())) / bs->pdf);
    const LightSampleContext ctx{hit.p, hit.pError, hit.ng};
    Ray ray = Scene::spawnRay(hit, bs->wi);
    // Straight-through transparency passes the ray on, as for the light sample's shadow ray.
    while (maxComponent(beta) > 0.0f) {
        ++counters.rays;
        const std::optional<SurfaceHit> next = scene.intersect(ray);
        if (!next)
            break;
        beta *= volumeAttenuation(scene, *next, ray.d);
        const Bsdf nextBsdf = scene.bsdf(*next);
        const StraightThrough straight =
            chooseStraightThrough(scene, *next, nextBsdf, -ray.d, sampler);
        beta *= straight.weight;
        if (straight.passes) {
            ray = Scene::spawnRay(*next, ray.d);
            continue;
        }
        const Color Le = scene.emitted(*next, -ray.d);
        if (scene.lightIndex(*next) < 0 || maxComponent(Le) <= 0.0f)
            break;
        return fromLight + beta * Le * emissionMisWeight(scene, ctx, bs->wi, *next, bs->pdf);
    }
    return fromLight;
}

}  // namespace penumbra
