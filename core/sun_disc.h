// The sun as a light: a disc of uniform radiance at infinity (limb darkening ignored), so that
// shadows have their penumbra. Its light on a plane facing it is the direct normal illuminance
// E_n the user gives (lux, as a weather file or a daylight standard states it); its radiance is
// E_n over the disc's solid angle. It is drawn by the environment light (core/environment_light.h),
// which samples it as part of the sky.
//
// Precision: the disc is 0.53 degrees across, so 1 - cos r is 1.1e-5, and a float cosine near 1
// moves in steps of 6e-8 (0.5 % of it). The disc is therefore described by its cap height
// h = 1 - cos r computed as 2 sin²(r / 2), sampled by drawing h directly, and tested by the sine
// of the angle from its centre (a cross product, exact to float's relative precision), never by
// comparing a cosine with cos r: a test by cosines lost 0.2 % of the sampled directions at the rim.
#pragma once

#include "core/math.h"

#include <cmath>
#include <numbers>

namespace penumbra {

// Half the sun's mean apparent diameter of 0.53 degrees, in radians.
inline constexpr float kSunAngularRadius = 0.5f * 0.53f * kPi / 180.0f;

struct SunDisc {
    Vec3 direction{0.0f, 1.0f, 0.0f};      // unit world direction towards the disc's centre
    float directNormalIlluminance = 0.0f;  // E_n, lux, >= 0
    float angularRadius = kSunAngularRadius;

    // 1 - cos r, the height of the disc's cap on the unit sphere.
    float capHeight() const {
        const double s = std::sin(0.5 * double(angularRadius));
        return float(2.0 * s * s);
    }
    // The disc's solid angle, 2 pi (1 - cos r).
    float solidAngle() const { return float(2.0 * std::numbers::pi * double(capHeight())); }
    // The disc's radiance, cd/m²: E_n = L times the solid angle (the cosine over a disc this
    // small is 1 within 1e-5).
    float radiance() const { return directNormalIlluminance / solidAngle(); }

    // Whether unit direction `towards` is inside the disc: sin² of its angle from the centre,
    // |towards x direction|², at most sin² r = h (2 - h), on the sun's side.
    bool contains(const Vec3& towards) const {
        const float h = capHeight();
        const Vec3 c = glm::cross(towards, direction);
        return glm::dot(towards, direction) > 0.0f && glm::dot(c, c) <= h * (2.0f - h);
    }
    // A direction uniform over the disc (density 1 / solidAngle()): the cap height below the
    // direction uniform in [0, h], as in uniform cone sampling (pbrt-v4's SampleUniformCone),
    // with sin theta from it rather than from cos theta.
    Vec3 sample(Vec2 u) const {
        const float t = u.x * capHeight();
        const float sinTheta = std::sqrt(t * (2.0f - t));
        const float phi = 2.0f * kPi * u.y;
        const Vec3 local(sinTheta * std::cos(phi), sinTheta * std::sin(phi), 1.0f - t);
        return Frame::fromNormal(direction).toWorld(local);
    }
};

}  // namespace penumbra
