#include "raytrace/image_renderer.h"

#include "core/errors.h"
#include "core/sampler.h"

#include <algorithm>

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace penumbra {

namespace {

// Tiles of 16 x 16 pixels balance the load on two to many cores without much scheduling cost.
constexpr int kTileSize = 16;

}  // namespace

std::vector<AovSpec> aovSpecs(const std::vector<std::string>& names) {
    std::vector<AovSpec> specs;
    for (const std::string& name : names) {
        if (name != "albedo" && name != "normal" && name != "depth") {
            throw UsageError("--aov: unknown layer '" + name + "'; valid: albedo, normal, depth");
        }
        if (name == "normal") {
            specs.push_back({name, {"X", "Y", "Z"}});
        } else if (name == "depth") {
            specs.push_back({name, {"Z"}});
        } else {
            specs.push_back({name, {"R", "G", "B"}});
        }
    }
    return specs;
}

namespace {

Vec3 aovValue(const std::string& name, const FirstHit& hit) {
    if (!hit.valid)
        return Vec3(0.0f);
    if (name == "albedo")
        return hit.albedo;
    if (name == "normal")
        return hit.normal;
    return Vec3(hit.depth);
}

}  // namespace

ImageRenderer::ImageRenderer(const Camera& camera, const RenderSettings& settings,
                             RadianceEstimator estimator)
    : camera_(camera),
      settings_(settings),
      estimator_(std::move(estimator)),
      filter_(parseFilter(settings.filter)),
      aovNames_(settings.aovs),
      film_(settings.width, settings.height, aovSpecs(aovNames_)) {}

void ImageRenderer::renderSamplePass() {
    struct Counts {
        uint64_t rays = 0, dropped = 0;
    };
    tbb::combinable<Counts> counts;
    const uint32_t sampleIndex = static_cast<uint32_t>(samplesDone_);
    const bool wantAovs = !aovNames_.empty();
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, settings_.height, kTileSize, 0, settings_.width, kTileSize),
        [&](const tbb::blocked_range2d<int>& tile) {
            Sampler sampler(settings_.seed);
            PathCounters counters;
            uint64_t dropped = 0;
            for (int y = tile.rows().begin(); y < tile.rows().end(); ++y) {
                for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
                    const IVec2 pixel(x, y);
                    sampler.startPixelSample(pixel, sampleIndex);
                    const Vec2 offset = filter_.sampleOffset(sampler.getPixel2D());
                    const Ray ray = camera_.generateRay(Vec2(pixel) + Vec2(0.5f) + offset);
                    FirstHit firstHit;
                    const Color L =
                        estimator_(ray, sampler, wantAovs ? &firstHit : nullptr, counters);
                    // NaN and Inf never reach the film: dropped and counted (DEVELOPERS.md).
                    if (!isFinite(L)) {
                        ++dropped;
                        continue;
                    }
                    film_.addSample(pixel, L, 1.0f);
                    for (size_t a = 0; a < aovNames_.size(); ++a) {
                        film_.addAov(pixel, static_cast<int>(a), aovValue(aovNames_[a], firstHit));
                    }
                }
            }
            Counts& local = counts.local();
            local.rays += counters.rays;
            local.dropped += dropped;
        });
    counts.combine_each([this](const Counts& c) {
        rays_ += c.rays;
        dropped_ += c.dropped;
    });
    ++samplesDone_;
}

}  // namespace penumbra
