#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace penumbra::test {

double relativeError(double a, double b) {
    return std::abs(a - b) / std::max(std::abs(b), 1e-30);
}

void expectColorNear(const Color& actual, const Color& expected, double tolerance) {
    for (int i = 0; i < 3; ++i)
        EXPECT_LE(relativeError(actual[i], expected[i]), tolerance)
            << "channel " << i << ": " << actual[i] << " vs " << expected[i];
}

std::unique_ptr<Emitter> makeEmitter(bool doubleSided, Color Le) {
    auto e = std::make_unique<Emitter>();
    e->mesh.name = "emitter";
    e->mesh.positions = {Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f), Vec3(0.3f, 0.8f, 0.0f)};
    e->mesh.triangles = {glm::uvec3(0, 1, 2)};
    e->material.emissive = Le;
    e->material.doubleSided = doubleSided;
    e->light.emplace(e->mesh, 0, e->material, e->textures);
    return e;
}

void addEmissionTexture(Emitter& e) {
    e.textures.emplace_back(
        "emission", 2, 2,
        std::vector<Vec4>{Vec4(0.1f, 0.0f, 1.0f, 1.0f), Vec4(0.7f, 0.5f, 0.2f, 1.0f),
                          Vec4(0.3f, 0.5f, 0.6f, 1.0f), Vec4(0.5f, 0.0f, 0.6f, 1.0f)},
        WrapMode::Repeat, WrapMode::Repeat);
    e.material.emissiveTexture.texture = 0;
}

PunctualLightDesc punctual(PunctualType type, float intensity, Color color) {
    PunctualLightDesc desc;
    desc.name = "test";
    desc.type = type;
    desc.intensity = intensity;
    desc.color = color;
    desc.position = Vec3(0.5f, -1.0f, 2.0f);
    desc.direction = glm::normalize(Vec3(1.0f, 2.0f, -2.0f));
    return desc;
}

}  // namespace penumbra::test
