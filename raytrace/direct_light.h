// Next-event estimation: the light arriving at a surface point directly from the scene's lights,
// shared by every tracer that forms images (path tracing, distribution ray tracing).
#pragma once

#include "core/bsdf.h"
#include "core/phase_function.h"
#include "core/scene.h"

namespace penumbra {

class Sampler;
struct PathCounters;

// Reflected radiance towards wo from one light chosen by power and one point on it, with a
// shadow ray (thin glass and alpha cut-outs transmit), weighted by the power heuristic against
// bsdf.pdf() (Veach 1997, Eq. 9.13) for a tracer that also counts the emission its BSDF samples
// reach; a delta light's weight is 1, as BSDF sampling cannot reach it. With the glossy lobes
// alone the weight is still against the whole bsdf.pdf(), the density the tracer's BSDF samples
// have whatever they are then weighed by.
Color sampleDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                        Sampler& sampler, PathCounters& counters,
                        ReflectingLobes lobes = ReflectingLobes::All);

// sampleDirectLight with the light drawn from set `set` of `selection` (core/light_sampler.h)
// instead of from all the scene's lights, and weighted against bsdf.pdf() with its pmf in that
// set. `light` receives the light drawn (its index in scene.lights()) when the result is not zero.
Color sampleDirectLightFromSet(const Scene& scene, const LightSelection& selection, size_t set,
                               const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                               Sampler& sampler, PathCounters& counters, uint32_t& light);

// The same from one part of the environment alone (its map or its sun: EnvironmentLight's
// sampleLi(.., part)), drawn at every call, weighted against bsdf.pdf() with that part's density;
// zero without an environment. environmentPartMisWeight() is the weight of the part's radiance
// that a BSDF sample of density bsdfPdf, leaving point `from`, found past a ray that left the
// scene in direction wi.
Color sampleEnvironmentPart(const Scene& scene, EnvironmentPart part, const SurfaceHit& hit,
                            const Bsdf& bsdf, const Vec3& wo, Sampler& sampler,
                            PathCounters& counters);
float environmentPartMisWeight(const Scene& scene, EnvironmentPart part, const Vec3& from,
                               const Vec3& wi, float bsdfPdf);

// A segment of a ray through the scene's participating medium (core/medium.h): the ray's span
// [t0, t1] in it (Medium::span), on which both its free flight and equiangular
// sampling (sampleEquiangularInScattering) draw scattering events.
struct MediumSegment {
    Ray ray;
    float t0, t1;
    const Medium& medium;
    // The density (per metre) of the free flight's event at ray parameter t.
    float flightPdf(float t) const { return medium.flightPdf(ray, t0, t); }
};

// A scattering event in the medium: the point, the medium's phase function and the direction the
// light leaves towards. When equiangular sampling also draws events on the segment whose free
// flight drew this one, `segment` and the event's ray parameter t, against which a point-like
// light's sample is then weighted; otherwise null.
struct MediumPoint {
    Vec3 p;
    const HenyeyGreenstein& phase;
    Vec3 wo;
    const MediumSegment* segment = nullptr;
    float t = 0.0f;
};

// The three estimates above at a scattering event in the medium: the light scattered towards wo
// by the phase function (which is also its own sampling density, against which the light sample
// is weighted), the shadow ray attenuated by the medium (Scene::transmittance). The in-scattered
// radiance still to be multiplied by sigma_s, which the free flight's weight holds
// (Medium::sampleFlight).
Color sampleDirectLight(const Scene& scene, const MediumPoint& point, Sampler& sampler,
                        PathCounters& counters);
Color sampleDirectLightFromSet(const Scene& scene, const LightSelection& selection, size_t set,
                               const MediumPoint& point, Sampler& sampler, PathCounters& counters,
                               uint32_t& light);
Color sampleEnvironmentPart(const Scene& scene, EnvironmentPart part, const MediumPoint& point,
                            Sampler& sampler, PathCounters& counters);

// The direct light of the point-like lights (point, spot and measured luminaires: delta lights
// at a place) that the medium along `segment` scatters towards the ray's origin, per unit of the
// path's weight there: one light drawn from `lights`, one distance drawn by equiangular sampling
// towards it (Kulla and Fajardo 2012, "Importance Sampling Techniques for Path Tracing in
// Participating Media"), the transmittance from the span's start, sigma_s and the phase function
// applied, weighted against the free flight's events by the power heuristic in the distance
// (their light samples of point-like lights take the other weight, MediumPoint::segment). Its
// density follows a point light's 1 / r^2, where the free flight's follows the transmittance
// alone and seldom falls near a lamp in a thin haze. Zero when the light drawn is not point-
// like; `light` receives the light drawn when the result is not zero.
Color sampleEquiangularInScattering(const Scene& scene, const PowerLightSampler& lights,
                                    const MediumSegment& segment, Sampler& sampler,
                                    PathCounters& counters, uint32_t& light);
// Whether a light is point-like, the lights equiangular sampling draws towards.
bool pointLike(const Light& light);

// The reflected radiance of sampleDirectLight by all the non-delta lobes and by the glossy ones
// alone, from one light sample and one shadow ray: for a tracer that takes the Lambertian layer's
// share (all - glossy) apart at a vertex.
struct DirectLightShares {
    Color all{0.0f};
    Color glossy{0.0f};
};
DirectLightShares sampleDirectLightShares(const Scene& scene, const SurfaceHit& hit,
                                          const Bsdf& bsdf, const Vec3& wo, Sampler& sampler,
                                          PathCounters& counters);

// The power heuristic weight (Veach 1997, Eq. 9.13) of emission that a BSDF sample of density
// bsdfPdf, leaving the point of ctx in direction wi, reached on lightHit, against the light
// sampling of sampleDirectLight from the same point (of sampleDirectLightFromSet, whose light
// comes from its set of `selection`, when that is given); 1 where that is not a light of the
// scene.
float emissionMisWeight(const Scene& scene, const LightSampleContext& ctx, const Vec3& wi,
                        const SurfaceHit& lightHit, float bsdfPdf,
                        const LightSelection* selection = nullptr);

// The same for the environment's radiance that a BSDF sample of density bsdfPdf, leaving point
// `from`, found past a ray that left the scene in direction wi; 1 without an environment.
float escapedMisWeight(const Scene& scene, const Vec3& from, const Vec3& wi, float bsdfPdf);

// The whole direct light reflected towards wo by the non-delta lobes, for a tracer that traces
// no further bounce from this vertex (distribution ray tracing): the light sample above and one
// BSDF sample followed (through thin glass) to the emitter it reaches, each weighted by the power
// heuristic against the other (Veach 1997, section 9.2, Eq. 9.13). The BSDF sample bounds what
// light sampling alone makes unbounded: an area light's 1 / r² next to the surface it lights.
Color estimateDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                          const Vec3& wo, Sampler& sampler, PathCounters& counters);

// The same at a point of the medium (no equiangular sampling: point.segment null): the direct
// light the phase function scatters towards point.wo, from the light sample and one phase
// function sample, each weighted by the power heuristic against the other; still to be
// multiplied by sigma_s there. For a tracer that traces no bounce from the medium (the
// single-scattering preview, raytrace/single_scattering.h).
Color estimateInScattering(const Scene& scene, const MediumPoint& point, Sampler& sampler,
                           PathCounters& counters);

}  // namespace penumbra
