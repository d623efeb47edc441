// The isotropic GGX (Trowbridge-Reitz) microfacet distribution with Smith masking-shadowing,
// in a local frame whose +z axis is the macro-surface normal. Directions point away from the
// surface; callers make sure the direction that sees the surface (wo) has z > 0.
#pragma once

#include "core/math.h"

#include <limits>

namespace penumbra {

class GgxDistribution {
  public:
    // alpha = perceptual roughness squared (glTF 2.0 spec, appendix B). Values below
    // kSmoothAlpha are treated as a perfect mirror by the BSDF, never evaluated here.
    explicit GgxDistribution(float alpha) : alpha2_(alpha * alpha), alpha_(alpha) {}

    // Below this alpha the lobe is narrower than ~0.06 degree and its peak D = 1/(pi alpha^2)
    // exceeds 3e5: for a renderer it is a mirror, and evaluating it would only produce fireflies
    // (the same threshold as pbrt-v4's TrowbridgeReitzDistribution::EffectivelySmooth).
    static constexpr float kSmoothAlpha = 1e-3f;

    float alpha() const { return alpha_; }

    // Normal distribution D(h) per unit projected area (Walter et al. 2007, "Microfacet Models
    // for Refraction through Rough Surfaces", Eq. 33), written as
    // alpha^2 / (pi (sin^2 + alpha^2 cos^2)^2) so that sin^2 = x^2 + y^2 keeps full precision
    // near the peak.
    float D(const Vec3& h) const {
        if (h.z <= 0.0f)
            return 0.0f;
        const float t = (h.x * h.x + h.y * h.y) + alpha2_ * h.z * h.z;
        return alpha2_ / (kPi * t * t);
    }

    // Smith Lambda for GGX (Heitz 2014, "Understanding the Masking-Shadowing Function in
    // Microfacet-Based BRDFs", JCGT 3(2), Eq. 72): (sqrt(1 + alpha^2 tan^2) - 1) / 2, written as
    // x / (2 (1 + sqrt(1 + x))) with x = alpha^2 tan^2 to avoid cancellation near the normal.
    float lambda(const Vec3& w) const {
        const float z2 = w.z * w.z;
        const float x = alpha2_ * (w.x * w.x + w.y * w.y) / z2;
        if (!(x < std::numeric_limits<float>::infinity())) {
            return std::numeric_limits<float>::infinity();
        }
        return 0.5f * x / (1.0f + std::sqrt(1.0f + x));
    }

    // Smith masking G1 (Heitz 2014, Eq. 43).
    float G1(const Vec3& w) const { return 1.0f / (1.0f + lambda(w)); }

    // Height-correlated masking-shadowing (Heitz 2014, Eq. 99). It is symmetric in its
    // arguments (so BSDFs built on it are reciprocal) and G2 / G1(wo) <= 1. Heitz gives a
    // Beta-function variant for transmission; like pbrt-v4 we use this form for both, the
    // difference being small against the single-scattering model itself.
    float G2(const Vec3& wo, const Vec3& wi) const {
        return 1.0f / (1.0f + lambda(wo) + lambda(wi));
    }

    // Distribution of normals visible from wo, D_wo(h) = G1(wo) max(0, wo.h) D(h) / wo.z
    // (Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), Eq. 1),
    // per unit solid angle of h. Requires wo.z > 0.
    float visibleNormalPdf(const Vec3& wo, const Vec3& h) const {
        const float cosOH = glm::dot(wo, h);
        if (cosOH <= 0.0f || wo.z <= 0.0f)
            return 0.0f;
        return G1(wo) * cosOH * D(h) / wo.z;
    }

    // Samples h from D_wo (Heitz 2018, Listing 1). Requires wo.z > 0; returns h with h.z >= 0.
    Vec3 sampleVisibleNormal(const Vec3& wo, Vec2 u) const;

  private:
    float alpha2_;
    float alpha_;
};

}  // namespace penumbra
