// Directional albedo of the GGX reflection lobe with Schlick Fresnel, tabulated once.
//
// The lobe is f = F(wo.h) D G2 / (4 |wo.n| |wi.n|) with F = F0 + (1 - F0) (1 - wo.h)^5 and
// alpha = roughness^2. Its directional albedo E(mu) = integral of f cos(theta_i) dwi over the
// hemisphere, mu = cos(theta_o), is linear in F0:
//     E(mu) = F0 A(mu, roughness) + (1 - F0) B(mu, roughness),
// A being the albedo with F = 1 and B the one with F = (1 - wo.h)^5 (the split-sum of Karis
// 2013, "Real Shading in Unreal Engine 4", used for the same purpose by Kulla and Conty 2017,
// "Revisiting Physically Based Shading at Imageworks"). A and B are tabulated over (mu,
// roughness); their cosine-weighted averages E_avg = 2 integral E(mu) mu dmu over roughness.
#pragma once

#include "core/math.h"

namespace penumbra {

// The two Fresnel-independent parts of a directional albedo.
struct SchlickAlbedo {
    float a = 0.0f;  // albedo with F = 1
    float b = 0.0f;  // albedo with F = (1 - wo.h)^5

    Color operator()(const Color& f0) const { return f0 * a + (Color(1.0f) - f0) * b; }
};

// E(mu) for perceptual roughness in [0, 1], bilinearly interpolated. The roughness-0 row holds
// the mirror's A = 1, B = (1 - mu)^5.
SchlickAlbedo ggxSchlickAlbedo(float cosTheta, float roughness);

// E_avg = 2 integral_0^1 E(mu) mu dmu of the interpolated table, so that the interpolated E and
// its average are consistent (the Kelemen coupling relies on it to conserve energy exactly).
SchlickAlbedo ggxSchlickAlbedoAverage(float roughness);

}  // namespace penumbra
