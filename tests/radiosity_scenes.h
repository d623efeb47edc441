// Scenes and checks shared by the radiosity solvers' tests: the closed box of the furnace tests,
// a ceiling light, loading a built scene through the real glTF loader.
#pragma once

#include "core/math.h"
#include "core/scene.h"
#include "tests/gltf_builder.h"

#include <memory>
#include <string>

namespace penumbra::test {

// Writes the built scene to a temporary folder named after `name` and loads it as the command
// line does.
std::unique_ptr<Scene> loadBuiltScene(const GltfBuilder& builder, const std::string& name);

// The cube [-h, h]^3 as six quads, all counter-clockwise seen from inside; `floor` gets the
// material of the face y = -h, the others `walls`.
void addClosedBox(GltfBuilder& scene, int walls, int floor, float h = 1.0f);

// A square emitter of side 2s centred at height y, facing down (counter-clockwise from below),
// emitting Le cd/m², reflecting nothing.
void addCeilingLight(GltfBuilder& scene, float s, float y, float Le);

// A block [-0.6, 0.2] x [-1, -0.4] x [-0.2, 0.6] standing on the floor of the unit closed box, its
// five visible faces facing outward (no bottom).
void addFloorBlock(GltfBuilder& scene, int material);

// A point light of I candela at height h over a floor [-half, half]^2 (reflectance rho, facing
// up) in the plane y = 0, and nothing else.
struct PointLightOverFloor {
    float rho = 0.5f, intensity = 10.0f, height = 1.0f, half = 2.0f;

    void build(GltfBuilder& scene) const;
    // The floor's reflected flux divided by pi, sum A L = rho I Omega / pi (cd), with Omega the
    // solid angle of the floor seen from the light.
    double reflectedPower() const;
};

// Finite and non-negative in every channel.
bool validRadiance(const Color& L);

}  // namespace penumbra::test
