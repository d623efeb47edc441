#include "tests/support/radiosity_scenes.h"

#include "core/gltf_loader.h"
#include "tests/support/cli_runner.h"

#include <algorithm>
#include <cmath>

namespace penumbra::test {

std::unique_ptr<Scene> loadBuiltScene(const GltfBuilder& builder, const std::string& name) {
    TempDir dir(name);
    builder.write(dir.file("scene.gltf"));
    return std::make_unique<Scene>(loadGltf(dir.file("scene.gltf")));
}

void addMirrorRoom(GltfBuilder& scene) {
    const int walls = scene.addMaterial({.baseColor = Color(0.75f, 0.7f, 0.6f)});
    addClosedBox(scene, walls, walls);
    const int mirror = scene.addMaterial(
        {.baseColor = Color(0.95f), .lambertian = false, .metallic = 1.0f, .roughness = 0.0f});
    constexpr float m = 0.3f, y = 0.97f;
    scene.addQuad({-m, y, -m}, {m, y, -m}, {m, y, m}, {-m, y, m}, mirror);  // faces down
    const int lamp = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 20.0f});
    constexpr float s = 0.15f, h = 0.85f;
    scene.addQuad({-s, h, -s}, {-s, h, s}, {s, h, s}, {s, h, -s}, lamp);  // faces up
    scene.setPerspectiveCamera({0.0f, -0.2f, 0.99f}, {0.0f, 0.0f, 0.0f, 1.0f}, 1.4f);
}

void addMirrorCeilingRoom(GltfBuilder& scene, float roughness) {
    const int walls = scene.addMaterial({.baseColor = Color(0.75f, 0.7f, 0.6f)});
    addClosedBox(scene, walls, walls);
    const int mirror = scene.addMaterial(
        {.baseColor = Color(0.95f), .lambertian = false, .metallic = 1.0f, .roughness = roughness});
    constexpr float m = 1.0f, y = 0.99f;
    scene.addQuad({-m, y, -m}, {m, y, -m}, {m, y, m}, {-m, y, m}, mirror);  // faces down
    const int lamp = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 20.0f});
    constexpr float s = 0.2f, h = 0.9f;
    scene.addQuad({-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}, lamp);  // faces down
    scene.setPerspectiveCamera({0.0f, -0.3f, 0.99f}, {0.0f, 0.0f, 0.0f, 1.0f}, 1.4f);
}

void addClosedBox(GltfBuilder& scene, int walls, int floor, float h) {
    const Vec3 c[8] = {{-h, -h, -h}, {h, -h, -h}, {h, h, -h}, {-h, h, -h},
                       {-h, -h, h},  {h, -h, h},  {h, h, h},  {-h, h, h}};
    scene.addQuad(c[0], c[1], c[2], c[3], walls);  // z = -h, faces +z
    scene.addQuad(c[5], c[4], c[7], c[6], walls);  // z = +h, faces -z
    scene.addQuad(c[4], c[0], c[3], c[7], walls);  // x = -h, faces +x
    scene.addQuad(c[1], c[5], c[6], c[2], walls);  // x = +h, faces -x
    scene.addQuad(c[4], c[5], c[1], c[0], floor);  // y = -h, faces +y
    scene.addQuad(c[3], c[2], c[6], c[7], walls);  // y = +h, faces -y
}

std::unique_ptr<Scene> furnaceBox(float rho, const std::string& name) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(rho), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    return loadBuiltScene(builder, name);
}

std::unique_ptr<Scene> doubledFurnaceBox(float rho, bool flipped, const std::string& name) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(rho), .emissive = Color(1.0f), .emissiveStrength = 1.0f});
    addClosedBox(builder, wall, wall);
    const float h = 1.0f;
    const Vec3 c[8] = {{-h, -h, -h}, {h, -h, -h}, {h, h, -h}, {-h, h, -h},
                       {-h, -h, h},  {h, -h, h},  {h, h, h},  {-h, h, h}};
    // addClosedBox's quads, starting at their second corner (the other diagonal), or reversed.
    const int quads[6][4] = {{0, 1, 2, 3}, {5, 4, 7, 6}, {4, 0, 3, 7},
                             {1, 5, 6, 2}, {4, 5, 1, 0}, {3, 2, 6, 7}};
    for (const auto& q : quads) {
        if (flipped)
            builder.addQuad(c[q[3]], c[q[2]], c[q[1]], c[q[0]], wall);
        else
            builder.addQuad(c[q[1]], c[q[2]], c[q[3]], c[q[0]], wall);
    }
    return loadBuiltScene(builder, name);
}

double worstInsideError(
    const Scene& scene, double expected,
    const std::function<Color(uint32_t mesh, uint32_t triangle, Vec3 b, bool front)>& radiance) {
    double worst = 0.0;
    for (uint32_t m = 0; m < scene.meshes().size(); ++m) {
        for (uint32_t t = 0; t < scene.meshes()[m].triangles.size(); ++t) {
            for (const Vec3& b : {Vec3(1.0f / 3.0f), Vec3(0.6f, 0.2f, 0.2f), Vec3(0.2f, 0.6f, 0.2f),
                                  Vec3(0.2f, 0.2f, 0.6f)}) {
                const SurfaceHit x = scene.surfaceAt(m, t, b);
                const bool front = glm::dot(x.ng, -x.p) > 0.0f;  // the side facing the origin
                const Color L = radiance(m, t, b, front);
                worst = std::max(worst, std::abs(L.g / expected - 1.0));
            }
        }
    }
    return worst;
}

void addCeilingLight(GltfBuilder& scene, float s, float y, float Le) {
    const int light = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = Le});
    scene.addQuad({-s, y, -s}, {s, y, -s}, {s, y, s}, {-s, y, s}, light);
}

