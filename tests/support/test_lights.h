// Lights shared by the light tests (tests/core): an emissive triangle with what it refers to, a
// KHR_lights_punctual description, and comparing colours channel by channel.
#pragma once

#include "core/material.h"
#include "core/scene_description.h"
#include "core/texture.h"
#include "core/triangle_light.h"

#include <memory>
#include <numbers>
#include <optional>
#include <vector>

namespace penumbra::test {

inline constexpr double kPiD = std::numbers::pi;

// |a - b| / |b|, with |b| floored at 1e-30.
double relativeError(double a, double b);

// Expects every channel of `actual` within `tolerance` of `expected`, relative to it.
void expectColorNear(const Color& actual, const Color& expected, double tolerance);

// An emissive triangle with the mesh, material and textures it refers to. TriangleLight keeps
// references to them, so an Emitter is built in place and never moved.
struct Emitter {
    Mesh mesh;
    Material material;
    std::vector<Texture> textures;
    std::optional<TriangleLight> light;

    Emitter(const Emitter&) = delete;
    Emitter& operator=(const Emitter&) = delete;
    Emitter() = default;

    const Vec3& vertex(int i) const { return mesh.positions[mesh.triangles[0][i]]; }
    Vec3 normal() const {
        return glm::normalize(glm::cross(vertex(1) - vertex(0), vertex(2) - vertex(0)));
    }
};

// A scalene triangle in the plane z = 0, counter-clockwise seen from +z (its front side),
// area 0.4 m².
std::unique_ptr<Emitter> makeEmitter(bool doubleSided, Color Le = Color(2.0f, 1.0f, 0.5f));

// Gives the emitter a 2x2 emission texture of mean (0.4, 0.25, 0.6).
void addEmissionTexture(Emitter& e);

// A punctual light named "test" at (0.5, -1, 2), pointing along (1, 2, -2) / 3.
PunctualLightDesc punctual(PunctualType type, float intensity, Color color = Color(1.0f));

}  // namespace penumbra::test
