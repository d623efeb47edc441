#include "raytrace/direct_light.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "raytrace/path_tracer.h"

namespace penumbra {

Color sampleDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                        Sampler& sampler, PathCounters& counters, DirectLightWeight weighting) {
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

    const Color f = bsdf.f(wo, ls->wi) * std::abs(glm::dot(ls->wi, bsdf.shadingNormal()));
    if (maxComponent(f) <= 0.0f)
        return Color(0.0f);
    ++counters.rays;
    const Color Tr =
        scene.transmittance(hit.p, hit.pError, hit.ng, ls->pLight, ls->pLightError, ls->nLight);
    if (maxComponent(Tr) <= 0.0f)
        return Color(0.0f);

    const float lightPdf = choice->pmf * ls->pdf;
    const float weight = light.isDelta() || weighting == DirectLightWeight::LightOnly
                             ? 1.0f
                             : powerHeuristic(lightPdf, bsdf.pdf(wo, ls->wi));
    return f * ls->L * Tr * (weight / lightPdf);
}

}  // namespace penumbra