void addFloorBlock(GltfBuilder& scene, int material) {
    const Vec3 b[8] = {{-0.6f, -1, -0.2f},    {0.2f, -1, -0.2f},   {0.2f, -0.4f, -0.2f},
                       {-0.6f, -0.4f, -0.2f}, {-0.6f, -1, 0.6f},   {0.2f, -1, 0.6f},
                       {0.2f, -0.4f, 0.6f},   {-0.6f, -0.4f, 0.6f}};
    scene.addQuad(b[1], b[0], b[3], b[2], material);  // z = -0.2, faces -z
    scene.addQuad(b[4], b[5], b[6], b[7], material);  // z = 0.6, faces +z
    scene.addQuad(b[0], b[4], b[7], b[3], material);  // x = -0.6, faces -x
    scene.addQuad(b[5], b[1], b[2], b[6], material);  // x = 0.2, faces +x
    scene.addQuad(b[3], b[7], b[6], b[2], material);  // y = -0.4, faces +y
}

TriangleMesh solidBox(const Vec3& lo, const Vec3& hi, bool inward, int faces) {
    const Vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                       {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                       {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    // Counter-clockwise seen from outside.
    const int quads[6][4] = {{1, 0, 3, 2}, {4, 5, 6, 7}, {0, 4, 7, 3},
                             {5, 1, 2, 6}, {3, 7, 6, 2}, {0, 1, 5, 4}};
    const std::array<uint32_t, 6> outwardOrder{0, 1, 2, 0, 2, 3}, inwardOrder{0, 2, 1, 0, 3, 2};
    TriangleMesh box;
    for (int f = 0; f < faces; ++f) {
        const uint32_t base = static_cast<uint32_t>(box.positions.size());
        for (const int k : quads[f])
            box.positions.push_back(c[k]);
        for (const uint32_t i : inward ? inwardOrder : outwardOrder)
            box.indices.push_back(base + i);
    }
    return box;
}

void addSolidBox(GltfBuilder& scene, const Vec3& lo, const Vec3& hi, int material, bool inward,
                 int faces) {
    const TriangleMesh box = solidBox(lo, hi, inward, faces);
    scene.addMesh(box.positions, box.indices, material);
}

void PointLightOverFloor::build(GltfBuilder& scene) const {
    const int floor = scene.addMaterial({.baseColor = Color(rho)});
    scene.addQuad({-half, 0, -half}, {-half, 0, half}, {half, 0, half}, {half, 0, -half}, floor);
    scene.addLight({.type = "point", .intensity = intensity, .position = {0, height, 0}});
}

double PointLightOverFloor::reflectedPower() const {
    // Solid angle of a rectangle 2a x 2b seen from height h above its centre:
    // 4 atan(a b / (h sqrt(h^2 + a^2 + b^2))).
    const double h = height, a = half;
    const double Omega = 4.0 * std::atan(a * a / (h * std::sqrt(h * h + 2.0 * a * a)));
    return rho * intensity * Omega / kPi;
}

std::unique_ptr<Scene> EmittingFloorBox::load(const std::string& name) const {
    GltfBuilder scene;
    const int walls = scene.addMaterial({.baseColor = Color(rho)});
    const int floor = scene.addMaterial(
        {.baseColor = Color(rho), .emissive = Color(1.0f), .emissiveStrength = Le});
    addClosedBox(scene, walls, floor, h);
    return loadBuiltScene(scene, name);
}

double EmittingFloorBox::worstCeilingPoint(
    const Scene& scene,
    const std::function<Color(uint32_t mesh, uint32_t triangle, Vec3 b)>& direct) const {
    constexpr uint32_t kCeiling = 5;  // the face y = +h of addClosedBox
    const Mesh& ceiling = scene.meshes()[kCeiling];
    double worst = 0.0;
    for (uint32_t t = 0; t < ceiling.triangles.size(); ++t) {
        for (const Vec3 b : {Vec3(1.0f / 3.0f), Vec3(0.6f, 0.2f, 0.2f), Vec3(0.2f, 0.6f, 0.2f),
                             Vec3(0.2f, 0.2f, 0.6f), Vec3(0.45f, 0.45f, 0.1f)}) {
            const auto& v = ceiling.triangles[t];
            const Vec3 p = b.x * ceiling.positions[v[0]] + b.y * ceiling.positions[v[1]] +
                           b.z * ceiling.positions[v[2]];
            const double expected = ceilingDirect(p.x, p.z);
            worst = std::max(worst, std::abs(direct(kCeiling, t, b).g / expected - 1.0));
        }
    }
    return worst;
}

double EmittingFloorBox::ceilingDirect(double x, double z) const {
    // Howell B-3 with X = a / c, Y = b / c: F = 1/(2 pi) [X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2))
    // + Y / sqrt(1 + Y^2) atan(X / sqrt(1 + Y^2))], for the floor's a x b rectangles at c = 2h.
    const double c = 2.0 * h;
    double F = 0.0;
    for (const double a : {h - x, h + x}) {
        for (const double b : {h - z, h + z}) {
            const double X = a / c, Y = b / c;
            const double sX = std::sqrt(1.0 + X * X), sY = std::sqrt(1.0 + Y * Y);
            F += (X / sX * std::atan(Y / sX) + Y / sY * std::atan(X / sY)) / (2.0 * kPi);
        }
    }
    return static_cast<double>(rho) * Le * F;
}

bool validRadiance(const Color& L) {
    return isFinite(L) && L.r >= 0.0f && L.g >= 0.0f && L.b >= 0.0f;
}

}  // namespace penumbra::test
