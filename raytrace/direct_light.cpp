#include "raytrace/direct_light.h"

#include "core/medium.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/surface_crossing.h"
#include "raytrace/path_tracer.h"

namespace penumbra {

namespace {

// The arriving radiance of light sample `ls` at the point of `ctx` over its density lightPdf (the
// light's probability of being drawn times ls->pdf), with a shadow ray, weighted by the power
// heuristic against scatterPdf(wi), the density of the tracer's own sample there (a BSDF's or a
// phase function's: Veach 1997, Eq. 9.13; 1 for a delta light); nothing when no light arrives
// or `reflects(wi)` says the caller's lobes send none of it back, checked before the shadow ray
// is cast.
template <typename ScatterPdf, typename Reflects>
std::optional<Color> incidentLight(const Scene& scene, const std::optional<LightLiSample>& ls,
                                   float lightPdf, bool delta, const LightSampleContext& ctx,
                                   const ScatterPdf& scatterPdf, PathCounters& counters,
                                   const Reflects& reflects) {
    if (!ls || !(ls->pdf > 0.0f) || !(lightPdf > 0.0f) || !reflects(ls->wi))
        return std::nullopt;
    ++counters.rays;
    const Color Tr =
        scene.transmittance(ctx.p, ctx.pError, ctx.n, ls->pLight, ls->pLightError, ls->nLight);
    if (maxComponent(Tr) <= 0.0f)
        return std::nullopt;
    const float weight = delta ? 1.0f : powerHeuristic(lightPdf, scatterPdf(ls->wi));
    return ls->L * Tr * (weight / lightPdf);
}

// One light sample for next-event estimation at the point of `ctx`: a light chosen by power
// from `lights`, a point on it and incidentLight(). Returns the light and what incidentLight()
// returns.
struct IncidentLight {
    uint32_t light;
    Color L;
    Vec3 pLight;  // the point sampled on the light
};
template <typename ScatterPdf, typename Reflects>
std::optional<IncidentLight> sampleIncidentLight(const Scene& scene,
                                                 const PowerLightSampler& lights,
                                                 const LightSampleContext& ctx,
                                                 const ScatterPdf& scatterPdf, Sampler& sampler,
                                                 PathCounters& counters, const Reflects& reflects) {
    const float uLight = sampler.get1D();
    const Vec2 uPoint = sampler.get2D();
    const auto choice = lights.sample(uLight);
    if (!choice)
        return std::nullopt;
    const Light& light = *scene.lights()[choice->light];
    const std::optional<LightLiSample> ls = light.sampleLi(ctx, uPoint);
    const std::optional<Color> L =
        incidentLight(scene, ls, choice->pmf * (ls ? ls->pdf : 0.0f), light.isDelta(), ctx,
                      scatterPdf, counters, reflects);
    if (!L)
        return std::nullopt;
    return IncidentLight{choice->light, *L, ls->pLight};
}

// Where a surface's next-event estimate is taken, and its BSDF's density there.
LightSampleContext surfaceContext(const SurfaceHit& hit) {
    return LightSampleContext{hit.p, hit.pError, hit.ng};
}
struct BsdfPdf {
    const Bsdf& bsdf;
    const Vec3& wo;
    float operator()(const Vec3& wi) const { return bsdf.pdf(wo, wi); }
};

// The same for a scattering event in the medium: a point off any surface (zero normal), and the
// phase function, which is its own density and what incidentLight()'s caller multiplies by.
LightSampleContext mediumContext(const MediumPoint& point) {
    return LightSampleContext{point.p, Vec3(0.0f), Vec3(0.0f)};
}
struct PhasePdf {
    const MediumPoint& point;
    float operator()(const Vec3& wi) const { return point.phase.p(point.wo, wi); }
};
// The power heuristic weight, in the distance, of a point-like light's sample at the event at
// ray parameter t of the segment, drawn by the free flight (`byFlight`) or by equiangular
// sampling towards the light at y.
float distanceMisWeight(const MediumSegment& segment, float t, const Vec3& y, bool byFlight) {
    const std::optional<Equiangular> towards =
        equiangularTowards(segment.ray.o, segment.ray.d, segment.t0, segment.t1, y);
    const float flight = segment.flightPdf(t);
    const float equiangular = towards ? towards->pdf(t) : 0.0f;
    return byFlight ? powerHeuristic(flight, equiangular) : powerHeuristic(equiangular, flight);
}

// The weight of a light sample at a free flight's event: against equiangular sampling when that
// also draws events on its segment and the light is point-like, else 1.
float flightEventWeight(const Scene& scene, const MediumPoint& point,
                        const IncidentLight& incident) {
    if (!point.segment || !pointLike(*scene.lights()[incident.light]))
        return 1.0f;
    return distanceMisWeight(*point.segment, point.t, incident.pLight, true);
}

struct PhaseScatters {
    const MediumPoint& point;
    Color& f;
    bool operator()(const Vec3& wi) const {
        f = Color(point.phase.p(point.wo, wi));
        return f[0] > 0.0f;
    }
};

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

// One direction from one part of the environment (its map or its sun) and incidentLight(),
// weighted against scatterPdf with that part's density; nothing without an environment.
template <typename ScatterPdf, typename Reflects>
std::optional<Color> incidentEnvironmentPart(const Scene& scene, EnvironmentPart part,
                                             const LightSampleContext& ctx,
                                             const ScatterPdf& scatterPdf, Sampler& sampler,
                                             PathCounters& counters, const Reflects& reflects) {
    const Vec2 u = sampler.get2D();
    const EnvironmentLight* environment = scene.environment();
    if (!environment)
        return std::nullopt;
    const std::optional<LightLiSample> ls = environment->sampleLi(ctx, u, part);
    return incidentLight(scene, ls, ls ? ls->pdf : 0.0f, false, ctx, scatterPdf, counters,
                         reflects);
}

// The emission that a direction sampled at `ctx` with density `pdf` reaches along `ray`
// (through straight-through surfaces, attenuated by solids and the medium on the way), times
// `beta` and weighted by the power heuristic against light sampling from ctx (Veach 1997,
// Eq. 9.13): the scattering sample's half of estimateDirectLight and estimateInScattering.
Color sampledEmission(const Scene& scene, const LightSampleContext& ctx, Ray ray, float pdf,
                      Color beta, Sampler& sampler, PathCounters& counters) {
    const Vec3 wi = ray.d;
    while (maxComponent(beta) > 0.0f) {
        ++counters.rays;
        const std::optional<SurfaceHit> next = scene.intersect(ray);
        beta *= segmentAttenuation(scene, ray, next ? &*next : nullptr);
        if (!next)
            return beta * scene.escaped(wi) * escapedMisWeight(scene, ctx.p, wi, pdf);
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
        return beta * Le * emissionMisWeight(scene, ctx, wi, *next, pdf);
    }
    return Color(0.0f);
}

}  // namespace

Color sampleDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                        Sampler& sampler, PathCounters& counters, ReflectingLobes lobes) {
    Color f(0.0f);
    const auto incident =
        sampleIncidentLight(scene, scene.lightSampler(), surfaceContext(hit), BsdfPdf{bsdf, wo},
                            sampler, counters, LobesReflect{bsdf, wo, f, lobes});
    return incident ? f * incident->L : Color(0.0f);
}

