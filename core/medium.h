// A homogeneous participating medium (fog, haze, smoke of even density) filling an axis-aligned
// box: absorption and scattering coefficients sigma_a and sigma_s per linear-sRGB channel (per
// metre) and a Henyey-Greenstein phase function (core/phase_function.h). The radiative transfer
// equation along a ray (Chandrasekhar 1960; Pharr, Jakob and Humphreys, "Physically Based
// Rendering", 4th ed., chapter 11) then has the transmittance T(t) = exp(-sigma_t t) over the
// length t the ray runs inside the box, sigma_t = sigma_a + sigma_s.
//
// The medium is outside every solid: a segment of a ray that ends on the back face of a
// KHR_materials_volume material runs inside that solid (core/surface_crossing.h, insideSolid),
// whose own absorption applies there instead.
//
// Free-flight sampling (sampleFlight) draws the distance to the next scattering event from one
// channel's exponential, the channel chosen uniformly, and weighs the event by the density of
// the three strategies together (one-sample multiple importance sampling with the balance
// heuristic over the channels: Veach 1997, section 9.2.4; for chromatic media Wilkie et al. 2014,
// "Hero Wavelength Spectral Sampling", the "spectral MIS" of Miller, Georgiev and Jarosz 2019):
// unbiased for any sigma_t, also one that is zero in some channel, with bounded weights.
#pragma once

#include "core/math.h"
#include "core/phase_function.h"
#include "core/ray.h"

#include <optional>
#include <string>

namespace penumbra {

// A medium as the scene description holds it (SceneDescription::media).
struct MediumDesc {
    std::string name;                  // where it came from, for messages and `info`
    Color sigmaA{0.0f}, sigmaS{0.0f};  // per metre, per channel, >= 0 and finite
    float g = 0.0f;                    // the phase function's asymmetry, in (-1, 1)
    // The box it fills, in penumbra's world frame (the file's, less SceneDescription::origin);
    // nothing: the scene's bounding box.
    std::optional<Bounds3> box;
};

class HomogeneousMedium {
  public:
    // `box` is where it is (MediumDesc::box, or the scene's bounds when that is empty).
    HomogeneousMedium(const MediumDesc& desc, const Bounds3& box);

    const Bounds3& box() const { return box_; }
    const Color& sigmaS() const { return sigmaS_; }
    const Color& sigmaT() const { return sigmaT_; }
    const HenyeyGreenstein& phase() const { return phase_; }
    // Whether the medium scatters at all (else it only absorbs: no scattering event is drawn).
    bool scatters() const { return maxComponent(sigmaS_) > 0.0f; }

    // The part [t0, t1] of the ray's span [0, tMax] that lies in the box (ray.d unit); nothing
    // when the two do not overlap.
    struct Span {
        float t0, t1;
    };
    std::optional<Span> span(const Ray& ray, float tMax) const;

    // exp(-sigma_t L), L the length of the ray's span [0, tMax] in the box.
    Color transmittance(const Ray& ray, float tMax) const;

    // One free flight along a ray's span in the box (span(), not empty; the header's sampling):
    // either a scattering event at ray parameter t, weighted by T(t - t0) sigma_s / pdf, where
    // the path goes on with the phase function, or none, weighted by T / P(none), where it goes
    // on past the span.
    struct Flight {
        bool scattered = false;
        float t = 0.0f;
        Color weight{1.0f};
    };
    Flight sampleFlight(const Span& span, float uChannel, float uDistance) const;
    // The density (per metre) with which sampleFlight() draws a scattering event `distance` into
    // the span: the three channels' exponentials together; 0 for a medium that does not scatter.
    float flightPdf(float distance) const;

  private:
    Bounds3 box_;
    Color sigmaS_, sigmaT_;
    HenyeyGreenstein phase_;
};

}  // namespace penumbra
