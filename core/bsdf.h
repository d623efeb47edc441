// The glTF 2.0 metallic-roughness BSDF at one surface point.
//
// Conventions (as pbrt-v4): all directions are unit vectors in world space pointing away from
// the surface; wo points towards the viewer (or the previous vertex), wi towards the light.
// f() excludes the cosine factor; pdf() is per unit solid angle; neither includes delta lobes,
// which only sample() returns. Reflection versus transmission is decided by the geometric
// normal, so that shading normals cannot leak light through a surface.
#pragma once

#include "core/material.h"
#include "core/math.h"

#include <cstdint>
#include <optional>

namespace penumbra {

// Lobe flags so that a tracer can ask what a BSDF has ("any non-delta lobe?") and what a
// sample came from (Mitsuba's BSDFFlags, Tungsten's BsdfLobes). Heckbert's path classes map
// onto them: Diffuse and rough Glossy are D vertices, Specular (delta) lobes are S vertices.
enum BsdfLobe : uint32_t {
    kLobeNone = 0,
    kLobeReflection = 1u << 0,
    kLobeTransmission = 1u << 1,
    kLobeDiffuse = 1u << 2,
    kLobeGlossy = 1u << 3,
    kLobeSpecular = 1u << 4,  // a Dirac delta in direction
};

// Radiance: tracing from the eye; Importance: tracing from the lights (photons). They differ in
// the (1/eta^2) scaling of refraction (Veach 1997, section 5.2).
enum class TransportMode { Radiance, Importance };

struct BsdfSample {
    Color f{0.0f};  // BSDF value (for a delta lobe: its weight divided by |cos theta_i|)
    Vec3 wi{0.0f};
    float pdf = 0.0f;  // solid angle; for a delta lobe the discrete probability of the lobe
    uint32_t lobe = kLobeNone;
    float eta = 1.0f;  // relative IOR crossed by a transmission sample (1 otherwise)

    bool isDelta() const { return (lobe & kLobeSpecular) != 0; }
};

// Which lobes reflect: all, or the rough glossy ones alone (Bsdf::fGlossy), for a tracer that
// takes the Lambertian layer's light from a radiosity solution.
enum class ReflectingLobes { All, Glossy };

class Bsdf {
  public:
    // shading: frame of the shading normal (after normal mapping); ng: unit geometric normal on
    // the front side of the surface (counter-clockwise winding).
    Bsdf(const ShadingParams& params, const Frame& shading, const Vec3& ng);

    Color f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
    // f() without the Lambertian layer: the GGX reflection and rough refraction alone, for a
    // tracer that takes the Lambertian layer's light from elsewhere (distribution ray tracing's
    // radiosity ambient term). Zero where every non-Lambertian lobe is a delta.
    Color fGlossy(const Vec3& wo, const Vec3& wi,
                  TransportMode mode = TransportMode::Radiance) const;
    // f() or fGlossy(), as `lobes` says.
    Color f(const Vec3& wo, const Vec3& wi, ReflectingLobes lobes) const {
        return lobes == ReflectingLobes::All ? f(wo, wi) : fGlossy(wo, wi);
    }
    float pdf(const Vec3& wo, const Vec3& wi) const;
    // Samples wi given wo. uLobe picks the lobe, u the direction within it. Returns nothing when
    // the sample carries no energy (below the horizon, total internal reflection of a lobe with
    // no reflection counterpart, ...). The path weight is f * |cos(wi, shading normal)| / pdf.
    std::optional<BsdfSample> sample(const Vec3& wo, float uLobe, const Vec2& u,
                                     TransportMode mode = TransportMode::Radiance) const;

    // Union of the lobes this BSDF has at this point.
    uint32_t lobes() const { return lobes_; }
    bool hasNonDeltaLobe() const { return (lobes_ & (kLobeDiffuse | kLobeGlossy)) != 0; }

    // Rough glossy lobes at most this wide (GGX alpha; roughness about 0.22) are sharp: a lobe's
    // width in radians is about its alpha, so what such a surface reflects from a metre away is
    // blurred over a few centimetres, less than a radiosity element there. It reflects an image
    // of the room (a polished floor), which spreading its reflection as Lambertian, as a solution
    // does for rough lobes, puts in the wrong places.
    static constexpr float kSharpGlossyAlpha = 0.05f;
    // Whether this point's glossy lobes (GGX reflection, and rough refraction) are sharp: not
    // deltas, alpha at most kSharpGlossyAlpha.
    bool hasSharpGlossyLobe() const {
        return (lobes_ & kLobeGlossy) && alpha_ <= kSharpGlossyAlpha;
    }