Color sampleDirectLightFromSet(const Scene& scene, const LightSelection& selection, size_t set,
                               const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                               Sampler& sampler, PathCounters& counters, uint32_t& light) {
    Color f(0.0f);
    const auto incident =
        sampleIncidentLight(scene, selection.set(set), surfaceContext(hit), BsdfPdf{bsdf, wo},
                            sampler, counters, LobesReflect{bsdf, wo, f});
    if (!incident)
        return Color(0.0f);
    light = incident->light;
    return f * incident->L;
}

Color sampleEnvironmentPart(const Scene& scene, EnvironmentPart part, const SurfaceHit& hit,
                            const Bsdf& bsdf, const Vec3& wo, Sampler& sampler,
                            PathCounters& counters) {
    Color f(0.0f);
    const std::optional<Color> L =
        incidentEnvironmentPart(scene, part, surfaceContext(hit), BsdfPdf{bsdf, wo}, sampler,
                                counters, LobesReflect{bsdf, wo, f});
    return L ? f * *L : Color(0.0f);
}

Color sampleDirectLight(const Scene& scene, const MediumPoint& point, Sampler& sampler,
                        PathCounters& counters) {
    Color f(0.0f);
    const auto incident =
        sampleIncidentLight(scene, scene.lightSampler(), mediumContext(point), PhasePdf{point},
                            sampler, counters, PhaseScatters{point, f});
    return incident ? f * incident->L * flightEventWeight(scene, point, *incident) : Color(0.0f);
}

