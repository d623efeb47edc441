#include "core/phase_function.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

HenyeyGreenstein::HenyeyGreenstein(float g) : g_(std::clamp(g, -kMaxAsymmetry, kMaxAsymmetry)) {}

float HenyeyGreenstein::p(float cosTheta) const {
    // (1 - g^2) / (4 pi (1 + g^2 - 2 g cos theta)^(3/2)).
    const float denominator = 1.0f + g_ * g_ - 2.0f * g_ * cosTheta;
    return (1.0f - g_ * g_) / (4.0f * kPi * denominator * std::sqrt(std::max(denominator, 0.0f)));
}

Vec3 HenyeyGreenstein::sample(const Vec3& wo, Vec2 u) const {
    // The inverse of the cumulative distribution in cos theta (pbrt-v4, Eq. 11.12); the
    // isotropic limit below |g| = 1e-3, where the closed form loses its precision.
    float cosTheta;
    if (std::abs(g_) < 1e-3f) {
        cosTheta = 1.0f - 2.0f * u.x;
    } else {
        const float s = (1.0f - g_ * g_) / (1.0f - g_ + 2.0f * g_ * u.x);
        cosTheta = (1.0f + g_ * g_ - s * s) / (2.0f * g_);
    }
    cosTheta = std::clamp(cosTheta, -1.0f, 1.0f);
    const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
    const float phi = 2.0f * kPi * u.y;
    // theta is measured from the light's direction of travel before scattering, -wi, about
    // the direction it goes on in, wo: wi = -(the direction at angle theta from wo).
    const Frame frame = Frame::fromNormal(wo);
    const Vec3 travel = sinTheta * std::cos(phi) * frame.s + sinTheta * std::sin(phi) * frame.t +
                        cosTheta * frame.n;
    return -travel;
}

}  // namespace penumbra
