// The reference path tracer on the Cornell box at 512 x 512, as `penumbra render` runs it
// (ImageRenderer over PathTracer::Li, box filter, no AOVs): one iteration renders one sample per
// pixel, so the benchmark's time per iteration is the time per sample per pixel.
//
// Counters: rays_per_s (PathCounters::rays, closest-hit and shadow rays, per wall-clock second),
// rays_per_pixel (per sample), and for PathTracerEfficiency the ratio of the path tracer's ray
// rate to the raw rate of Embree on the same rays.
#include "bench/cornell_fixture.h"

#include "raytrace/image_renderer.h"
#include "raytrace/path_tracer.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace penumbra::bench {

namespace {

RenderSettings benchSettings() {
    RenderSettings settings;
    settings.width = settings.height = kImageSize;
    settings.seed = kSeed;
    return settings;
}

// The path tracer behind an image renderer, as PathPass wires them (passes/path_pass.cpp).
struct Renderer {
    explicit Renderer(const CornellFixture& f)
        : tracer(*f.scene, PathTracerSettings{}),
          image(
              *f.camera, settings,
              [this](const Ray& ray, Sampler& sampler, FirstHit* firstHit, PathCounters& counters) {
                  return tracer.Li(ray, sampler, firstHit, counters);
              }) {}

    RenderSettings settings = benchSettings();
    PathTracer tracer;
    ImageRenderer image;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void PathTracerSamplePass(benchmark::State& state) {
    const CornellFixture& f = cornell();
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
    Renderer renderer(f);
    for (auto _ : state)
        renderer.image.renderSamplePass();
    const double rays = static_cast<double>(renderer.image.rays());
    state.counters["rays_per_s"] = benchmark::Counter(rays, benchmark::Counter::kIsRate);
    state.counters["rays_per_pixel"] =
        rays / (static_cast<double>(renderer.image.samplesDone()) * kImageSize * kImageSize);
    state.counters["dropped"] = static_cast<double>(renderer.image.droppedSamples());
}

// The efficiency figure: path tracer rays per second over raw Embree rays per second on the same
// rays (the first pass's RaySet). Each iteration times one raw cast of the ray set and one
// sample pass of the path tracer, alternately, so that load from other processes on a shared
// machine falls on both alike; the counters are the medians over the iterations.
void PathTracerEfficiency(benchmark::State& state) {
    const CornellFixture& f = cornell();
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
    Renderer renderer(f);
    std::vector<double> rawRates, tracerRates;
    for (auto _ : state) {
        const auto rawStart = std::chrono::steady_clock::now();
        benchmark::DoNotOptimize(castRays(*f.accel, f.rays.all));
        rawRates.push_back(static_cast<double>(f.rays.all.size()) / secondsSince(rawStart));

        const uint64_t raysBefore = renderer.image.rays();
        const auto tracerStart = std::chrono::steady_clock::now();
        renderer.image.renderSamplePass();
        const uint64_t tracerRays = renderer.image.rays() - raysBefore;
        tracerRates.push_back(static_cast<double>(tracerRays) / secondsSince(tracerStart));
        // The recorder follows PathTracer::Li; if they part, the ratio compares different work.
        if (raysBefore == 0 && tracerRays != f.rays.all.size()) {
            state.SkipWithError("the recorded ray set is not the path tracer's first pass");
            return;
        }
    }
    const double raw = median(rawRates), tracer = median(tracerRates);
    state.counters["raw_rays_per_s"] = raw;
    state.counters["pt_rays_per_s"] = tracer;
    state.counters["efficiency"] = tracer / raw;
}

BENCHMARK(PathTracerSamplePass)->Apply(perThreadCount);
BENCHMARK(PathTracerEfficiency)->Apply(perThreadCount);

}  // namespace

}  // namespace penumbra::bench