    // Thin-walled transmission (KHR_materials_volume thickness 0): the light that passes
    // straight through, not bent, per channel, for light arriving along -wo. Tracers treat it as
    // transparency (a shadow ray's transmittance, a path continuing unchanged), not as a
    // scattering vertex, so it is NOT part of f(), pdf() or sample(). Zero for other materials.
    Color straightTransmittance(const Vec3& wo) const;

    // Unit shading normal (after normal mapping), on the front side of the geometric normal.
    const Vec3& shadingNormal() const { return shading_.n; }

    // Hemispherical-hemispherical reflectance of the lobes that make this point a D vertex
    // (Heckbert's notation: diffuse or rough glossy): the fraction of uniform (diffuse) incident
    // light that the Lambertian layer and the non-delta GGX reflection send back, what a
    // radiosity solver treats as rho. The Lambertian layer gives (1 - metallic) (1 -
    // transmission) baseColor (1 - E_avg), E_avg being the average albedo of the dielectric
    // specular layer above it; when that layer is rough it adds (1 - metallic) E_avg, and a rough
    // metal adds metallic E_avg(Schlick(baseColor)). Delta (S) lobes and transmission are left
    // out: they are the ray tracer's. Without `withSharpGlossy`, the sharp glossy lobes' part
    // (hasSharpGlossyLobe) is left out too: for a radiosity solution that carries their
    // reflection by photons instead of spreading it (passes/specular_transfer.h).
    Color diffuseGlossyReflectance(bool withSharpGlossy = true) const;
    // The Lambertian layer's share of it: (1 - metallic) (1 - transmission) baseColor (1 - E_avg).
    Color matteReflectance() const;
    // The Lambertian layer's directional albedo seen from wo: (1 - metallic) (1 - transmission)
    // baseColor (1 - E(wo)), what it reflects towards wo of uniform incident light. Its cosine-
    // weighted average over wo is matteReflectance(); at grazing wo, where the specular layer
    // reflects more, it is lower. Zero where nothing scatters towards wo.
    Color matteAlbedo(const Vec3& wo) const;

  private:
    // One wo in the local frame, with the quantities every query about it needs.
    struct Query {
        Vec3 wo;       // local, mirrored so that wo.z > 0
        bool front;    // wo on the front side of the geometric normal
        float eta;     // relative IOR n(wi side) / n(wo side) of refraction: ior from the front
        Color albedo;  // E(mu_o) of the dielectric specular layer (two-sided Schlick)
        float pDiffuse = 0.0f, pReflection = 0.0f, pGlass = 0.0f;  // strategy selection
    };

    std::optional<Query> query(const Vec3& wo) const;
    std::optional<Query> computeQuery(const Vec3& wo) const;
    Vec3 toLocal(const Vec3& w, bool front) const;
    Vec3 toWorld(const Vec3& w, bool front) const;
    Color specularAlbedo(float cosTheta) const;
    // The Lambertian layer's albedo under a specular layer of albedo E: (1 - metallic) (1 -
    // transmission) baseColor (1 - E).
    Color matteUnder(const Color& specularAlbedo) const;
    Color mirrorFresnel(const Query& q, float cosTheta) const;
    float glassReflectionChoice(const Query& q, float cosTheta) const;
    Color evalF(const Query& q, const Vec3& wi, TransportMode mode, bool withMatte = true) const;
    float evalPdf(const Query& q, const Vec3& wi) const;

    ShadingParams params_;  // clamped to the ranges of the glTF spec
    Frame shading_;         // normal turned to the side of ng_
    Vec3 ng_;
    uint32_t lobes_ = kLobeNone;
    // The last query, reused while wo stays the same (a Bsdf lives in one thread).
    mutable Vec3 cachedWo_{0.0f};
    mutable std::optional<std::optional<Query>> cachedQuery_;
    float alpha_ = 0.0f;            // GGX alpha = roughness^2
    bool smooth_ = false;           // alpha below GgxDistribution::kSmoothAlpha: delta lobes
    bool deltaRefraction_ = false;  // smooth, or index-matched (ior 1): refraction is a delta
    Color f0_{0.0f};                // dielectric normal-incidence reflectance
    Color albedoAvg_{0.0f};         // E_avg of the dielectric specular layer (Kelemen coupling)
    // Sampling strategies: Lambertian, GGX reflection, and the glass term of a solid.
    bool hasDiffuse_ = false, hasReflection_ = false, hasGlass_ = false;
};

}  // namespace penumbra
