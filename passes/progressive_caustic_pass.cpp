#include "passes/progressive_caustic_pass.h"

#include "core/film.h"
#include "core/progress.h"
#include "core/sampler.h"
#include "core/stats.h"
#include "raytrace/specular_chain.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <vector>

namespace penumbra {

ProgressiveCausticPass::ProgressiveCausticPass(ProgressiveCausticSettings settings, int iterations,
                                               int maxSpecularDepth)
    : settings_(settings), iterations_(iterations), maxSpecularDepth_(maxSpecularDepth) {
    validateProgressiveCausticSettings(settings_);
}

ProgressiveCausticPass::~ProgressiveCausticPass() = default;

PassStats ProgressiveCausticPass::parameters() const {
    return {{"method", "progressive"},
            {"iterations", std::to_string(iterations_)},
            {"photons_per_iteration", std::to_string(settings_.photonsPerIteration)},
            {"initial_radius",
             settings_.initialRadius > 0.0f ? formatStat(settings_.initialRadius) : "auto"},
            {"alpha", formatStat(settings_.alpha)},
            {"max_specular_depth", std::to_string(maxSpecularDepth_)}};
}

void ProgressiveCausticPass::prepare(PassContext& context) {
    const RenderSettings& s = context.settings;
    ProgressiveCausticSettings seeded = settings_;
    seeded.seed += s.seed;  // a render's seed changes its photons too
    caustics_ = std::make_unique<ProgressiveCaustics>(
        context.scene, static_cast<size_t>(s.width) * s.height, seeded);
    progress_ = std::make_unique<Progress>("progressive caustics",
                                           static_cast<uint64_t>(iterations_), s.quiet);
}

bool ProgressiveCausticPass::run(PassContext& context) {
    const auto start = std::chrono::steady_clock::now();
    const RenderSettings& s = context.settings;
    const PixelFilter filter(parseFilter(s.filter));
    const SpecularChainSettings chain{maxSpecularDepth_, false};
    const uint32_t iteration = static_cast<uint32_t>(caustics_->iterations());
    std::vector<VisiblePoint> points(static_cast<size_t>(s.width) * s.height);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, s.height), [&](const tbb::blocked_range<int>& rows) {
            Sampler sampler(s.seed);
            PathCounters counters;
            for (int y = rows.begin(); y < rows.end(); ++y) {
                for (int x = 0; x < s.width; ++x) {
                    sampler.startPixelSample(IVec2(x, y), iteration);
                    const Vec2 offset = filter.sampleOffset(sampler.getPixel2D());
                    const Ray ray = context.camera.generateRay(Vec2(x, y) + Vec2(0.5f) + offset);
                    VisiblePoint& point = points[static_cast<size_t>(y) * s.width + x];
                    bool found = false;
                    // The chain's weight at the first diffuse vertex is what it returns when that
                    // vertex's term is 1 and every later one 0.
                    const Color beta =
                        traceSpecularChain(context.scene, ray, sampler, nullptr, counters, chain,
                                           [&](const SurfaceHit& hit, const Bsdf&, const Vec3& wo,
                                               Sampler&, PathCounters&) {
                                               if (found)
                                                   return Color(0.0f);
                                               found = true;
                                               point.hit = hit;
                                               point.wo = wo;
                                               return Color(1.0f);
                                           });
                    point.beta = found ? beta : Color(0.0f);
                }
            }
        });
    caustics_->iterate(points, nullptr);
    progress_->advance(1);
    seconds_ += secondsSince(start);
    // A fixed number of iterations, like the photon map's view: the time limit is left to the
    // passes after it.
    if (caustics_->iterations() < iterations_)
        return false;
    progress_->finish();
    Image image(s.width, s.height, {"R", "G", "B"});
    for (int y = 0; y < s.height; ++y) {
        for (int x = 0; x < s.width; ++x) {
            const Color L = caustics_->radiance(static_cast<size_t>(y) * s.width + x);
            for (int c = 0; c < 3; ++c)
                image.at(x, y, c) = L[c];
        }
    }
    context.contribute(type(), std::move(image));
    return true;
}

PassStats ProgressiveCausticPass::stats() const {
    PassStats stats = parameters();
    stats.push_back({"seconds", formatStat(seconds_)});
    for (const auto& [key, value] : caustics_->stats())
        stats.push_back({"sppm " + key, value});
    return stats;
}

}  // namespace penumbra
