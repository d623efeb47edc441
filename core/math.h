// Numeric types and small geometric helpers shared by every module.
// GLM is the only third-party library visible in core/ headers, and only through these aliases,
// so precision can be changed in one place (as pbrt's Float).
#pragma once

#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

namespace penumbra {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using Mat3 = glm::mat3;
using Mat4 = glm::mat4;
using IVec2 = glm::ivec2;

// Linear-sRGB triple. For radiance it is in cd/m² per channel, for intensity in cd, for
// illuminance in lux: penumbra works in photometric units throughout (CONTRIBUTING.md, "Units").
using Color = glm::vec3;

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInv2Pi = 1.0f / (2.0f * kPi);
inline constexpr float kInv4Pi = 1.0f / (4.0f * kPi);

// Relative luminance Y of a linear-sRGB colour (ITU-R BT.709 primaries, D65).
inline float luminance(const Color& c) {
    return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

inline float maxComponent(const Color& c) {
    return glm::max(c.r, glm::max(c.g, c.b));
}

inline bool isFinite(const Color& c) {
    return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

inline float sqr(float x) {
    return x * x;
}

// sqrt that tolerates tiny negative arguments produced by rounding.
inline float safeSqrt(float x) {
    return std::sqrt(glm::max(x, 0.0f));
}

// Orthonormal basis around a unit normal n, branchless construction of
// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), Listing 3.
struct Frame {
    Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

    static Frame fromNormal(const Vec3& n) {
        const float sign = std::copysign(1.0f, n.z);
        const float a = -1.0f / (sign + n.z);
        const float b = n.x * n.y * a;
        Frame f;
        f.n = n;
        f.s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        f.t = Vec3(b, sign + n.y * n.y * a, -n.y);
        return f;
    }

    // Basis from a normal and an approximate tangent (Gram-Schmidt); falls back to fromNormal
    // when the tangent is parallel to the normal or not finite.
    static Frame fromNormalTangent(const Vec3& n, const Vec3& tangent) {
        const Vec3 s = tangent - n * glm::dot(n, tangent);
        const float len2 = glm::dot(s, s);
        if (!(len2 > 1e-12f) || !std::isfinite(len2))
            return fromNormal(n);
        Frame f;
        f.n = n;
        f.s = s / std::sqrt(len2);
        f.t = glm::cross(n, f.s);
        return f;
    }

    Vec3 toLocal(const Vec3& v) const { return {glm::dot(v, s), glm::dot(v, t), glm::dot(v, n)}; }
    Vec3 toWorld(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Axis-aligned bounding box.
struct Bounds3 {
    Vec3 lo{INFINITY}, hi{-INFINITY};

    void extend(const Vec3& p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void extend(const Bounds3& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    Vec3 center() const { return 0.5f * (lo + hi); }
    Vec3 diagonal() const { return hi - lo; }
    float boundingRadius() const { return 0.5f * glm::length(hi - lo); }
};

}  // namespace penumbra
