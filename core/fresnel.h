// Fresnel reflectance as the glTF 2.0 material model defines it (Schlick's approximation), and
// the law of reflection and Snell's law for unit vectors pointing away from the surface.
#pragma once

#include "core/math.h"

#include <optional>

namespace penumbra {

// (1 - cos)^5, the weight of (1 - F0) in Schlick's approximation.
inline float schlickWeight(float cosTheta) {
    const float m = glm::clamp(1.0f - cosTheta, 0.0f, 1.0f);
    const float m2 = m * m;
    return m2 * m2 * m;
}

// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", as the glTF 2.0 spec
// writes it (appendix B, "Fresnel"): F = F0 + (1 - F0) (1 - |cos|)^5.
inline Color fresnelSchlick(const Color& f0, float cosTheta) {
    return f0 + (Color(1.0f) - f0) * schlickWeight(std::abs(cosTheta));
}

// Normal-incidence reflectance of a dielectric, KHR_materials_ior ("Implementation") with the
// KHR_materials_specular colour: ((ior - 1) / (ior + 1))^2 * specularColor, clamped to 1.
inline Color dielectricF0(float ior, const Color& specularColor) {
    return glm::min(sqr((ior - 1.0f) / (ior + 1.0f)) * specularColor, Color(1.0f));
}

// Schlick's approximation for a dielectric seen from either side. eta = n_t / n_i is the relative
// IOR across the interface for light arriving at cosine cosI (> 0) to the microfacet normal.
// Schlick's formula holds for incidence from the optically thinner side; from the denser side
// (eta < 1) it is evaluated at the cosine on the thinner side (the refraction cosine), as the
// exact Fresnel equations are unchanged when theta_i and theta_t swap (Born and Wolf,
// "Principles of Optics", section 1.5.2). This makes reflection and refraction use the same F
// from both sides (so refraction stays reciprocal), and beyond the critical angle F = 1 (total
// internal reflection).
inline Color fresnelDielectric(const Color& f0, float cosI, float eta) {
    if (eta >= 1.0f)
        return fresnelSchlick(f0, cosI);
    const float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f)
        return Color(1.0f);
    return fresnelSchlick(f0, std::sqrt(1.0f - sin2T));
}

// Mirror direction of w about the unit normal n.
inline Vec3 reflect(const Vec3& w, const Vec3& n) {
    return 2.0f * glm::dot(w, n) * n - w;
}

// Refraction of w (pointing away from the surface, dot(w, n) > 0) through an interface with unit
// normal n and relative IOR eta = n_t / n_i, by Snell's law (pbrt-v4 section 9.3.2). Returns
// nothing on total internal reflection.
inline std::optional<Vec3> refract(const Vec3& w, const Vec3& n, float eta) {
    const float cosI = glm::dot(w, n);
    const float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f)
        return std::nullopt;
    const float cosT = safeSqrt(1.0f - sin2T);
    return glm::normalize(-w / eta + (cosI / eta - cosT) * n);
}

}  // namespace penumbra
