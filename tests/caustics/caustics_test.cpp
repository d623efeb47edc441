// The caustic photon map (caustics/): analytic caustics of a point, an area and a directional
// light in a plane mirror against the mirror image of the light; the storage rules (no photon
// without an S vertex, none on a one-sided back face, thin glass is transparency, not S); energy
// (a closed box with a glass and a mirror sphere stores exactly the power that hits the spheres);
// determinism across thread counts; settings refused with their key. Fixed seeds; every
// tolerance says where it comes from.
#include "caustics/caustic_map.h"
#include "caustics/progressive_caustics.h"
#include "core/errors.h"
#include "core/ray.h"
#include "core/scene.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {
namespace {

constexpr double kPiD = std::numbers::pi;

// Scenes are built as a SceneDescription directly (the glTF builder has no transmission or
// volume materials): world space, counter-clockwise = front.
class SceneBuilder {
  public:
    int addMaterial(const Material& m) {
        desc_.materials.push_back(m);
        return static_cast<int>(desc_.materials.size()) - 1;
    }
    void addMesh(std::vector<Vec3> positions, std::vector<glm::uvec3> triangles, int material) {
        Mesh mesh;
        mesh.name = "mesh" + std::to_string(desc_.meshes.size());
        mesh.material = material;
        mesh.positions = std::move(positions);
        mesh.triangles = std::move(triangles);
        desc_.meshes.push_back(std::move(mesh));
    }
    void addQuad(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, int material) {
        addMesh({p0, p1, p2, p3}, {glm::uvec3(0, 1, 2), glm::uvec3(0, 2, 3)}, material);
    }
    // An icosphere (the icosahedron subdivided `levels` times, vertices on the sphere), facing
    // outward. Returns the smallest distance from the centre to a face's plane.
    float addSphere(const Vec3& center, float radius, int material, bool split = false,
                    int levels = 3) {
        const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
        std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                               {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                               {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
        std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                     {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                     {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                     {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
        for (Vec3& p : v)
            p = glm::normalize(p);
        for (int level = 0; level < levels; ++level) {
            std::map<std::pair<uint32_t, uint32_t>, uint32_t> middle;
            const auto mid = [&](uint32_t a, uint32_t b) {
                const auto key = std::minmax(a, b);
                const auto it = middle.find(key);
                if (it != middle.end())
                    return it->second;
                v.push_back(glm::normalize(v[a] + v[b]));
                return middle[key] = static_cast<uint32_t>(v.size() - 1);
            };
            std::vector<glm::uvec3> next;
            for (const glm::uvec3& tri : f) {
                const uint32_t a = mid(tri.x, tri.y), b = mid(tri.y, tri.z), c = mid(tri.z, tri.x);
                next.insert(next.end(), {{tri.x, a, c}, {tri.y, b, a}, {tri.z, c, b}, {a, b, c}});
            }
            f = std::move(next);
        }
        float inner = radius;
        for (const glm::uvec3& tri : f) {
            const Vec3 n = glm::normalize(glm::cross(v[tri.y] - v[tri.x], v[tri.z] - v[tri.x]));
            EXPECT_GT(glm::dot(n, v[tri.x]), 0.0f);  // outward winding
            inner = std::min(inner, radius * glm::dot(n, v[tri.x]));
        }
        for (Vec3& p : v)
            p = center + radius * p;
        if (!split) {
            addMesh(std::move(v), std::move(f), material);
            return inner;
        }
        // Two meshes, the faces whose centroids lie at x < centre and the others, each with
        // only its own vertices (so each has its own, smaller bounding sphere).
        for (const bool low : {true, false}) {
            std::vector<Vec3> positions;
            std::vector<glm::uvec3> triangles;
            std::map<uint32_t, uint32_t> remap;
            const auto index = [&](uint32_t i) {
                const auto [it, added] = remap.try_emplace(i, uint32_t(positions.size()));
                if (added)
                    positions.push_back(v[i]);
                return it->second;
            };
            for (const glm::uvec3& tri : f) {
                if (((v[tri.x].x + v[tri.y].x + v[tri.z].x) / 3.0f < center.x) == low)
                    triangles.emplace_back(index(tri.x), index(tri.y), index(tri.z));
            }
            addMesh(std::move(positions), std::move(triangles), material);
        }
        return inner;
    }
    // The six faces of the cube [-a, a]³, facing in.
    void addClosedBox(float a, int material) {
        addQuad({-a, -a, -a}, {a, -a, -a}, {a, a, -a}, {-a, a, -a}, material);  // floor, +z
        addQuad({-a, -a, a}, {-a, a, a}, {a, a, a}, {a, -a, a}, material);      // ceiling
        addQuad({-a, -a, -a}, {-a, a, -a}, {-a, a, a}, {-a, -a, a}, material);  // x = -a, +x
        addQuad({a, -a, -a}, {a, -a, a}, {a, a, a}, {a, a, -a}, material);      // x = +a
        addQuad({-a, -a, -a}, {-a, -a, a}, {a, -a, a}, {a, -a, -a}, material);  // y = -a, +y
        addQuad({-a, a, -a}, {a, a, -a}, {a, a, a}, {-a, a, a}, material);      // y = +a
    }
    void addPointLight(const Vec3& position, float intensity) {
        PunctualLightDesc light;
        light.name = "point";
        light.position = position;
        light.intensity = intensity;
        desc_.lights.push_back(light);
    }
    void addDirectionalLight(const Vec3& direction, float illuminance) {
        PunctualLightDesc light;
        light.name = "sun";
        light.type = PunctualType::Directional;
        light.direction = glm::normalize(direction);
        light.intensity = illuminance;
        desc_.lights.push_back(light);
    }
    std::unique_ptr<Scene> build() { return std::make_unique<Scene>(std::move(desc_)); }

  private:
    SceneDescription desc_;
};

Material lambertian(float rho, bool doubleSided = false) {
    Material m;
    m.baseColor = Color(rho);
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.specular = 0.0f;
    m.doubleSided = doubleSided;
    return m;
}

Material mirror() {
    Material m;
    m.baseColor = Color(1.0f);
    m.metallic = 1.0f;
    m.roughness = 0.0f;
    return m;
}

// Smooth glass: a solid (volume, no absorption) or a thin wall.
Material glass(bool thinWalled) {
    Material m;
    m.baseColor = Color(1.0f);
    m.metallic = 0.0f;
    m.roughness = 0.0f;
    m.transmission = 1.0f;
    m.ior = 1.5f;
    m.thickness = thinWalled ? 0.0f : 1.0f;
    return m;
}

Material emitter(float Le) {
    Material m = lambertian(0.0f);
    m.emissive = Color(Le);
    return m;
}

CausticSettings settings(int64_t photons, int k, float maxRadius,
                         CausticKernel kernel = CausticKernel::Cone) {
    CausticSettings s;
    s.photons = photons;
    s.k = k;
    s.maxRadius = maxRadius;
    s.kernel = kernel;
    s.seed = 1;
    return s;
}

// The caustic radiance seen from below at (x, y) on a ceiling at height z (facing down).
Color ceilingRadiance(const Scene& scene, const CausticMap& map, float x, float y, float z) {
    const Ray ray{Vec3(x, y, z - 0.5f), Vec3(0.0f, 0.0f, 1.0f)};
    const std::optional<SurfaceHit> hit = scene.intersect(ray);
    EXPECT_TRUE(hit);
    if (!hit)
        return Color(0.0f);
    EXPECT_NEAR(hit->p.z, z, 1e-4f);
    return map.radiance(*hit, scene.bsdf(*hit), -ray.d);
}

void printStats(const CausticMap& map) {
    for (const auto& [name, value] : map.stats())
        std::printf("[ stats    ] %s: %s\n", name.c_str(), value.c_str());
}

// Solid angle of the rectangle [-a, a] x [-b, b] seen from distance d above its centre.
double rectangleSolidAngle(double a, double b, double d) {
    return 4.0 * std::asin(a * b / std::sqrt((a * a + d * d) * (b * b + d * d)));
}

// A point light of I cd at height h = 1 over a horizontal perfect mirror (z = 0, 20 x 20 m) under
// a Lambertian ceiling (z = H = 2, 10 x 10 m, reflectance rho, facing down).
constexpr float kIntensity = 10.0f, kRho = 0.5f, kCeiling = 2.0f, kLightHeight = 1.0f;

std::unique_ptr<Scene> mirrorScene(const Material& ceiling, bool flipCeiling = false) {
    SceneBuilder b;
    const int m = b.addMaterial(mirror());
    const int c = b.addMaterial(ceiling);
    b.addQuad({-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, m);
    const float H = kCeiling;
    if (flipCeiling)
        b.addQuad({-5, -5, H}, {5, -5, H}, {5, 5, H}, {-5, 5, H}, c);  // facing up
    else
        b.addQuad({-5, -5, H}, {-5, 5, H}, {5, 5, H}, {5, -5, H}, c);  // facing down
    b.addPointLight(Vec3(0.0f, 0.0f, kLightHeight), kIntensity);
    return b.build();
}

// The ceiling's caustic at (x, y): the direct light of the mirror image of the point light at
// depth -h, E = I cos / d² with cos = (H + h) / d (Fresnel 1 for a metal of baseColor 1),
// reflected as rho / pi E.
double mirrorImageRadiance(const Vec2& xy) {
    const double d = std::sqrt(xy.x * xy.x + xy.y * xy.y + sqr(kCeiling + kLightHeight));
    return kRho / kPiD * kIntensity * (kCeiling + kLightHeight) / (d * d * d);
}

// The points where the estimate is compared with the closed form.
const std::array<Vec2, 5> kCeilingPoints = {Vec2(0.0f), Vec2(0.5f, 0.0f), Vec2(0.0f, -1.0f),
                                            Vec2(-1.0f, 1.0f), Vec2(1.5f, 0.5f)};

class MirrorCaustic : public testing::TestWithParam<CausticKernel> {};

// The ceiling's caustic is the mirror image's light (mirrorImageRadiance). The direct light of the
// source (10 times brighter at the centre) must not be in the map: photons without an S vertex are
// not stored.
TEST_P(MirrorCaustic, MatchesTheMirrorImageOfAPointLight) {
    const auto scene = mirrorScene(lambertian(kRho));
    const CausticMap map =
        CausticMap::build(*scene, settings(400000, 400, 1.0f, GetParam()), nullptr);
    printStats(map);

    // Every photon went light -> mirror -> ceiling: stored on the ceiling, and their total power
    // is the flux the ceiling receives from the mirror image, I times its solid angle from 3 m
    // below its centre (rounding only: every photon of the aimed mixture carries I / pdf, and
    // the photons that land are counted exactly by the Sobol net up to its stratification).
    for (const Photon& p : map.photons())
        ASSERT_NEAR(p.p.z, kCeiling, 1e-4f);
    const double expectedPower =
        kIntensity * rectangleSolidAngle(5.0, 5.0, kCeiling + kLightHeight);
    const double storedPower = luminance(map.trace().storedPower);
    std::printf("[ measured ] stored power %.6g lm, expected %.6g lm\n", storedPower,
                expectedPower);
    EXPECT_NEAR(storedPower / expectedPower, 1.0, 0.01);

    for (const Vec2& xy : kCeilingPoints) {
        const double expected = mirrorImageRadiance(xy);
        const Color L = ceilingRadiance(*scene, map, xy.x, xy.y, kCeiling);
        std::printf("[ measured ] (%.1f, %.1f): L %.5g, expected %.5g, ratio %.4f\n", xy.x, xy.y,
                    luminance(L), expected, luminance(L) / expected);
        // 400 photons per estimate: Poisson noise would be 1/sqrt(399) = 5 %; the photons'
        // Sobol stratification makes it smaller (seeds 1 to 4, all three kernels: largest
        // error 1.6 %), and the disc's curvature bias is below 0.2 %. 6 % fails a wrong cosine,
        // a wrong or missing kernel normalisation (33 to 100 %) or stored direct light (x 10).
        EXPECT_NEAR(luminance(L) / expected, 1.0, 0.06);
    }
}

INSTANTIATE_TEST_SUITE_P(Kernels, MirrorCaustic,
                         testing::Values(CausticKernel::Cone, CausticKernel::Epanechnikov,
                                         CausticKernel::Gaussian),
                         [](const testing::TestParamInfo<CausticKernel>& info) {
                             return kernelName(info.param);
                         });

// The same with a small area light (0.1 m square, Le, facing the mirror): its image irradiates
// the ceiling with E = Le A cos_s cos_r / d², both cosines (H + h) / d. The points are off the
// axis, where the emitter itself does not shadow the reflected light.
TEST(CausticMap, AreaLightInAMirror) {
    SceneBuilder b;
    const int m = b.addMaterial(mirror());
    const int c = b.addMaterial(lambertian(kRho));
    const int e = b.addMaterial(emitter(1000.0f));
    b.addQuad({-10, -10, 0}, {10, -10, 0}, {10, 10, 0}, {-10, 10, 0}, m);
    b.addQuad({-5, -5, 2}, {-5, 5, 2}, {5, 5, 2}, {5, -5, 2}, c);
    const float s = 0.05f;
    b.addQuad({-s, -s, 1}, {-s, s, 1}, {s, s, 1}, {s, -s, 1}, e);  // facing down
    const auto scene = b.build();
    const CausticMap map = CausticMap::build(*scene, settings(400000, 400, 1.0f), nullptr);
    printStats(map);
    for (const Vec2& xy : {Vec2(1.0f, 0.0f), Vec2(0.0f, -1.2f), Vec2(-1.0f, 1.0f)}) {
        const double d2 = xy.x * xy.x + xy.y * xy.y + 9.0;
        const double E = 1000.0 * sqr(2.0f * s) * (9.0 / d2) / d2;
        const double expected = kRho / kPiD * E;
        const Color L = ceilingRadiance(*scene, map, xy.x, xy.y, 2.0f);
        std::printf("[ measured ] (%.1f, %.1f): L %.5g, expected %.5g, ratio %.4f\n", xy.x, xy.y,
                    luminance(L), expected, luminance(L) / expected);
        // As for the point light, but each photon's power varies with its cosine at the
        // emitter: seeds 1 to 4 gave errors up to 3.6 %. The point-source approximation of the
        // 0.1 m emitter at 3 m is good to (0.1 / 3)² = 0.1 %.
        EXPECT_NEAR(luminance(L) / expected, 1.0, 0.06);
    }
}

// A directional light of E lux straight down on a 1 m square mirror tilted by 45 degrees: the
// reflected beam runs horizontally to a wall 3 m away (facing -x), whose irradiance inside the
// beam (|y| < 0.5, |z| < 0.354) is E.
constexpr float kSunIlluminance = 5.0f;

std::unique_ptr<Scene> tiltedMirrorScene() {
    SceneBuilder b;
    const int m = b.addMaterial(mirror());
    const int w = b.addMaterial(lambertian(kRho));
    const float h = 0.5f / std::sqrt(2.0f);
    // Normal (1, 0, 1) / sqrt(2): the points run counter-clockwise seen from it.
    b.addQuad({-h, -0.5f, h}, {h, -0.5f, -h}, {h, 0.5f, -h}, {-h, 0.5f, h}, m);
    b.addQuad({3, -2, -2}, {3, -2, 2}, {3, 2, 2}, {3, 2, -2}, w);
    b.addDirectionalLight(Vec3(0.0f, 0.0f, -1.0f), kSunIlluminance);
    return b.build();
}

// Photons are aimed at the disc the mirror's bounding sphere projects onto the light's disc.
TEST(CausticMap, DirectionalLightInATiltedMirror) {
    const auto scene = tiltedMirrorScene();
    const CausticMap map = CausticMap::build(*scene, settings(200000, 200, 0.2f), nullptr);
    printStats(map);
    for (const Vec3& p : {Vec3(0.0f), Vec3(0.0f, 0.25f, 0.1f), Vec3(0.0f, -0.2f, -0.15f)}) {
        const Ray ray{Vec3(2.5f, p.y, p.z), Vec3(1.0f, 0.0f, 0.0f)};
        const std::optional<SurfaceHit> hit = scene->intersect(ray);
        ASSERT_TRUE(hit);
        const Color L = map.radiance(*hit, scene->bsdf(*hit), -ray.d);
        const double expected = kRho / kPiD * kSunIlluminance;
        std::printf("[ measured ] (y %.2f, z %.2f): L %.5g, expected %.5g\n", p.y, p.z,
                    luminance(L), expected);
        // 200 photons per estimate; seeds 1 to 4: largest error 1.5 %.
        EXPECT_NEAR(luminance(L) / expected, 1.0, 0.06);
    }
    // Outside the beam there is no caustic.
    const Ray outside{Vec3(2.5f, 1.5f, 1.5f), Vec3(1.0f, 0.0f, 0.0f)};
    const std::optional<SurfaceHit> hit = scene->intersect(outside);
    ASSERT_TRUE(hit);
    EXPECT_EQ(luminance(map.radiance(*hit, scene->bsdf(*hit), -outside.d)), 0.0f);
}

// The mirror scene with the ceiling turned over (front face up, one-sided): the reflected photons
// arrive at its back and are not stored. Double-sided, the same surface stores them.
TEST(CausticMap, BackFacesOfOneSidedSurfacesStoreNothing) {
    const auto oneSided = mirrorScene(lambertian(kRho, false), true);
    const CausticMap none = CausticMap::build(*oneSided, settings(100000, 50, 1.0f), nullptr);
    EXPECT_EQ(none.photons().size(), 0u);
    EXPECT_GT(none.trace().aimedAtSpecular, 0u);

    const auto twoSided = mirrorScene(lambertian(kRho, true), true);
    const CausticMap some = CausticMap::build(*twoSided, settings(100000, 50, 1.0f), nullptr);
    printStats(some);
    EXPECT_GT(some.photons().size(), 10000u);
    for (const Photon& p : some.photons())
        ASSERT_EQ(p.n, Vec3(0.0f, 0.0f, -1.0f));  // the side the photon arrived from
}

// A point light 2 m over a diffuse floor with a thin glass pane at 1 m in between: the light
// that goes straight through the pane is transparency, not an S vertex, so the floor gets no
// caustic photon (the pane's mirror reflection goes up, into nothing). A solid glass slab in the
// same place refracts twice (S S) and does store photons on the floor.
TEST(CausticMap, ThinGlassIsTransparentNotSpecular) {
    const auto build = [](bool thin) {
        SceneBuilder b;
        const int floor = b.addMaterial(lambertian(kRho));
        const int pane = b.addMaterial(glass(thin));
        b.addQuad({-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}, floor);
        b.addQuad({-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}, pane);
        if (!thin)
            b.addQuad({-1, -1, 0.9f}, {-1, 1, 0.9f}, {1, 1, 0.9f}, {1, -1, 0.9f}, pane);
        b.addPointLight(Vec3(0.0f, 0.0f, 2.0f), kIntensity);
        return b.build();
    };
    const auto thin = build(true);
    const CausticMap none = CausticMap::build(*thin, settings(50000, 50, 1.0f), nullptr);
    EXPECT_EQ(none.trace().specularMeshes, 1);
    // The light is inside the pane's bounding sphere, so photons leave in every direction; the
    // pane subtends 4 asin(1/2) = 2.09 sr of 4 pi, 8300 photons, and scatters (reflects) the
    // Fresnel share of them, about 4 %: 336 measured. The rest pass straight through.
    EXPECT_GT(none.trace().aimedAtSpecular, 200u);
    EXPECT_LT(none.trace().aimedAtSpecular, 800u);
    EXPECT_EQ(none.photons().size(), 0u);

    const auto slab = build(false);
    const CausticMap some = CausticMap::build(*slab, settings(50000, 50, 1.0f), nullptr);
    printStats(some);
    // Most of the light that reaches the slab crosses both faces: (1 - F)² with F = 4 % at
    // normal incidence, more at the slab's corners (incidence up to 55 degrees).
    EXPECT_GT(some.photons().size(), some.trace().aimedAtSpecular * 8 / 10);
    for (const Photon& p : some.photons())
        ASSERT_NEAR(p.p.z, 0.0f, 1e-4f);
}

// Energy: in a closed box of Lambertian walls (facing in), everything that hits a glass sphere
// (no absorption) or a mirror sphere (Fresnel 1) leaves it and lands on a wall, where it is
// stored once; so the stored power is I times the spheres' solid angles from the light, between
// the values for the spheres through the meshes' vertices and those tangent to their faces. The
// mirror sphere is made of two meshes (its halves), whose cones from the light overlap: the
// aimed photons' density must count both cones where they overlap, or the halves' shared
// directions would be counted twice (measured: the stored power 26 % too high).
TEST(CausticMap, StoredPowerIsThePowerThatHitsTheSpecularSpheres) {
    SceneBuilder b;
    const int walls = b.addMaterial(lambertian(0.8f));
    const int g = b.addMaterial(glass(false));
    const int m = b.addMaterial(mirror());
    const float a = 2.0f;
    b.addClosedBox(a, walls);
    const Vec3 light(0.0f, 0.0f, 1.5f);
    const Vec3 glassCenter(-0.8f, 0.0f, 0.0f), mirrorCenter(0.8f, 0.0f, 0.0f);
    const float glassRadius = 0.5f, mirrorRadius = 0.4f;
    const float glassInner = b.addSphere(glassCenter, glassRadius, g);
    const float mirrorInner = b.addSphere(mirrorCenter, mirrorRadius, m, true);
    b.addPointLight(light, kIntensity);
    const auto scene = b.build();

    const auto solidAngle = [&](const Vec3& c, float r) {
        const double d = glm::distance(light, c);
        return 2.0 * kPiD * (1.0 - std::sqrt(1.0 - sqr(r / d)));
    };
    const double lower =
        kIntensity * (solidAngle(glassCenter, glassInner) + solidAngle(mirrorCenter, mirrorInner));
    const double upper = kIntensity * (solidAngle(glassCenter, glassRadius) +
                                       solidAngle(mirrorCenter, mirrorRadius));
    const CausticMap map = CausticMap::build(*scene, settings(200000, 50, 0.0f), nullptr);
    printStats(map);
    const double stored = luminance(map.trace().storedPower);
    const double emitted = luminance(map.trace().emittedPower);
    std::printf("[ measured ] stored %.6g lm, expected in [%.6g, %.6g], emitted %.6g lm\n", stored,
                lower, upper, emitted);
    EXPECT_EQ(map.trace().specularMeshes, 3);
    EXPECT_NEAR(emitted, 4.0 * kPiD * kIntensity, 1e-3);
    EXPECT_LE(stored, emitted);
    // Russian roulette at the glass (survival F or 1 - F against the lobe choice) and the
    // stratified photon positions: measured within 0.5 % of the band; 2 % allowed.
    EXPECT_GE(stored, lower * 0.98);
    EXPECT_LE(stored, upper * 1.02);
    const double fraction =
        static_cast<double>(map.photons().size()) / static_cast<double>(map.trace().shot);
    EXPECT_GT(fraction, 0.5);  // aimed photons mostly land; unaimed, 2 % would
    EXPECT_LE(fraction, 1.0);
}

// The photons depend on the seed and the photon count only, not on the thread count.
TEST(CausticMap, DeterministicWhateverTheThreadCount) {
    const auto scene = mirrorScene(lambertian(kRho));
    const auto buildWith = [&](int threads) {
        tbb::task_arena arena(threads);
        std::optional<CausticMap> map;
        arena.execute(
            [&] { map.emplace(CausticMap::build(*scene, settings(20000, 50, 1.0f), nullptr)); });
        return std::move(*map);
    };
    const CausticMap one = buildWith(1);
    const CausticMap two = buildWith(2);
    ASSERT_EQ(one.photons().size(), two.photons().size());
    ASSERT_GT(one.photons().size(), 0u);
    for (size_t i = 0; i < one.photons().size(); ++i) {
        ASSERT_EQ(one.photons()[i].p, two.photons()[i].p) << i;
        ASSERT_EQ(one.photons()[i].power, two.photons()[i].power) << i;
    }
    CausticSettings other = settings(20000, 50, 1.0f);
    other.seed += 1;
    const CausticMap reseeded = CausticMap::build(*scene, other, nullptr);
    EXPECT_NE(reseeded.photons()[0].p, one.photons()[0].p);
}

// Photons from a Lambertian surface instead of the lights (tracePhotonsFromSurfaces, the
// radiosity solution's transfer through specular surfaces): a small patch on the floor of a
// closed box, radiance L into its upper hemisphere, under a perfect mirror sphere (reflectance 1).
// Every photon that meets the sphere is reflected once onto a wall and stored there, so the
// stored power is the flux the patch sends into the sphere: L A F pi, with F = cos(beta) (r/d)²
// the form factor from a point to a sphere above its horizon (Howell's catalogue, C-13), between
// the values for the sphere through the mesh's vertices and the one tangent to its faces.
TEST(PhotonsFromSurfaces, StoredPowerIsTheFluxTheSurfaceSendsIntoTheSpecularSphere) {
    SceneBuilder b;
    const int walls = b.addMaterial(lambertian(0.8f));
    const int m = b.addMaterial(mirror());
    const float a = 2.0f;
    b.addClosedBox(a, walls);
    const Vec3 center(0.0f, 0.0f, 0.0f);
    const float radius = 0.5f;
    const float inner = b.addSphere(center, radius, m);
    const auto scene = b.build();

    const float side = 0.1f, L = 3.0f;
    const SurfaceEmitter patch = [&](float, Vec2 u) -> std::optional<SurfaceEmission> {
        const Vec3 p(side * (u.x - 0.5f), side * (u.y - 0.5f), -a);
        return SurfaceEmission{p, Vec3(1e-6f), Vec3(0.0f, 0.0f, 1.0f), Color(L), 1.0f / sqr(side)};
    };
    const Color emitted(kPi * L * sqr(side));
    PhotonTracerSettings s;
    s.photons = 200000;
    s.seed = 1;
    const PhotonTraceResult traced = tracePhotonsFromSurfaces(*scene, patch, emitted, s, nullptr);
    // The patch is small beside the distance (2 m): its centre's form factor, within 0.3 %.
    const double d = a;
    const double lower = kPiD * L * sqr(side) * sqr(inner / d);
    const double upper = kPiD * L * sqr(side) * sqr(radius / d);
    const double stored = luminance(traced.storedPower);
    std::printf("[ measured ] stored %.6g lm, expected in [%.6g, %.6g], %zu photons stored\n",
                stored, lower, upper, traced.photons.size());
    EXPECT_EQ(traced.specularMeshes, 1);
    EXPECT_EQ(luminance(traced.emittedPower), luminance(emitted));
    // The aimed photons' noise at 200 000 (each carries the same flux but for the cosine):
    // measured within 1 % of the band; 2 % allowed, as for the lights' photons above.
    EXPECT_GE(stored, lower * 0.98);
    EXPECT_LE(stored, upper * 1.02);
    for (const Photon& photon : traced.photons)
        ASSERT_GT(glm::dot(photon.n, photon.wi), 0.0f);  // stored on the side it came from
}

// Without a specular surface nothing is shot, and the radiance is zero.
TEST(CausticMap, NoSpecularSurfaceShootsNothing) {
    SceneBuilder b;
    const int d = b.addMaterial(lambertian(kRho));
    b.addQuad({-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, d);
    b.addPointLight(Vec3(0.0f, 0.0f, 1.0f), kIntensity);
    const auto scene = b.build();
    const CausticMap map = CausticMap::build(*scene, settings(1000, 50, 0.0f), nullptr);
    EXPECT_EQ(map.trace().shot, 0u);
    EXPECT_EQ(map.trace().specularMeshes, 0);
    const Ray ray{Vec3(0.0f, 0.0f, 0.5f), Vec3(0.0f, 0.0f, -1.0f)};
    const auto hit = scene->intersect(ray);
    ASSERT_TRUE(hit);
    EXPECT_EQ(map.radiance(*hit, scene->bsdf(*hit), -ray.d), Color(0.0f));
}

TEST(CausticSettings, RefusesValuesOutOfRangeNamingTheKey) {
    const auto message = [](const CausticSettings& s) {
        try {
            validateCausticSettings(s);
        } catch (const UsageError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CausticSettings s;
    EXPECT_EQ(message(s), "");
    s.photons = 0;
    EXPECT_NE(message(s).find("caustics.photons: expected"), std::string::npos) << message(s);
    s = {};
    s.k = 1;
    EXPECT_NE(message(s).find("caustics.k: expected an integer in [2, 10000], got 1"),
              std::string::npos)
        << message(s);
    s = {};
    s.maxRadius = -1.0f;
    EXPECT_NE(message(s).find("caustics.max_radius"), std::string::npos) << message(s);
    s.maxRadius = std::nanf("");
    EXPECT_NE(message(s).find("caustics.max_radius"), std::string::npos) << message(s);
}

// Visible points of the measurements at the given points of a surface, seen along -z from above
// (or +x from the side): beta 1, wo back along the ray.
std::vector<VisiblePoint> visiblePoints(const Scene& scene, const std::vector<Ray>& rays) {
    std::vector<VisiblePoint> points;
    for (const Ray& ray : rays) {
        const std::optional<SurfaceHit> hit = scene.intersect(ray);
        EXPECT_TRUE(hit);
        points.push_back(VisiblePoint{hit ? *hit : SurfaceHit{}, -ray.d, Color(hit ? 1.0f : 0.0f)});
    }
    return points;
}

// Progressive caustics of the point light in the mirror converge to the mirror image's radiance,
// with radii that shrink at every iteration that finds photons.
TEST(ProgressiveCaustics, ConvergesToTheMirrorImageOfAPointLight) {
    const auto scene = mirrorScene(lambertian(kRho));
    std::vector<Ray> rays;
    for (const Vec2& xy : kCeilingPoints)
        rays.push_back(Ray{Vec3(xy.x, xy.y, kCeiling - 0.5f), Vec3(0.0f, 0.0f, 1.0f)});
    const std::vector<VisiblePoint> points = visiblePoints(*scene, rays);
    ProgressiveCausticSettings s;
    s.photonsPerIteration = 25000;
    s.initialRadius = 0.3f;
    s.seed = 1;
    ProgressiveCaustics sppm(*scene, points.size(), s);
    std::vector<float> previous(points.size(), s.initialRadius);
    for (int iteration = 0; iteration < 16; ++iteration) {
        sppm.iterate(points, nullptr);
        for (size_t i = 0; i < points.size(); ++i) {
            EXPECT_LT(sppm.radius(i), previous[i]);
            previous[i] = sppm.radius(i);
        }
    }
    for (const auto& [name, value] : sppm.stats())
        std::printf("[ stats    ] %s: %s\n", name.c_str(), value.c_str());
    for (size_t i = 0; i < points.size(); ++i) {
        const Vec2& xy = kCeilingPoints[i];
        const double expected = mirrorImageRadiance(xy);
        const Color L = sppm.radiance(i);
        std::printf("[ measured ] (%.1f, %.1f): L %.5g, expected %.5g, ratio %.4f, radius %.4f\n",
                    xy.x, xy.y, luminance(L), expected, luminance(L) / expected, sppm.radius(i));
        // 400000 photons in all, as the k-nearest test, gathered within radii of 0.3 to 0.16 m:
        // measured errors up to 3.6 % (seed 1); 6 % as there.
        EXPECT_NEAR(luminance(L) / expected, 1.0, 0.06);
    }
}

// Near the edge of the directional light's reflected beam (0.054 m inside it), a fixed radius
// larger than that is biased low; progressive radii shrink, and the bias with them.
TEST(ProgressiveCaustics, BiasAtABeamEdgeShrinks) {
    const auto scene = tiltedMirrorScene();
    const double expected = kRho / kPiD * kSunIlluminance;
    const std::vector<VisiblePoint> points =
        visiblePoints(*scene, {Ray{Vec3(2.5f, 0.0f, 0.30f), Vec3(1.0f, 0.0f, 0.0f)}});

    ProgressiveCausticSettings s;
    s.photonsPerIteration = 20000;
    s.initialRadius = 0.15f;
    s.seed = 1;
    ProgressiveCaustics sppm(*scene, 1, s);
    std::vector<double> errors;
    for (int iteration = 1; iteration <= 64; ++iteration) {
        sppm.iterate(points, nullptr);
        if (iteration == 4 || iteration == 64) {
            errors.push_back(luminance(sppm.radiance(0)) / expected - 1.0);
            std::printf("[ measured ] after %d iterations: relative error %.4f, radius %.4f\n",
                        iteration, errors.back(), sppm.radius(0));
        }
    }
    // Measured: -22.5 % after 4 iterations (radius 0.100), -8.5 % after 64 (0.062). Without the
    // radius reduction (alpha 0.999) it stays at -27.7 % and the test fails.
    EXPECT_LT(errors[0], -0.1);
    EXPECT_LT(std::abs(errors[1]), 0.5 * std::abs(errors[0]));
}

TEST(ProgressiveCaustics, RefusesValuesOutOfRangeNamingTheKey) {
    ProgressiveCausticSettings s;
    EXPECT_NO_THROW(validateProgressiveCausticSettings(s));
    s.alpha = 1.0f;
    EXPECT_THROW(validateProgressiveCausticSettings(s), UsageError);
    s = {};
    s.photonsPerIteration = 0;
    EXPECT_THROW(validateProgressiveCausticSettings(s), UsageError);
    s = {};
    s.initialRadius = -0.1f;
    try {
        validateProgressiveCausticSettings(s);
        ADD_FAILURE() << "no error";
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find("caustics.initial_radius: expected a length >= 0"),
                  std::string::npos)
            << e.what();
    }
}

}  // namespace
}  // namespace penumbra
