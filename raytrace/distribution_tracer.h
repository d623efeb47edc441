// Distribution ray tracing (Cook, Porter and Carpenter 1984, "Distributed Ray Tracing") with the
// radiosity ambient term of the seed's two-pass method: the fast preview for architecture.
//
// From the eye, a ray is followed through specular vertices (mirror reflection and refraction,
// one lobe chosen per sample, up to maxSpecularDepth of them; thin glass is passed straight
// through). At the first vertex with a non-delta lobe (diffuse or rough glossy) it takes
// - the direct light of every light type, area lights sampled over their area so that shadows
//   are soft over the samples of a pixel, glossy highlights included, with one BSDF sample
//   towards the emitters weighted against it by MIS (estimateDirectLight: light sampling alone
//   put 1000 cd/m² fireflies on walls next to the modern hall's lamps);
// - the indirect light (L D D+), the direct part being the line above: for the Lambertian
//   layer, the indirect-only radiosity solution there as the ambient term (its share of it: the
//   solution reflects with the whole non-delta reflectance, Lambertian layer and rough glossy
//   lobes spread as Lambertian, Bsdf::diffuseGlossyReflectance, the sharp ones too unless its
//   specular transfer carried them); for the rough glossy lobes, glossy reflection by sampling
//   the lobe (Cook et al.): one BSDF sample through any mirrors and glass to the next diffuse
//   surface, whose reflected radiance the solution gives;
// and continues only through that vertex's specular lobes, if it has any. Emission is counted
// where a ray from the eye or a specular chain meets it.
//
// With a constant ambient term (Whitted's pass) the chain also previews a participating medium:
// its single scattering L V S* E (raytrace/single_scattering.h, DistributionSettings::mediumSteps)
// and its attenuation of every ray, or the seed's linear fog in their place, which counts no
// light path (raytrace/linear_fog.h, DistributionSettings::mediumPreview).
//
// Light paths: L S* E | L D S* E | L D D+ S* E. Left out: caustics (L S+ D ...), diffuse light
// reaching the visible surface through mirrors (L D+ S+ D ...): see docs/light-paths.md. The
// glossy reflection of other glossy surfaces is that of their radiosity, i.e. spread as
// Lambertian.
#pragma once

#include "raytrace/path_tracer.h"

namespace penumbra {

class Sampler;

struct DistributionSettings {
    int maxSpecularDepth = 16;  // specular vertices followed from the eye
    // Whitted's constant ambient term (Whitted 1980, Eq. 2: I = Ia ka + ...): radiance (cd/m² per
    // channel) assumed to arrive uniformly at every diffuse surface, reflected by its diffuse and
    // rough glossy lobes (Bsdf::diffuseGlossyReflectance). Used instead of a radiosity solution by
    // the `whitted` pass; 0 = none.
    Color ambient{0.0f};
    // Points marched per ray segment through a participating medium for the light it scatters
    // once (raytrace/single_scattering.h): the `whitted` pass's medium preview, which also
    // attenuates what lies behind; the planner keeps the `distribution` pass from media.
    int mediumSteps = 8;
    // Or the seed's linear fog, lit by the ambient term (raytrace/linear_fog.h), in its place.
    enum class MediumPreview { SingleScattering, LinearFog };
    MediumPreview mediumPreview = MediumPreview::SingleScattering;
};

// The light paths distribution ray tracing counts with a radiosity solution's indirect part as
// its ambient term; with a solution that took the caustic photons (L S+ D+), the ambient term
// holds their further bounces too; with one that carried its light through specular surfaces
// (D S+ D, the radiosity pass's specular transfer), those paths too.
std::string distributionLightPaths(bool causticsInRadiosity = false, bool specularTransfer = false);

class DistributionTracer {
  public:
    // indirect: the radiosity solution to take the ambient term from; null = no ambient term
    // (a scene the planner found without diffuse surfaces).
    DistributionTracer(const Scene& scene, const DistributionSettings& settings,
                       const ReusedSolution* indirect);

    // Radiance (cd/m²) arriving along -ray.d at the ray's origin (contract of PathTracer::Li).
    PathRadiance Li(Ray ray, Sampler& sampler, FirstHit* firstHit, PathCounters& counters) const;

  private:
    // The radiosity solution's light that the rough glossy lobes at `hit` reflect towards wo:
    // one BSDF sample to the next surface, whose reflected radiance (L D+) the solution gives.
    Color glossyIndirect(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo, Sampler& sampler,
                         PathCounters& counters) const;

    const Scene& scene_;
    DistributionSettings settings_;
    const ReusedSolution* indirect_;
};

}  // namespace penumbra
