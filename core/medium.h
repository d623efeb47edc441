// A participating medium (fog, haze, smoke, a cloud) filling an axis-aligned box: absorption and
// scattering coefficients sigma_a and sigma_s per linear-sRGB channel (per metre) scaled by a
// density, uniform 1 (a homogeneous medium) or a heterogeneous one on a voxel grid
// (core/density_grid.h), and a Henyey-Greenstein phase function (core/phase_function.h). The
// radiative transfer equation along a ray (Chandrasekhar 1960; Pharr, Jakob and Humphreys,
// "Physically Based Rendering", 4th ed., chapter 11) then has the transmittance
// T(t) = exp(-sigma_t D(t)), sigma_t = sigma_a + sigma_s and D(t) the integral of the density
// along the ray's part in the box up to t (its length, for a homogeneous medium).
//
// The medium is outside every solid: a segment of a ray that ends on the back face of a
// KHR_materials_volume material runs inside that solid (core/surface_crossing.h, insideSolid),
// whose own absorption applies there instead.
//
// Free-flight sampling (sampleFlight) draws the distance to the next scattering event from one
// channel's transmittance, the channel chosen uniformly (the optical depth drawn from an
// exponential, then the distance at which D reaches it: exact for a grid, as DensityGrid
// explains), and weighs the event by the density of the three strategies together (one-sample
// multiple importance sampling with the balance heuristic over the channels: Veach 1997, section
// 9.2.4; for chromatic media Wilkie et al. 2014, "Hero Wavelength Spectral Sampling", the
// "spectral MIS" of Miller, Georgiev and Jarosz 2019): unbiased for any sigma_t, also one that is
// zero in some channel, with bounded weights. The density at the event cancels from the weight.
//
// An emitting medium (a flame's glow, a lit fog in a stage's haze) adds sigma_a rho Le per metre
// along a ray (pbrt-v4's convention: emission tied to absorption, as Kirchhoff's law ties them),
// Le the radiance of a layer thick enough to be opaque. Along a span the emission reaching its
// start is then the closed form Le sigma_a / sigma_t (1 - T) per channel, for a heterogeneous
// medium too (d T / ds = -sigma_t rho T): emitted() adds it exactly, without sampling.
#pragma once

#include "core/density_grid.h"
#include "core/math.h"
#include "core/phase_function.h"
#include "core/ray.h"

#include <memory>
#include <optional>
#include <string>

namespace penumbra {

// A medium as the scene description holds it (SceneDescription::media).
struct MediumDesc {
    std::string name;                  // where it came from, for messages and `info`
    Color sigmaA{0.0f}, sigmaS{0.0f};  // per metre at density 1, per channel, >= 0 and finite
    float g = 0.0f;                    // the phase function's asymmetry, in (-1, 1)
    // The emission Le of the header, cd/m² per channel, >= 0, zero where sigma_a is zero.
    Color emission{0.0f};
    // The box it fills, in penumbra's world frame (the file's, less SceneDescription::origin);
    // nothing: the scene's bounding box. With a density grid, the grid's own box.
    std::optional<Bounds3> box;
    // The density that scales sigma_a and sigma_s; nothing: 1 everywhere in the box.
    std::shared_ptr<const DensityGrid> density = nullptr;
};

class Medium {
  public:
    // `box` is where it is (MediumDesc::box, or the scene's bounds when that is empty).
    Medium(const MediumDesc& desc, const Bounds3& box);

    const Bounds3& box() const { return box_; }
    // The coefficients at density 1 (per metre).
    const Color& sigmaS() const { return sigmaS_; }
    const Color& sigmaT() const { return sigmaT_; }
    // The density grid; null for a homogeneous medium.
    const DensityGrid* density() const { return density_.get(); }
    // The scattering coefficient at p, a point in the box.
    Color sigmaSAt(const Vec3& p) const { return density_ ? sigmaS_ * density_->at(p) : sigmaS_; }
    const HenyeyGreenstein& phase() const { return phase_; }
    // Whether the medium scatters at all (else it only absorbs: no scattering event is drawn).
    bool scatters() const { return maxComponent(sigmaS_) > 0.0f; }
    const Color& emission() const { return emission_; }
    bool emits() const { return maxComponent(emission_) > 0.0f; }

    // The part [t0, t1] of the ray's span [0, tMax] that lies in the box (ray.d unit); nothing
    // when the two do not overlap.
    struct Span {
        float t0, t1;
    };
    std::optional<Span> span(const Ray& ray, float tMax) const;

    // exp(-sigma_t D) over the ray's span [0, tMax] in the box (the header's T).
    Color transmittance(const Ray& ray, float tMax) const;
    // The same from ray parameter t0 to t, both in the box's span of the ray.
    Color transmittance(const Ray& ray, float t0, float t) const;
    // The radiance the medium emits along the span that reaches its start (the header's closed
    // form); zero for a medium that does not emit.
    Color emitted(const Ray& ray, const Span& span) const;

    // One free flight along a ray's span in the box (span(), not empty; the header's sampling):
    // either a scattering event at ray parameter t, weighted by T(t0, t) sigma_s(t) / pdf, where
    // the path goes on with the phase function, or none, weighted by T / P(none), where it goes
    // on past the span.
    struct Flight {
        bool scattered = false;
        float t = 0.0f;
        Color weight{1.0f};
    };
    Flight sampleFlight(const Ray& ray, const Span& span, float uChannel, float uDistance) const;
    // The density (per metre) with which sampleFlight() draws a scattering event at ray parameter
    // t of the span that starts at t0: the three channels' strategies together; 0 for a medium
    // that does not scatter.
    float flightPdf(const Ray& ray, float t0, float t) const;

  private:
    // D of the header from ray parameter t0 to t1.
    float opticalLength(const Ray& ray, float t0, float t1) const;
    // The three channels' densities together per unit of density at the event, D into the span.
    float channelsPdf(float D) const;

    Bounds3 box_;
    Color sigmaS_, sigmaT_, sigmaA_, emission_;
    HenyeyGreenstein phase_;
    std::shared_ptr<const DensityGrid> density_;
};

}  // namespace penumbra
