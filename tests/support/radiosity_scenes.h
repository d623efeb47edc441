// Scenes and checks shared by the radiosity solvers' tests: the closed box of the furnace tests,
// a ceiling light, loading a built scene through the real glTF loader.
#pragma once

#include "core/math.h"
#include "core/scene.h"
#include "radiosity/solve_progress.h"
#include "tests/support/gltf_builder.h"

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace penumbra::test {

// Writes the built scene to a temporary folder named after `name` and loads it as the command
// line does.
std::unique_ptr<Scene> loadBuiltScene(const GltfBuilder& builder, const std::string& name);

// The cube [-h, h]^3 as six quads, all counter-clockwise seen from inside; `floor` gets the
// material of the face y = -h, the others `walls`.
void addClosedBox(GltfBuilder& scene, int walls, int floor, float h = 1.0f);

// A closed room whose ceiling is one mirror (just under addClosedBox's ceiling, h = 1, albedo
// 0.75, 0.7, 0.6), lit by a 0.4 m square lamp 0.1 m under it that faces down (20 cd/m²): no
// light reaches the mirror from the lamp, but the lit floor and walls see themselves in it
// (L D S D). The camera looks along -z from near the far wall. With a `roughness`, the mirror
// (a metal of base colour 0.95) is that rough.
void addMirrorCeilingRoom(GltfBuilder& scene, float roughness = 0.0f);

// A closed room lit mostly through a mirror: addClosedBox's six quads (h = 1, albedo 0.75, 0.7,
// 0.6), a mirror of 0.6 x 0.6 m just under the ceiling facing down, and a 0.3 x 0.3 m light of
// 20 cd/m² below it facing up at the mirror, which catches most of its light and sends it down.
// A perspective camera at the middle of the front wall looks at the back wall (-Z).
void addMirrorRoom(GltfBuilder& scene);

// The closed furnace box: addClosedBox's six quads (h = 1), one material emitting Le = 1 and
// reflecting rho. Built and loaded as loadBuiltScene() does.
std::unique_ptr<Scene> furnaceBox(float rho, const std::string& name);

// The closed furnace box with every wall twice, in the same place (radiosity/coincident_faces.h):
// addClosedBox's six quads (h = 1), one material emitting Le = 1 and reflecting rho, then the same
// quads again, split along the other diagonal (each of the second box's triangles lies over parts
// of two of the first's) or, if `flipped`, wound the other way (facing outward). Built and loaded
// as loadBuiltScene() does.
std::unique_ptr<Scene> doubledFurnaceBox(float rho, bool flipped, const std::string& name);

// The largest relative error |L.g / expected - 1| of radiance(mesh, triangle, b, front) over four
// points inside every triangle of the scene, on the side facing the origin (the inside of a box
// around it).
double worstInsideError(
    const Scene& scene, double expected,
    const std::function<Color(uint32_t mesh, uint32_t triangle, Vec3 b, bool front)>& radiance);

// A square emitter of side 2s centred at height y, facing down (counter-clockwise from below),
// emitting Le cd/m², reflecting nothing.
void addCeilingLight(GltfBuilder& scene, float s, float y, float Le);

// A block [-0.6, 0.2] x [-1, -0.4] x [-0.2, 0.6] standing on the floor of the unit closed box, its
// five visible faces facing outward (no bottom).
void addFloorBlock(GltfBuilder& scene, int material);

// The box [lo, hi] as one mesh of quads with four vertices each (as exporters write flat shaded
// solids: vertices repeated at every hard edge), facing outward or inward: a closed solid
// (sealed_interiors.h); its first `faces` of six quads only (the last, y = lo.y, left out of
// five), an open one.
struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<uint32_t> indices;
};
TriangleMesh solidBox(const Vec3& lo, const Vec3& hi, bool inward = false, int faces = 6);
void addSolidBox(GltfBuilder& scene, const Vec3& lo, const Vec3& hi, int material,
                 bool inward = false, int faces = 6);

// A point light of I candela at height h over a floor [-half, half]^2 (reflectance rho, facing
// up) in the plane y = 0, and nothing else.
struct PointLightOverFloor {
    float rho = 0.5f, intensity = 10.0f, height = 1.0f, half = 2.0f;

    void build(GltfBuilder& scene) const;
    // The floor's reflected flux divided by pi, sum A L = rho I Omega / pi (cd), with Omega the
    // solid angle of the floor seen from the light.
    double reflectedPower() const;
};

// The closed box of addClosedBox (half-size h) whose floor alone emits, Le cd/m², and every face
// reflects rho: the first reflection of the floor's light, the direct part of the solution, is in
// closed form on the ceiling (y = h, facing down), parallel to the floor.
struct EmittingFloorBox {
    float rho = 0.5f, Le = 1.0f, h = 1.0f;

    // The scene, built and loaded as loadBuiltScene() does.
    std::unique_ptr<Scene> load(const std::string& name) const;
    // The floor's direct light reflected at the ceiling point (x, h, z), |x|, |z| <= h (cd/m²):
    // rho Le F(x -> floor), F by superposition of the four rectangles of the floor around the
    // point's foot (Howell's catalogue B-3: a differential element on the normal through a
    // corner of a parallel rectangle).
    double ceilingDirect(double x, double z) const;
    // The largest relative error of direct(mesh, triangle, b), a solver's direct part at a
    // point of the ceiling (scene mesh 5), against ceilingDirect(), over points inside both of
    // the ceiling's triangles.
    double worstCeilingPoint(
        const Scene& scene,
        const std::function<Color(uint32_t mesh, uint32_t triangle, Vec3 b)>& direct) const;
};

// A SolveProgress that keeps what a solver reported: each stage's name, announced total, the
// work advanced during it and its summary, in order.
struct RecordedProgress : SolveProgress {
    struct Stage {
        std::string name, summary;
        uint64_t total = 0, done = 0;
        bool ended = false;
    };
    std::vector<Stage> stages;
    std::mutex mutex;  // advance() may come from several threads

    void beginStage(const std::string& name, uint64_t total) override {
        stages.push_back({name, "", total, 0, false});
    }
    void advance(uint64_t work) override {
        const std::lock_guard<std::mutex> lock(mutex);
        stages.back().done += work;
    }
    void endStage(const std::string& summary) override {
        stages.back().summary = summary;
        stages.back().ended = true;
    }
    // The first stage whose name starts with `prefix`, or null.
    const Stage* find(const std::string& prefix) const {
        for (const Stage& s : stages) {
            if (s.name.rfind(prefix, 0) == 0)
                return &s;
        }
        return nullptr;
    }
};

// Finite and non-negative in every channel.
bool validRadiance(const Color& L);

}  // namespace penumbra::test
