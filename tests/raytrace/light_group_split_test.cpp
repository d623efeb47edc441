// The path tracer filing its light by group in one render (core/light_groups.h, LightGroupSplit)
// against another estimator: the plain path tracer on the scene lit by each group alone
// (litOnlyBy), which draws its lights from its own scene and weighs them by its own MIS. A scene
// with every kind of source the split tells apart (a point light, an emissive panel, an
// environment map and its sun) over a Lambertian floor and a glossy wall: each group's mean must
// agree with the group's own render within the two estimates' noise, and every sample's groups
// must sum to its radiance.
#include "core/light_groups.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "raytrace/path_tracer.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"
#include "tests/support/sample_estimate.h"

#include <gtest/gtest.h>

#include <array>
#include <memory>

namespace penumbra::test {
namespace {

// Samples per camera ray and estimator: the standard error of each group's mean is then 0.04 to
// 0.5 % of it, in the split as in the renders of each group alone (measured), so a wrong MIS
// weight or a group drawn with the wrong probability, which moves a mean by its share of the
// light, stands out (the panel's MIS weights taken over all the lights doubled its layer; the
// map's and the sun's taken from the whole environment's density failed 12 comparisons).
constexpr uint32_t kSamples = 20000;
// Deviations between two independent means the test accepts: at 4.5 standard errors a false
// alarm among its 48 comparisons has a probability under 1e-4 (for normal means).
constexpr double kDeviations = 4.5;

// The scene's glTF: a Lambertian floor, a glossy wall behind it, a point light and an emissive
// panel (both sides) above the floor.
GltfBuilder litCorner() {
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(0.5f), .name = "Floor"});
    const int wall = scene.addMaterial({.baseColor = Color(0.6f, 0.7f, 0.5f),
                                        .lambertian = false,
                                        .roughness = 0.3f,
                                        .name = "Wall"});
    const int panel = scene.addMaterial({.baseColor = Color(0.0f),
                                         .emissive = Color(1.0f, 0.9f, 0.8f),
                                         .emissiveStrength = 5.0f,
                                         .doubleSided = true,
                                         .name = "Panel"});
    scene.addQuad({-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}, floor);
    scene.addQuad({-2, 0, -2}, {2, 0, -2}, {2, 2, -2}, {-2, 2, -2}, wall);
    scene.addQuad({-0.3f, 1.5f, 0.3f}, {0.3f, 1.5f, 0.3f}, {0.3f, 1.5f, -0.3f},
                  {-0.3f, 1.5f, -0.3f}, panel);
    scene.addLight({.type = "point",
                    .name = "Lamp",
                    .color = Color(1.0f, 0.5f, 0.3f),
                    .intensity = 20.0f,
                    .position = {1, 1, 0.5f}});
    return scene;
}

// The built scene's description with a blue environment map and a sun.
SceneDescription litCornerUnderTheSky() {
    const std::unique_ptr<Scene> built = loadBuiltScene(litCorner(), "light-group-split");
    SceneDescription description = built->description();
    EnvironmentDesc environment;
    environment.file = "a blue map";
    environment.radiance = Image(16, 8, {"R", "G", "B"});
    for (int y = 0; y < 8; ++y) {
        for (int x = 0; x < 16; ++x) {
            environment.radiance.at(x, y, 0) = 0.2f;
            environment.radiance.at(x, y, 1) = 0.3f;
            environment.radiance.at(x, y, 2) = 0.5f;
        }
    }
    environment.sun = SunDisc{.direction = glm::normalize(Vec3(0.3f, 0.8f, 0.5f)),
                              .directNormalIlluminance = 5.0f};
    description.environment = std::move(environment);
    return description;
}

// Camera rays from above the corner to points of the floor and the wall (file coordinates).
std::vector<Ray> cameraRays(const SceneDescription& description) {
    const Vec3 origin(description.origin);
    const Vec3 eye = Vec3(0.0f, 3.0f, 3.0f) - origin;
    std::vector<Ray> rays;
    for (const Vec3 target :
         {Vec3(0, 0, 0), Vec3(1, 0, -1), Vec3(-1.2f, 0, 0.8f), Vec3(0.5f, 1, -2)}) {
        rays.push_back(Ray{eye, glm::normalize(target - origin - eye)});
    }
    return rays;
}

TEST(LightGroupSplit, EachGroupMatchesARenderOfItAlone) {
    const SceneDescription description = litCornerUnderTheSky();
    const Scene scene{SceneDescription(description)};
    const LightGroupSplit split(scene);
    std::vector<std::string> names;
    for (const LightGroup& group : split.groups())
        names.push_back(group.name);
    ASSERT_EQ(names,
              (std::vector<std::string>{"light-Lamp", "emissive-Panel", "environment", "sun"}));
    const PathTracer tracer(scene, PathTracerSettings{}, nullptr, nullptr, &split);
    const std::vector<Ray> rays = cameraRays(description);
    PathCounters counters;

    for (size_t r = 0; r < rays.size(); ++r) {
        SCOPED_TRACE("ray " + std::to_string(r));
        std::vector<std::array<Estimate, 3>> splitMeans(names.size());
        Sampler sampler(11);
        for (uint32_t i = 0; i < kSamples; ++i) {
            sampler.startPixelSample(IVec2(int(r), 0), i);
            const PathRadiance L = tracer.Li(rays[r], sampler, nullptr, counters);
            ASSERT_EQ(L.groups.size(), names.size());
            Color sum(0.0f);
            for (size_t g = 0; g < names.size(); ++g) {
                sum += L.groups[g];
                for (int c = 0; c < 3; ++c)
                    splitMeans[g][c].add(L.groups[g][c]);
            }
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(sum[c], L.total()[c], 1e-5f * L.total()[c] + 1e-9f) << "sample " << i;
        }
        for (size_t g = 0; g < names.size(); ++g) {
            SCOPED_TRACE(names[g]);
            const Scene alone(litOnlyBy(description, split.groups()[g]));
            const PathTracer plain(alone, PathTracerSettings{});
            std::array<Estimate, 3> aloneMeans;
            Sampler aloneSampler(23);
            for (uint32_t i = 0; i < kSamples; ++i) {
                aloneSampler.startPixelSample(IVec2(int(r), 0), i);
                const Color L = plain.Li(rays[r], aloneSampler, nullptr, counters).total();
                for (int c = 0; c < 3; ++c)
                    aloneMeans[c].add(L[c]);
            }
            for (int c = 0; c < 3; ++c) {
                const Estimate& a = splitMeans[g][c];
                const Estimate& b = aloneMeans[c];
                EXPECT_GT(b.mean(), 0.0) << "channel " << c;
                const double error = std::hypot(a.standardError(), b.standardError());
                EXPECT_NEAR(a.mean(), b.mean(), kDeviations * error) << "channel " << c;
            }
        }
    }
}

}  // namespace
}  // namespace penumbra::test