Color sampleDirectLightFromSet(const Scene& scene, const LightSelection& selection, size_t set,
                               const MediumPoint& point, Sampler& sampler, PathCounters& counters,
                               uint32_t& light) {
    Color f(0.0f);
    const auto incident =
        sampleIncidentLight(scene, selection.set(set), mediumContext(point), PhasePdf{point},
                            sampler, counters, PhaseScatters{point, f});
    if (!incident)
        return Color(0.0f);
    light = incident->light;
    return f * incident->L * flightEventWeight(scene, point, *incident);
}

bool pointLike(const Light& light) {
    return light.isDelta() && light.kind() != LightKind::Directional;
}

Color sampleEquiangularInScattering(const Scene& scene, const PowerLightSampler& lights,
                                    const MediumSegment& segment, Sampler& sampler,
                                    PathCounters& counters, uint32_t& light) {
    const float uLight = sampler.get1D();
    const Vec2 uPoint = sampler.get2D();
    const float uDistance = sampler.get1D();
    const auto choice = lights.sample(uLight);
    if (!choice || !pointLike(*scene.lights()[choice->light]))
        return Color(0.0f);
    const Light& chosen = *scene.lights()[choice->light];
    // A point-like light's samples all come from its place, whatever the receiver.
    const std::optional<LightLiSample> place =
        chosen.sampleLi(LightSampleContext{segment.ray.o}, uPoint);
    if (!place)
        return Color(0.0f);
    const Ray& ray = segment.ray;
    const std::optional<Equiangular> towards =
        equiangularTowards(ray.o, ray.d, segment.t0, segment.t1, place->pLight);
    if (!towards)
        return Color(0.0f);
    const float t = std::clamp(towards->sample(uDistance), segment.t0, segment.t1);
    const MediumPoint point{ray.o + t * ray.d, segment.medium.phase(), -ray.d};
    const std::optional<LightLiSample> ls = chosen.sampleLi(mediumContext(point), uPoint);
    Color f(0.0f);
    const std::optional<Color> L =
        incidentLight(scene, ls, choice->pmf * (ls ? ls->pdf : 0.0f), true, mediumContext(point),
                      PhasePdf{point}, counters, PhaseScatters{point, f});
    if (!L)
        return Color(0.0f);
    light = choice->light;
    const Color T = segment.medium.transmittance(ray, segment.t0, t);
    return T * segment.medium.sigmaSAt(point.p) * f * *L *
           (distanceMisWeight(segment, t, ls->pLight, false) / towards->pdf(t));
}

Color sampleEnvironmentPart(const Scene& scene, EnvironmentPart part, const MediumPoint& point,
                            Sampler& sampler, PathCounters& counters) {
    Color f(0.0f);
    const std::optional<Color> L =
        incidentEnvironmentPart(scene, part, mediumContext(point), PhasePdf{point}, sampler,
                                counters, PhaseScatters{point, f});
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
    const auto incident = sampleIncidentLight(scene, scene.lightSampler(), surfaceContext(hit),
                                              BsdfPdf{bsdf, wo}, sampler, counters, reflects);
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
    const Color beta = bs->f * (std::abs(glm::dot(bs->wi, bsdf.shadingNormal())) / bs->pdf);
    // Straight-through transparency passes the ray on, as for the light sample's shadow ray.
    return fromLight + sampledEmission(scene, LightSampleContext{hit.p, hit.pError, hit.ng},
                                       Scene::spawnRay(hit, bs->wi), bs->pdf, beta, sampler,
                                       counters);
}

Color estimateInScattering(const Scene& scene, const MediumPoint& point, Sampler& sampler,
                           PathCounters& counters) {
    const Color fromLight = sampleDirectLight(scene, point, sampler, counters);
    // The phase function's sample: its weight p / pdf is 1.
    const Vec3 wi = point.phase.sample(point.wo, sampler.get2D());
    return fromLight + sampledEmission(scene, mediumContext(point), Ray{point.p, wi},
                                       point.phase.p(point.wo, wi), Color(1.0f), sampler, counters);
}

}  // namespace penumbra
