// The image renderer over the path tracer in-process: the image is a function of the seed alone
// (core/sampler.h's contract: every sample depends only on seed, pixel, sample index and
// dimension), so one and two threads give bit-identical images, beauty and light-path component
// layers alike, and another seed gives another image. The oracle is the first render itself:
// any shared state between tiles, or an accumulation in the order tiles finish, breaks it.
#include "core/camera.h"
#include "core/image.h"
#include "core/render_settings.h"
#include "core/scene.h"
#include "raytrace/image_renderer.h"
#include "raytrace/path_tracer.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>

namespace penumbra::test {
namespace {

// A closed Lambertian room with a ceiling light and a block on the floor: soft shadows, light
// bounced off coloured walls, paths of every length.
std::unique_ptr<Scene> smallRoom() {
    GltfBuilder builder;
    const int walls = builder.addMaterial({.baseColor = Color(0.7f, 0.6f, 0.5f)});
    const int floor = builder.addMaterial({.baseColor = Color(0.3f, 0.5f, 0.7f)});
    addClosedBox(builder, walls, floor);
    addCeilingLight(builder, 0.3f, 0.99f, 10.0f);
    addFloorBlock(builder, walls);
    return loadBuiltScene(builder, "raytrace-determinism");
}

struct Render {
    std::vector<Image> layers;  // the beauty, then the four component layers
    size_t threadsUsed = 0;     // distinct threads that traced paths
};

// 32 x 32 pixels are four of the renderer's 16 x 16 tiles, so that two threads share the work;
// 4 samples per pixel are four passes over them.
Render render(const Scene& scene, uint32_t seed, int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    RenderSettings settings;
    settings.width = settings.height = 32;
    settings.spp = 4;
    settings.seed = seed;
    settings.aovs = expandAovNames({"components"});
    // A perspective camera near the front wall, looking down -Z into the room.
    CameraDesc desc;
    desc.yfov = 1.2f;
    desc.cameraToWorld[3] = Vec4(Vec3(0.0f, 0.0f, 0.9f) - Vec3(scene.description().origin), 1.0f);
    const Camera camera(desc, settings.width, settings.height);

    const PathTracer tracer(scene, PathTracerSettings{});
    std::mutex mutex;
    std::set<std::thread::id> ids;
    ImageRenderer renderer(camera, settings,
                           [&](const Ray& ray, Sampler& sampler, FirstHit* hit, PathCounters& c) {
                               {
                                   const std::lock_guard<std::mutex> lock(mutex);
                                   ids.insert(std::this_thread::get_id());
                               }
                               return tracer.Li(ray, sampler, hit, c);
                           });
    for (int s = 0; s < settings.spp; ++s)
        renderer.renderSamplePass();
    EXPECT_EQ(renderer.droppedSamples(), 0u);

    Render result;
    result.layers.push_back(renderer.resolve());
    for (size_t a = 0; a < renderer.aovNames().size(); ++a)
        result.layers.push_back(renderer.resolveAov(a));
    result.threadsUsed = ids.size();
    return result;
}

// The number of values that differ in their bits (NaN never equals itself, and is counted).
size_t differingValues(const Image& a, const Image& b) {
    EXPECT_EQ(a.pixels().size(), b.pixels().size());
    size_t differing = 0;
    for (size_t i = 0; i < std::min(a.pixels().size(), b.pixels().size()); ++i) {
        if (!(a.pixels()[i] == b.pixels()[i]))
            ++differing;
    }
    return differing;
}

TEST(ImageRendererDeterminism, SameSeedSameImageOnOneAndTwoThreads) {
    const std::unique_ptr<Scene> scene = smallRoom();
    const Render one = render(*scene, 5, 1);
    const Render two = render(*scene, 5, 2);
    // The limit held; whether the second thread took tiles is the scheduler's choice (it nearly
    // always does, over four passes of four tiles).
    EXPECT_EQ(one.threadsUsed, 1u);
    EXPECT_LE(two.threadsUsed, 2u);
    std::cout << "threads that traced paths: " << one.threadsUsed << " and " << two.threadsUsed
              << "\n";
    ASSERT_EQ(one.layers.size(), 5u);
    ASSERT_EQ(two.layers.size(), 5u);
    for (size_t l = 0; l < one.layers.size(); ++l)
        EXPECT_EQ(differingValues(one.layers[l], two.layers[l]), 0u) << "layer " << l;

    // The image is lit: a test of a black image would pass whatever the tracer did.
    double sum = 0.0;
    for (const float v : one.layers[0].pixels())
        sum += v;
    EXPECT_GT(sum, 0.0);
    EXPECT_TRUE(std::isfinite(sum));
}

TEST(ImageRendererDeterminism, AnotherSeedAnotherImage) {
    const std::unique_ptr<Scene> scene = smallRoom();
    const Render a = render(*scene, 5, 2);
    const Render b = render(*scene, 6, 2);
    // Four paths per pixel are noisy: nearly every lit pixel changes with the seed.
    const Image& beauty = a.layers[0];
    EXPECT_GT(differingValues(beauty, b.layers[0]), beauty.pixels().size() / 2);
}

}  // namespace
}  // namespace penumbra::test
