// The seed's linear fog, the cheapest preview of a participating medium: along a ray, what lies
// behind is attenuated linearly with depth, down to nothing at a thickness T, and replaced by the
// fog's own radiance L_a in proportion:
//     L = max(0, 1 - s / T) L_behind + min(1, s / T) L_a
// (depth cueing, as in Foley, van Dam, Feiner and Hughes, "Computer Graphics: Principles and
// Practice", 2nd ed.). penumbra takes both from the medium, per channel, so that
// the preview needs no setting of its own and stays near the medium's look:
// - the depth is the optical thickness tau = sigma_t D (D the optical length along the ray: the
//   distance in an even medium), and T = 2 in it: the linear law then takes away as much light in
//   all as Beer-Lambert's exp(-tau) does (the integrals of 1 - tau / 2 over [0, 2] and of
//   exp(-tau) over [0, inf) are both 1), exactly for tau -> 0 to first order;
// - L_a is the radiance of a deep layer of the medium lit by Whitted's ambient radiance A from
//   every direction and scattering it once: albedo A, plus its glow sigma_a / sigma_t Le, what an
//   opaque layer of it shows (core/medium.h).
// No light path is counted by it (as by the ambient term): the plan names L V ... E as missing.
#pragma once

#include "core/medium.h"

namespace penumbra {

struct LinearFog {
    Color transmittance{1.0f};  // max(0, 1 - tau / 2) per channel
    Color radiance{0.0f};       // (1 - transmittance) L_a: what the fog adds along the span
};

// The linear fog along `span` of `ray`, lit by the ambient radiance A.
LinearFog linearFog(const Medium& medium, const Ray& ray, const Medium::Span& span,
                    const Color& ambient);

}  // namespace penumbra
