#include "raytrace/direct_light.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "core/surface_crossing.h"
#include "raytrace/path_tracer.h"

namespace penumbra {

namespace {

// The arriving radiance of light sample `ls` at `hit` over its density lightPdf (the light's
// probability of being drawn times ls->pdf), with a shadow ray, weighted by the power heuristic
// against bsdf.pdf() (Veach 1997, Eq. 9.13; 1 for a delta light); nothing when no light arrives
// or `reflects(wi)` says the caller's lobes send none of it back, checked before the shadow ray
// is cast.
template <typename Reflects>
std::optional<Color> incidentLight(const Scene& scene, const std::optional<LightLiSample>& ls,
                                   float lightPdf, bool delta, const SurfaceHit& hit,
                                   const Bsdf& bsdf, const Vec3& wo, PathCounters& counters,
                                   const Reflects& reflects) {
    if (!ls || !(ls->pdf > 0.0f) || !(lightPdf > 0.0f) || !reflects(ls->wi))
        return std::nullopt;
    ++counters.rays;
    const Color Tr =
        scene.transmittance(hit.p, hit.pError, hit.ng, ls->pLight, ls->pLightError, ls->nLight);
    if (maxComponent(Tr) <= 0.0f)
        return std::nullopt;
    const float weight = delta ? 1.0f : powerHeuristic(lightPdf, bsdf.pdf(wo, ls->wi));
    return ls->L * Tr * (weight / lightPdf);
}

// One light sample for next-event estimation at `hit`: a light chosen by power from `lights`, a
// point on it and incidentLight(). Returns the light and what incidentLight() returns.
struct IncidentLight {
    uint32_t light;
    Color L;
};
template <typename Reflects>
std::optional<IncidentLight> sampleIncidentLight(const Scene& scene,
                                                 const PowerLightSampler& lights,
                                                 const SurfaceHit& hit, const Bsdf& bsdf,
                                                 const Vec3& wo, Sampler& sampler,
                                                 PathCounters& counters, const Reflects& reflects) {
    const float uLight = sampler.get1D();
    const Vec2 uPoint = sampler.get2D();
    const auto choice = lights.sample(uLight);
    if (!choice)
        return std::nullopt;
    const Light& light = *scene.lights()[choice->light];
    const std::optional<LightLiSample> ls =
        light.sampleLi(LightSampleContext{hit.p, hit.pError, hit.ng}, uPoint);
    const std::optional<Color> L =
        incidentLight(scene, ls, choice->pmf * (ls ? ls->pdf : 0.0f), light.isDelta(), hit, bsdf,
                      wo, counters, reflects);
    if (!L)
        return std::nullopt;
    return IncidentLight{choice->light, *L};
}

// The predicate incidentLight() asks, for the lobes `lobes`: sets f to their BSDF times the cosine
// towards wi.
struct LobesReflect {
    const Bsdf& bsdf;
    const Vec3& wo;
    Color& f;
    ReflectingLobes lobes = ReflectingLobes::All;
    bool operator()(const Vec3& wi) const {
        f = bsdf.f(wo, wi, lobes) * std::abs(glm::dot(wi, bsdf.shadingNormal()));
        return maxComponent(f) > 0.0f;
    }
};

// The probability with which next-event estimation draws `light`: from its set of `selection`,
// or without one from the scene's lights.
float selectionPmf(const Scene& scene, uint32_t light, const LightSelection* selection) {
    return selection ? selection->pmf(light) : scene.lightSampler().pmf(light);
}

}  // namespace

Color sampleDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                        Sampler& sampler, PathCounters& counters, ReflectingLobes lobes) {
    Color f(0.0f);
    const auto incident = sampleIncidentLight(scene, scene.lightSampler(), hit, bsdf, wo, sampler,
                                              counters, LobesReflect{bsdf, wo, f, lobes});
    return incident ? f * incident->L : Color(0.0f);
}

Color sampleDirectLightFromSet(const Scene& scene, const LightSelection& selection, size_t set,
                               const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                               Sampler& sampler, PathCounters& counters, uint32_t& light) {
    Color f(0.0f);
    const auto incident = sampleIncidentLight(scene, selection.set(set), hit, bsdf, wo, sampler,
                                              counters, LobesReflect{bsdf, wo, f});
    if (!incident)
        return Color(0.0f);
    light = incident->light;
    return f * incident->L;
}

Color sampleEnvironmentPart(const Scene& scene, EnvironmentPart part, const SurfaceHit& hit,
                            const Bsdf& bsdf, const Vec3& wo, Sampler& sampler,
                            PathCounters& counters) {
    const Vec2 u = sampler.get2D();
    const EnvironmentLight* environment = scene.environment();
    if (!environment)
        return Color(0.0f);
    const std::optional<LightLiSample> ls =
        environment->sampleLi(LightSampleContext{hit.p, hit.pError, hit.ng}, u, part);
    Color f(0.0f);
    const std::optional<Color> L = incidentLight(scene, ls, ls ? ls->pdf : 0.0f, false, hit, bsdf,
                                                 wo, counters, LobesReflect{bsdf, wo, f});
    return L ? f * *L : Color(0.0f);
}

float environmentPartMisWeight(const Scene& scene, EnvironmentPart part, const Vec3& from,
                               const Vec3& wi, float bsdfPdf) {
    const EnvironmentLight* environment = scene.environment();
    return environment ? powerHeuristic(bsdfPdf, environment->pdfDirection(from, wi, part)) : 1.0f;
}

DirectLightShares sampleDirectLightShares(const Scene& scene, const SurfaceHit& hit,
                                          const Bsdf& bsdf, const Vec3& wo, Sampler& sampler,
                                          PathCounters& counters) {
    Color f(0.0f), fGlossy(0.0f);
    const auto reflects = [&](const Vec3& wi) {
        const float cosine = std::abs(glm::dot(wi, bsdf.shadingNormal()));
        f = bsdf.f(wo, wi) * cosine;
        fGlossy = bsdf.fGlossy(wo, wi) * cosine;
        return maxComponent(f) > 0.0f;
    };
    const auto incident = sampleIncidentLight(scene, scene.lightSampler(), hit, bsdf, wo, sampler,
                                              counters, reflects);
    if (!incident)
        return {};
    return {f * incident->L, fGlossy * incident->L};
}

float emissionMisWeight(const Scene& scene, const LightSampleContext& ctx, const Vec3& wi,
                        const SurfaceHit& lightHit, float bsdfPdf,
                        const LightSelection* selection) {
    const int lightIndex = scene.lightIndex(lightHit);
    if (lightIndex < 0)
        return 1.0f;
    const float lightPdf = selectionPmf(scene, uint32_t(lightIndex), selection) *
                           scene.lights()[lightIndex]->pdfLi(ctx, wi, lightHit);
    return powerHeuristic(bsdfPdf, lightPdf);
}

float escapedMisWeight(const Scene& scene, const Vec3& from, const Vec3& wi, float bsdfPdf) {
    const EnvironmentLight* environment = scene.environment();
    if (!environment)
        return 1.0f;
    const float lightPdf = scene.lightSampler().pmf(uint32_t(scene.environmentLightIndex())) *
                           environment->pdfDirection(from, wi);
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
        if (!next) {
            return fromLight +
                   beta * scene.escaped(ray.d) * escapedMisWeight(scene, hit.p, bs->wi, bs->pdf);
        }
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
