#include "bench/cornell_fixture.h"

#include "core/film.h"
#include "core/gltf_loader.h"
#include "core/sampler.h"
#include "raytrace/path_tracer.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_reduce.h>

#include <functional>
#include <stdexcept>

namespace penumbra::bench {

namespace {

// As in ImageRenderer (raytrace/image_renderer.cpp).
constexpr int kTileSize = 16;

// The shadow ray Scene::transmittance casts from a surface point to a point on a light: both
// ends offset off their surfaces, stopped just short of the target.
Ray shadowRay(const SurfaceHit& hit, const LightLiSample& ls) {
    const Vec3 toward = ls.pLight - hit.p;
    const Vec3 target = glm::dot(ls.nLight, ls.nLight) > 0.0f
                            ? offsetRayOrigin(ls.pLight, ls.pLightError, ls.nLight, -toward)
                            : ls.pLight;
    const Vec3 start = offsetRayOrigin(hit.p, hit.pError, hit.ng, target - hit.p);
    const Vec3 d = target - start;
    const float distance = glm::length(d);
    return Ray{start, d / distance, distance * (1.0f - kShadowEpsilon)};
}

// Appends the rays of one path started by `ray`, drawing the sampler's dimensions in the order
// PathTracer::Li draws them. Straight-through transparency is not followed: the scene has none.
void recordPath(const Scene& scene, Ray ray, Sampler& sampler, RaySet& out) {
    Color beta(1.0f);
    int depth = 0;
    while (true) {
        out.all.push_back({ray, false});
        const std::optional<SurfaceHit> hit = scene.intersect(ray);
        if (!hit)
            return;
        const Vec3 wo = -ray.d;
        const Bsdf bsdf = scene.bsdf(*hit);

        // Next-event estimation: one shadow ray when the light sample carries energy.
        if (bsdf.hasNonDeltaLobe()) {
            const float uLight = sampler.get1D();
            const Vec2 uPoint = sampler.get2D();
            if (const auto choice = scene.lightSampler().sample(uLight)) {
                const LightSampleContext ctx{hit->p, hit->pError, hit->ng};
                const auto ls = scene.lights()[choice->light]->sampleLi(ctx, uPoint);
                if (ls && ls->pdf > 0.0f &&
                    maxComponent(bsdf.f(wo, ls->wi) *
                                 std::abs(glm::dot(ls->wi, bsdf.shadingNormal()))) > 0.0f) {
                    out.all.push_back({shadowRay(*hit, *ls), true});
                }
            }
        }

        // BSDF-sampled continuation and Russian roulette, as PathTracer::Li.
        const float uLobe = sampler.get1D();
        const Vec2 uDirection = sampler.get2D();
        const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, uDirection);
        if (!bs || !(bs->pdf > 0.0f))
            return;
        beta *= bs->f * (std::abs(glm::dot(bs->wi, bsdf.shadingNormal())) / bs->pdf);
        if (maxComponent(beta) <= 0.0f)
            return;
        ray = Scene::spawnRay(*hit, bs->wi);
        ++depth;
        const float q = rouletteTerminationProbability(depth, beta);
        if (q > 0.0f) {
            if (sampler.get1D() < q)
                return;
            beta /= 1.0f - q;
        }
    }
}

RaySet recordRays(const Scene& scene, const Camera& camera) {
    RaySet rays;
    const PixelFilter filter(FilterType::Box);  // the renderer's default
    Sampler sampler(kSeed);
    for (int y0 = 0; y0 < kImageSize; y0 += kTileSize) {
        for (int x0 = 0; x0 < kImageSize; x0 += kTileSize) {
            for (int y = y0; y < y0 + kTileSize; ++y) {
                for (int x = x0; x < x0 + kTileSize; ++x) {
                    const IVec2 pixel(x, y);
                    sampler.startPixelSample(pixel, 0);
                    const Vec2 offset = filter.sampleOffset(sampler.getPixel2D());
                    recordPath(scene, camera.generateRay(Vec2(pixel) + Vec2(0.5f) + offset),
                               sampler, rays);
                }
            }
        }
    }
    for (const TracedRay& r : rays.all)
        (r.shadow ? rays.shadowRays : rays.segments).push_back(r.ray);
    return rays;
}

CornellFixture makeCornell() {
    CornellFixture f;
    f.scene = std::make_unique<Scene>(
        loadGltf(PENUMBRA_SOURCE_DIR "/scenes/cornell-box/cornell-box.gltf"));
    if (f.scene->description().cameras.empty())
        throw std::runtime_error("the Cornell box has lost its camera");
    f.camera =
        std::make_unique<Camera>(f.scene->description().cameras.front(), kImageSize, kImageSize);
    f.accel = std::make_unique<Accel>(f.scene->meshes());
    f.rays = recordRays(*f.scene, *f.camera);
    return f;
}

// Number of true results of test(i) for i in [0, n), over oneTBB's current parallelism.
template <class Test>
uint64_t parallelCount(size_t n, const Test& test) {
    // Chunks of 1024 rays: scheduling costs little next to 1024 traversals.
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, n, 1024), uint64_t{0},
        [&](const tbb::blocked_range<size_t>& range, uint64_t count) {
            for (size_t i = range.begin(); i < range.end(); ++i)
                count += test(i) ? 1 : 0;
            return count;
        },
        std::plus<>());
}

}  // namespace

const CornellFixture& cornell() {
    static const CornellFixture fixture = makeCornell();
    return fixture;
}

uint64_t castRays(const Accel& accel, std::span<const TracedRay> rays) {
    return parallelCount(rays.size(), [&](size_t i) {
        return rays[i].shadow ? accel.occluded(rays[i].ray)
                              : accel.intersect(rays[i].ray).has_value();
    });
}

uint64_t castClosestHit(const Accel& accel, std::span<const Ray> rays) {
    return parallelCount(rays.size(),
                         [&](size_t i) { return accel.intersect(rays[i]).has_value(); });
}

uint64_t castOcclusion(const Accel& accel, std::span<const Ray> rays) {
    return parallelCount(rays.size(), [&](size_t i) { return accel.occluded(rays[i]); });
}

void perThreadCount(benchmark::internal::Benchmark* b) {
    const int64_t all = tbb::info::default_concurrency();
    b->ArgName("threads")->Arg(1);
    if (all > 1)
        b->Arg(all);
    b->UseRealTime()->Unit(benchmark::kMillisecond);
}

}  // namespace penumbra::bench
