// Hierarchical radiosity (radiosity/radiosity_solver.h) as the radiosity pass runs it: the element
// mesh built and solved with default settings but for the smallest element area, which sets the
// resolution. One iteration is one whole solve (mesh construction excluded), timed by the wall
// clock on oneTBB's default parallelism.
//
// Counters: elements, leaves, links, links_per_leaf; for RadiosityLinkScaling the exponent b of a
// least-squares fit links = a leaves^b over the resolutions (HSA91's claim is b = 1: O(n) links
// instead of the O(n^2) of the full matrix), and the same for the time; for the modern hall the
// process's peak resident memory (getrusage ru_maxrss) after the solve.
#include <benchmark/benchmark.h>

#include "core/gltf_loader.h"
#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/full_matrix_solve.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <sys/resource.h>

namespace penumbra::bench {

namespace {

const Scene& cornellScene() {
    static const Scene scene(loadGltf(PENUMBRA_SOURCE_DIR "/scenes/cornell-box/cornell-box.gltf"));
    return scene;
}

// The shared scenes live beside the repository (as for scenes/cornell-box/make_cornell_box.py).
const std::string kModernHall =
    PENUMBRA_SOURCE_DIR "/../shared/scenes/bitterli-modern-hall/scene.gltf";

double peakMemoryMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// Default settings with the smallest element area = the scene's total area / divisor (the
// default divisor is 16384: about 9300 leaves on the Cornell box).
RadiositySettings resolution(const Scene& scene, double divisor) {
    RadiositySettings settings;
    settings.minElementArea =
        static_cast<float>(RadiositySettings{}.meshing(scene).minElementArea * 16384.0 / divisor);
    return settings;
}

struct Solved {
    size_t elements = 0, leaves = 0, links = 0;
    double seconds = 0.0;
};

Solved solveOnce(const Scene& scene, const RadiositySettings& settings) {
    RadiosityMesh mesh(scene, settings.meshing(scene));
    RadiositySolver solver(scene, mesh, settings);
    const auto start = std::chrono::steady_clock::now();
    solver.solve();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return {mesh.elementCount(), mesh.leafCount(), solver.linkCount(), seconds};
}

void setCounters(benchmark::State& state, const Solved& s) {
    state.counters["elements"] = static_cast<double>(s.elements);
    state.counters["leaves"] = static_cast<double>(s.leaves);
    state.counters["links"] = static_cast<double>(s.links);
    state.counters["links_per_leaf"] = static_cast<double>(s.links) / static_cast<double>(s.leaves);
}

// One hierarchical solve of the Cornell box; argument: the area divisor.
void RadiosityCornell(benchmark::State& state) {
    const Scene& scene = cornellScene();
    const RadiositySettings settings = resolution(scene, static_cast<double>(state.range(0)));
    Solved s;
    for (auto _ : state) {
        s = solveOnce(scene, settings);
        state.SetIterationTime(s.seconds);
    }
    setCounters(state, s);
}

// The dense solve over the same leaves (tests/support/full_matrix_solve.h, every pair of leaf
// sides), after the hierarchical solve that made them; only the dense solve is timed.
void RadiosityCornellFullMatrix(benchmark::State& state) {
    const Scene& scene = cornellScene();
    const RadiositySettings settings = resolution(scene, static_cast<double>(state.range(0)));
    RadiosityMesh mesh(scene, settings.meshing(scene));
    RadiositySolver solver(scene, mesh, settings);
    solver.solve();
    for (auto _ : state) {
        const auto start = std::chrono::steady_clock::now();
        benchmark::DoNotOptimize(test::solveFullMatrix(solver, mesh));
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    const size_t leaves = mesh.leafCount();
    setCounters(state, {mesh.elementCount(), leaves, solver.linkCount(), 0.0});
    // The dense matrix's pairs of leaf sides, for comparison with the links.
    state.counters["pairs"] = 4.0 * static_cast<double>(leaves) * static_cast<double>(leaves);
}

// Slope of the least-squares line through (log x, log y).
double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = static_cast<double>(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx;
        sy += ly;
        sxx += lx * lx;
        sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// The Cornell box at four resolutions, 4x apart; the exponents of links and time against leaves.
void RadiosityLinkScaling(benchmark::State& state) {
    const Scene& scene = cornellScene();
    std::vector<double> leaves, links, seconds;
    for (auto _ : state) {
        leaves.clear();
        links.clear();
        seconds.clear();
        for (const double divisor : {1024.0, 4096.0, 16384.0, 65536.0}) {
            const Solved s = solveOnce(scene, resolution(scene, divisor));
            leaves.push_back(static_cast<double>(s.leaves));
            links.push_back(static_cast<double>(s.links));
            seconds.push_back(s.seconds);
        }
    }
    state.counters["links_exponent"] = logLogSlope(leaves, links);
    state.counters["time_exponent"] = logLogSlope(leaves, seconds);
    state.counters["max_leaves"] = leaves.back();
    state.counters["max_links"] = links.back();
}

// The real interior: 31k triangles, 13 area lights, glass; default settings (clustered, as it has
// far more than RadiositySettings::clusterMinPatches patches). Skipped if the shared scenes are
// not beside the repository.
void RadiosityModernHall(benchmark::State& state) {
    if (!std::filesystem::exists(kModernHall)) {
        state.SkipWithError(("no " + kModernHall).c_str());
        return;
    }
    const Scene scene(loadGltf(kModernHall));
    const RadiositySettings settings;
    Solved s;
    for (auto _ : state) {
        s = solveOnce(scene, settings);
        state.SetIterationTime(s.seconds);
    }
    setCounters(state, s);
    state.counters["peak_memory_mib"] = peakMemoryMiB();
}

BENCHMARK(RadiosityCornell)
    ->ArgName("divisor")
    ->Arg(1024)
    ->Arg(4096)
    ->Arg(16384)
    ->Arg(65536)
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(RadiosityCornellFullMatrix)
    ->ArgName("divisor")
    ->Arg(1024)
    ->Arg(2048)
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(RadiosityLinkScaling)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(RadiosityModernHall)->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

}  // namespace penumbra::bench
