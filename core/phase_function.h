// The Henyey-Greenstein phase function (Henyey and Greenstein 1941, "Diffuse radiation in the
// galaxy", Astrophys. J. 93): the angular distribution of the light a participating medium
// scatters, with one parameter g in (-1, 1), the mean cosine of the scattering angle (0
// isotropic, > 0 forward as haze and smoke, < 0 backward). Normalised over the sphere, and
// sampled exactly by inverting its cumulative distribution in the cosine (Pharr, Jakob and
// Humphreys, "Physically Based Rendering", 4th ed., section 11.3.1), so a sample's weight
// p / pdf is 1.
//
// Directions point away from the scattering point, as a BSDF's: wo towards where the light goes
// on to (the eye, for a camera path), wi towards where it comes from. The scattering angle
// theta is between the light's direction of travel before (-wi) and after (wo): cos theta =
// -dot(wi, wo), 1 when the light goes straight on.
#pragma once

#include "core/math.h"

namespace penumbra {

class HenyeyGreenstein {
  public:
    // g is clamped to [-kMaxAsymmetry, kMaxAsymmetry]: at |g| = 1 the function is a delta.
    explicit HenyeyGreenstein(float g);

    static constexpr float kMaxAsymmetry = 0.99f;

    float g() const { return g_; }
    // The phase function, per steradian, of the scattering angle's cosine.
    float p(float cosTheta) const;
    // The phase function for light arriving from wi and leaving towards wo: also the density
    // (per steradian) with which sample(wo, ..) draws wi.
    float p(const Vec3& wo, const Vec3& wi) const { return p(-glm::dot(wo, wi)); }
    // Draws wi for light leaving towards wo (unit) with density p(wo, wi).
    Vec3 sample(const Vec3& wo, Vec2 u) const;

  private:
    float g_;
};

}  // namespace penumbra
