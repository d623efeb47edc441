// A ray's hit on a surface, with everything shading needs.
#pragma once

#include "core/math.h"

#include <array>
#include <cstdint>

namespace penumbra {

struct SurfaceHit {
    Vec3 p;       // world-space position, reconstructed from barycentrics
    Vec3 pError;  // conservative absolute error bound of p (core/ray.h)
    Vec3 ng;      // unit geometric normal on the FRONT side (counter-clockwise winding)
    Vec3 ns;      // unit interpolated shading normal (before normal mapping), same side as ng
    Vec4 tangent{0.0f};        // interpolated tangent and handedness, or zero
    std::array<Vec2, 2> uv{};  // TEXCOORD_0, TEXCOORD_1
    Vec3 barycentric;          // weights of the triangle's vertices 0, 1, 2
    float t = 0.0f;            // ray parameter of the hit
    uint32_t mesh = 0;
    uint32_t triangle = 0;
    int material = -1;

    // Whether the ray arrived from the front side.
    bool frontFace(const Vec3& rayDirection) const { return glm::dot(rayDirection, ng) < 0.0f; }
};

}  // namespace penumbra
