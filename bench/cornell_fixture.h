// What the benchmarks render: the Cornell box (scenes/cornell-box/cornell-box.gltf) at 512 x 512
// through its own camera, and the set of rays the path tracer casts for one sample per pixel of
// it, recorded once so that the raw ray-casting benchmarks trace exactly that distribution.
#pragma once

#include "core/accel.h"
#include "core/camera.h"
#include "core/ray.h"
#include "core/scene.h"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace penumbra::bench {

constexpr int kImageSize = 512;  // pixels, width and height
constexpr uint32_t kSeed = 1;

// One ray as the path tracer casts it: a path segment (closest hit, Scene::intersect) or a
// shadow ray of next-event estimation (any hit, Accel::occluded, as Scene::transmittance casts
// it in a scene without transparent surfaces).
struct TracedRay {
    Ray ray;
    bool shadow = false;
};

// The rays of sample 0 (seed kSeed) of every pixel, in the order PathTracer::Li casts them:
// pixels in 16 x 16 tiles row by row, each path's segments interleaved with its shadow rays.
// Recorded by following PathTracer::Li step by step with the same sampler dimensions (camera
// sample, light choice, light point, BSDF lobe and direction, roulette), so for a scene of
// opaque surfaces such as the Cornell box it is the very set of rays the first pass of the path
// tracer casts, not an approximation of it: BSDF-sampled (here cosine-distributed, the walls
// being Lambertian) bounces and shadow rays to points on the light, ended by the same roulette.
struct RaySet {
    std::vector<TracedRay> all;   // path order
    std::vector<Ray> segments;    // the closest-hit rays of `all`, in order
    std::vector<Ray> shadowRays;  // the shadow rays of `all`, in order
};

struct CornellFixture {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<Camera> camera;
    // A second acceleration structure over the scene's meshes, built exactly as Scene builds
    // its own (same class, same flags): Scene does not expose its Accel, and Accel is the one
    // interface to Embree (CONTRIBUTING.md, "Layering").
    std::unique_ptr<Accel> accel;
    RaySet rays;
};

// Loads, builds and records everything on first use (a few seconds), then returns the same one.
const CornellFixture& cornell();

// Casts rays with Accel::intersect / Accel::occluded over oneTBB's current parallelism and
// returns how many hit something (so the work cannot be optimised away, and as a sanity check).
uint64_t castRays(const Accel& accel, std::span<const TracedRay> rays);
uint64_t castClosestHit(const Accel& accel, std::span<const Ray> rays);
uint64_t castOcclusion(const Accel& accel, std::span<const Ray> rays);

// Runs a benchmark once per thread count (its argument `threads`: 1 and every available core,
// tbb::info::default_concurrency()), timed by the wall clock since the work runs on oneTBB's
// workers, not on the benchmark's thread.
void perThreadCount(benchmark::internal::Benchmark* b);

}  // namespace penumbra::bench
