// Exact tracking's cost on a large, sparse density grid (core/density_grid.h): a 256^3 lattice of
// cells over a 4-m box that holds two puffs of smoke filling about 0.5 % of it (as a cloud's or a
// plume's active voxels fill little of their bounding box once a VDB is made dense), and one
// iteration integrates the density along the same 10 000 chords through the box, on one thread.
//
// Counters: chords_per_s, and cells_per_chord (the mean number of lattice cells a chord crosses,
// empty or not).
#include "core/density_grid.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

namespace penumbra::bench {

namespace {

struct SparseGrid {
    Bounds3 box{Vec3(-2.0f), Vec3(2.0f)};
    std::unique_ptr<DensityGrid> grid;
    std::vector<std::pair<Ray, float>> chords;  // each ray from the box's face, and its length

    SparseGrid() {
        const glm::ivec3 nodes(257);
        std::vector<float> values;
        values.reserve(size_t(nodes.x) * nodes.y * nodes.z);
        const auto puff = [](const Vec3& g, const Vec3& centre, float radius) {
            return std::max(0.0f, 1.0f - glm::length(g - centre) / radius);
        };
        for (int z = 0; z < nodes.z; ++z)
            for (int y = 0; y < nodes.y; ++y)
                for (int x = 0; x < nodes.x; ++x) {
                    const Vec3 g(x, y, z);
                    values.push_back(puff(g, Vec3(80.0f, 100.0f, 90.0f), 20.0f) +
                                     puff(g, Vec3(170.0f, 150.0f, 160.0f), 25.0f));
                }
        grid = std::make_unique<DensityGrid>(box, nodes, std::move(values));
        // Chords between two random points on the box's surface (a random face each).
        std::mt19937_64 random(5);
        std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
        const auto onSurface = [&] {
            Vec3 p =
                box.lo + Vec3(uniform(random), uniform(random), uniform(random)) * box.diagonal();
            const int axis = int(uniform(random) * 3.0f) % 3;
            p[axis] = uniform(random) < 0.5f ? box.lo[axis] : box.hi[axis];
            return p;
        };
        while (chords.size() < 10000) {
            const Vec3 a = onSurface(), b = onSurface();
            const float length = glm::distance(a, b);
            if (length > 0.5f)
                chords.push_back({Ray{a, (b - a) / length}, length});
        }
    }
};

const SparseGrid& sparseGrid() {
    static const SparseGrid fixture;
    return fixture;
}

void SparseGridIntegral(benchmark::State& state) {
    const SparseGrid& f = sparseGrid();
    for (auto _ : state) {
        float sum = 0.0f;
        for (const auto& [ray, length] : f.chords)
            sum += f.grid->integral(ray, 0.0f, length);
        benchmark::DoNotOptimize(sum);
    }
    double cells = 0.0;
    const Vec3 cellSize = f.box.diagonal() / 256.0f;
    for (const auto& [ray, length] : f.chords) {
        const Vec3 crossed = glm::abs(ray.d) * length / cellSize;
        cells += double(crossed.x + crossed.y + crossed.z);
    }
    state.counters["chords_per_s"] =
        benchmark::Counter(double(f.chords.size()), benchmark::Counter::kIsIterationInvariantRate);
    state.counters["cells_per_chord"] = cells / double(f.chords.size());
}

BENCHMARK(SparseGridIntegral)->Unit(benchmark::kMillisecond);

}  // namespace

}  // namespace penumbra::bench
