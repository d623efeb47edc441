// Light sources. Units are photometric (DEVELOPERS.md): radiance in cd/m², intensity in cd,
// illuminance in lux, flux in lm, each per linear-sRGB channel.
//
// The interface follows pbrt-v4's Light: sampleLi() draws a direction towards the light from a
// receiving point, pdfLi() gives the density of that strategy for a direction found by other
// means (BSDF sampling hitting an emitter), which multiple importance sampling needs. Infinite
// lights (sky, environment) and goniometric lights (IES) fit the same interface later: the
// former through emittedEscaped(), the latter as another delta-position light.
#pragma once

#include "core/interaction.h"
#include "core/math.h"

#include <optional>
#include <string>

namespace penumbra {

enum class LightKind { Point, Spot, Directional, Area };

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

    // Total emitted flux (lm per channel). Used to choose lights in proportion to their power.
    virtual Color power() const = 0;

    virtual std::string describe() const = 0;
};

}  // namespace penumbra
