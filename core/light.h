// Light sources. Units are photometric (CONTRIBUTING.md, "Units"): radiance in cd/m², intensity in
// cd, illuminance in lux, flux in lm, each per linear-sRGB channel.
//
// The interface follows pbrt-v4's Light: sampleLi() draws a direction towards the light from a
// receiving point, pdfLi() gives the density of that strategy for a direction found by other
// means (BSDF sampling hitting an emitter), which multiple importance sampling needs. Infinite
// lights (the environment, core/environment_light.h) fit it through Scene::escaped() for rays that
// leave the scene; goniometric lights (IES) will be another delta-position light.
#pragma once

#include "core/interaction.h"
#include "core/math.h"

#include <optional>
#include <string>

namespace penumbra {

enum class LightKind { Point, Spot, Directional, Area, Environment, Goniometric };

// The receiving point of a light sample.
struct LightSampleContext {
    Vec3 p;
    Vec3 pError{0.0f};
    Vec3 n{0.0f};  // geometric normal of the receiver, zero for a point in a medium
};

struct LightLiSample {
    Color L{0.0f};      // radiance (area), or intensity / d² (point, spot), or illuminance
                        // (directional) arriving at the receiver along -wi, unoccluded
    Vec3 wi{0.0f};      // unit direction from the receiver towards the light
    float pdf = 0.0f;   // solid angle for area lights; 1 for delta lights
    Vec3 pLight{0.0f};  // the sampled point on the light (far away for directional lights)
    Vec3 nLight{0.0f};  // its geometric normal (zero for delta lights)
    Vec3 pLightError{0.0f};
};

// A ray leaving a light, for tracing photons (pbrt-v4's Light::SampleLe and LightLeSample).
struct LightLeSample {
    Vec3 p{0.0f};  // the ray's origin: on the light, or for a directional light on a disc
                   // perpendicular to it behind the scene
    Vec3 w{0.0f};  // unit direction of the ray
    // What is emitted along the ray: radiance (cd/m², area lights), intensity (cd, point and
    // spot lights) or illuminance (lux on a plane perpendicular to w, directional lights).
    Color L{0.0f};
    float pdfPos = 0.0f;  // area density (1/m²) of p; 1 for a delta position (point, spot)
    float pdfDir = 0.0f;  // solid-angle density (1/sr) of w; 1 for a delta direction
    Vec3 n{0.0f};         // unit normal of the emitting face at p (area lights), else zero
    Vec3 pError{0.0f};    // rounding error bound of p (area lights), to offset rays off the light
    Vec3 b{0.0f};         // barycentrics of p on an area light's triangle, for emittedLe()

    // The flux (lm per channel) one sample stands for, L |cos theta| / (pdfPos pdfDir), with
    // cos theta = n . w for area lights and 1 otherwise: its mean over samples is
    // Light::power() (the initial beta of a photon in pbrt-v4's SPPMIntegrator).
    Color flux() const {
        const float denominator = pdfPos * pdfDir;
        if (!(denominator > 0.0f))
            return Color(0.0f);
        const float cosTheta = glm::dot(n, n) > 0.0f ? std::abs(glm::dot(n, w)) : 1.0f;
        return L * (cosTheta / denominator);
    }
};

class Light {
  public:
    virtual ~Light() = default;

    virtual LightKind kind() const = 0;
    // Delta lights (point, spot, directional) can only be reached by sampleLi().
    virtual bool isDelta() const = 0;

    // Samples a direction from ctx towards the light. Returns nothing when the light sends no
    // light to ctx (behind a one-sided emitter, outside a spot cone, beyond the range).
    virtual std::optional<LightLiSample> sampleLi(const LightSampleContext& ctx, Vec2 u) const = 0;

    // Solid-angle density with which sampleLi() from ctx would produce direction wi that hits
    // this light at lightHit. Zero for delta lights.
    virtual float pdfLi(const LightSampleContext& ctx, const Vec3& wi,
                        const SurfaceHit& lightHit) const = 0;

    // Samples a ray leaving the light: the origin from uPosition, the direction from uDirection
    // (cosine-weighted over the emitting hemisphere of area lights, uniform over the sphere of a
    // point light and over the outer cone of a spot). Nothing when the sample carries no light.
    // The same uPosition gives the same origin whatever uDirection, so a caller may keep the
    // origin and choose its own direction with emittedLe() (photons aimed at objects); lights at
    // infinity (directional, environment) are the exception: their origin lies on a disc across
    // the direction, so a caller keeps their direction and chooses its own origin.
    virtual std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const = 0;

    // What the light emits from the origin of `origin` (a sampleLe() result) in unit direction w,
    // in the units of LightLeSample::L: radiance (zero behind a one-sided area light), intensity
    // (point, spot), or for a directional light its illuminance when w is its direction (zero
    // otherwise: a delta in direction).
    virtual Color emittedLe(const LightLeSample& origin, const Vec3& w) const = 0;

    // Total emitted flux (lm per channel). Used to choose lights in proportion to their power.
    virtual Color power() const = 0;

    virtual std::string describe() const = 0;
};

}  // namespace penumbra
