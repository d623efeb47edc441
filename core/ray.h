// Rays and robust ray origins.
#pragma once

#include "core/math.h"

#include <cmath>
#include <limits>

namespace penumbra {

struct Ray {
    Vec3 o;
    Vec3 d;  // unit length in penumbra's tracers
    float tMax = std::numeric_limits<float>::infinity();
};

// Bound on the relative rounding error of n floating-point operations,
// gamma_n = n u / (1 - n u) with u = 2^-24 (Higham 2002; pbrt-v3 section 3.9.1, Eq. 3.2).
constexpr float roundingGamma(int n) {
    constexpr float kUnitRoundoff = std::numeric_limits<float>::epsilon() * 0.5f;
    return (n * kUnitRoundoff) / (1.0f - n * kUnitRoundoff);
}

// Conservative absolute error of a point reconstructed from barycentrics as
// b0 p0 + b1 p1 + b2 p2 (pbrt-v3 section 3.9.5, Eq. 3.14), plus the same relative bound on the
// largest vertex magnitude: the ray-triangle test (Embree's, not ours) works with all of the
// triangle's coordinates, so a point whose own coordinate is exactly 0 (a wall on the plane
// x = 0) still needs an offset of the size of that test's rounding. Both terms scale with the
// magnitude of the vertices, so a scene at 1 mm and one at 1e5 m are treated alike.
inline Vec3 barycentricPointError(const Vec3& b, const Vec3& p0, const Vec3& p1, const Vec3& p2) {
    const Vec3 largest = glm::max(glm::abs(p0), glm::max(glm::abs(p1), glm::abs(p2)));
    const float magnitude = glm::max(largest.x, glm::max(largest.y, largest.z));
    return roundingGamma(7) *
           (glm::abs(b.x * p0) + glm::abs(b.y * p1) + glm::abs(b.z * p2) + Vec3(magnitude));
}

// Moves p off its surface, along the geometric normal n towards the side of direction w, by the
// projection of the error box pError onto n, then one ulp further outwards so that rounding in
// the addition cannot pull it back (pbrt-v3 section 3.9.5, "Robust Spawned Ray Origins").
inline Vec3 offsetRayOrigin(const Vec3& p, const Vec3& pError, const Vec3& n, const Vec3& w) {
    const float d = glm::dot(glm::abs(n), pError);
    Vec3 offset = d * n;
    if (glm::dot(w, n) < 0.0f)
        offset = -offset;
    Vec3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f) {
            po[i] = std::nextafter(po[i], std::numeric_limits<float>::infinity());
        } else if (offset[i] < 0.0f) {
            po[i] = std::nextafter(po[i], -std::numeric_limits<float>::infinity());
        }
    }
    return po;
}

// Fraction of the distance to a target point that a shadow ray may travel, so that it does not
// hit the surface the target lies on (pbrt-v3's ShadowEpsilon).
inline constexpr float kShadowEpsilon = 1e-4f;

}  // namespace penumbra
