// Raw ray casting: how many rays per second Embree (through penumbra::Accel) traces for the
// rays the path tracer casts on the Cornell box at 512 x 512, one sample per pixel (RaySet in
// cornell_fixture.h). One iteration casts the whole set once; nothing but the casts is timed.
//
// Counters: rays_per_s (wall clock), hit_fraction (rays that hit something).
#include "bench/cornell_fixture.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

namespace penumbra::bench {

namespace {

// Times `cast` (which casts one whole set of `count` rays and returns the hits) per iteration.
template <class Cast>
void benchmarkCasts(benchmark::State& state, size_t count, const Cast& cast) {
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, state.range(0));
    uint64_t hits = 0;
    for (auto _ : state) {
        hits = cast();
        benchmark::DoNotOptimize(hits);
    }
    const double rays = static_cast<double>(count);
    state.counters["rays_per_s"] =
        benchmark::Counter(rays, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["hit_fraction"] = static_cast<double>(hits) / rays;
}

// Both kinds in the path tracer's order and proportion: closest hit for path segments,
// occlusion for shadow rays. This is the rate PathCounters::rays is compared with.
void RawPathTracerRays(benchmark::State& state) {
    const CornellFixture& f = cornell();
    benchmarkCasts(state, f.rays.all.size(), [&] { return castRays(*f.accel, f.rays.all); });
    state.counters["shadow_fraction"] =
        static_cast<double>(f.rays.shadowRays.size()) / static_cast<double>(f.rays.all.size());
}

// The path segments alone (camera rays and BSDF-sampled bounces), closest hit
// (Accel::intersect, i.e. rtcIntersect1).
void RawClosestHit(benchmark::State& state) {
    const CornellFixture& f = cornell();
    benchmarkCasts(state, f.rays.segments.size(),
                   [&] { return castClosestHit(*f.accel, f.rays.segments); });
}

// The shadow rays alone, any hit (Accel::occluded, i.e. rtcOccluded1).
void RawOcclusion(benchmark::State& state) {
    const CornellFixture& f = cornell();
    benchmarkCasts(state, f.rays.shadowRays.size(),
                   [&] { return castOcclusion(*f.accel, f.rays.shadowRays); });
}

BENCHMARK(RawPathTracerRays)->Apply(perThreadCount);
BENCHMARK(RawClosestHit)->Apply(perThreadCount);
BENCHMARK(RawOcclusion)->Apply(perThreadCount);

}  // namespace

}  // namespace penumbra::bench
