#include "passes/progressive_caustic_pass.h"

#include "core/film.h"
#include "core/progress.h"
#include "core/sampler.h"
#include "core/stats.h"
#include "raytrace/specular_chain.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <limits>
#include <vector>

namespace penumbra {

namespace {

// Each pixel keeps two SPPM measurements, one for visible points the eye sees directly and one
// for those it sees through specular vertices: the light-path components indirect and specular
// (core/path_components.h). Each is its own consistent estimate (an iteration whose point falls
// in the other one gathers nothing for it), and the pixel's radiance is their sum.
constexpr size_t kMeasurementsPerPixel = 2;

size_t measurement(size_t pixel, bool throughSpecular) {
    return pixel * kMeasurementsPerPixel + (throughSpecular ? 1 : 0);
}

// The script keys of the pass (ProgressiveCausticSettings' and the iterations), in the order the
// plan prints them after `method`.
template <typename Settings, typename Count, typename Keys>
void progressiveCausticKeys(Settings& s, Count& iterations, Count& maxSpecularDepth, Keys& keys) {
    keys("iterations", iterations, 1, std::numeric_limits<int>::max());
    keys("photons_per_iteration", s.photonsPerIteration);
    keys.orAuto("initial_radius", s.initialRadius, 0.0f);
    keys("alpha", s.alpha);
    keys("seed", s.seed);
    keys("max_specular_depth", maxSpecularDepth, 0, kMaxDepthLimit);
}

}  // namespace

ProgressiveCausticPass::ProgressiveCausticPass(ProgressiveCausticSettings settings, int iterations,
                                               int maxSpecularDepth)
    : settings_(settings), iterations_(iterations), maxSpecularDepth_(maxSpecularDepth) {
    validateProgressiveCausticSettings(settings_);
}

ProgressiveCausticPass::~ProgressiveCausticPass() = default;

std::unique_ptr<Pass> ProgressiveCausticPass::fromScript(const ScriptTable& table,
                                                         const PassOverrides&) {
    ParameterReader keys(table);
    ProgressiveCausticSettings settings;
    int iterations = 64, maxSpecularDepth = CausticPass::kDefaultMaxSpecularDepth;
    progressiveCausticKeys(settings, iterations, maxSpecularDepth, keys);
    return keys.construct("caustics.", [&] {
        return std::make_unique<ProgressiveCausticPass>(settings, iterations, maxSpecularDepth);
    });
}

PassStats ProgressiveCausticPass::parameters() const {
    ParameterPrinter print;
    print("method", std::string("progressive"));
    progressiveCausticKeys(settings_, iterations_, maxSpecularDepth_, print);
    return print.stats();
}

void ProgressiveCausticPass::prepare(PassContext& context) {
    const RenderSettings& s = context.settings;
    ProgressiveCausticSettings seeded = settings_;
    seeded.seed += s.seed;  // a render's seed changes its photons too
    caustics_ = std::make_unique<ProgressiveCaustics>(
        context.scene, static_cast<size_t>(s.width) * s.height * kMeasurementsPerPixel, seeded);
    progress_ = std::make_unique<Progress>("progressive caustics",
                                           static_cast<uint64_t>(iterations_), s.quiet);
}

bool ProgressiveCausticPass::run(PassContext& context) {
    const auto start = std::chrono::steady_clock::now();
    const RenderSettings& s = context.settings;
    const PixelFilter filter(parseFilter(s.filter));
    const SpecularChainSettings chain{maxSpecularDepth_, false};
    const uint32_t iteration = static_cast<uint32_t>(caustics_->iterations());
    std::vector<VisiblePoint> points(static_cast<size_t>(s.width) * s.height *
                                     kMeasurementsPerPixel);
    tbb::parallel_for(
        tbb::blocked_range<int>(0, s.height), [&](const tbb::blocked_range<int>& rows) {
            Sampler sampler(s.seed);
            PathCounters counters;
            for (int y = rows.begin(); y < rows.end(); ++y) {
                for (int x = 0; x < s.width; ++x) {
                    sampler.startPixelSample(IVec2(x, y), iteration);
                    const Vec2 offset = filter.sampleOffset(sampler.getPixel2D());
                    const Ray ray = context.camera.generateRay(Vec2(x, y) + Vec2(0.5f) + offset);
                    VisiblePoint point;
                    bool found = false;
                    // The chain's weight at the first diffuse vertex is what it returns when that
                    // vertex's term is 1 and every later one 0; it files that weight under
                    // specular when the eye saw the vertex through a specular one.
                    const PathRadiance weight =
                        traceSpecularChain(context.scene, ray, sampler, nullptr, counters, chain,
                                           [&](const SurfaceHit& hit, const Bsdf&, const Vec3& wo,
                                               Sampler&, PathCounters&) {
                                               PathRadiance unit;
                                               if (found)
                                                   return unit;
                                               found = true;
                                               point.hit = hit;
                                               point.wo = wo;
                                               unit[PathComponent::Indirect] = Color(1.0f);
                                               return unit;
                                           });
                    if (!found)
                        continue;
                    point.beta = weight.total();
                    const bool throughSpecular =
                        maxComponent(weight[PathComponent::Specular]) > 0.0f;
                    points[measurement(static_cast<size_t>(y) * s.width + x, throughSpecular)] =
                        point;
                }
            }
        });
    caustics_->iterate(points, nullptr);
    progress_->advance(1);
    seconds_ += secondsSince(start);
    // A fixed number of iterations, like the photon map's view, leaving the time limit to the
    // passes after it; but under a limit it stops once it has spent kTimeShare of it.
    const bool outOfTime = context.deadline && seconds_ >= kTimeShare * context.settings.timeLimit;
    if (caustics_->iterations() < iterations_ && !outOfTime)
        return false;
    publish(context);
    return true;
}

bool ProgressiveCausticPass::stopEarly(PassContext& context) {
    publish(context);
    return true;
}

void ProgressiveCausticPass::publish(PassContext& context) {
    const RenderSettings& s = context.settings;
    progress_->finish();
    Image image(s.width, s.height, {"R", "G", "B"});
    Image seenDirectly = image;
    Image seenThroughSpecular = image;
    for (int y = 0; y < s.height; ++y) {
        for (int x = 0; x < s.width; ++x) {
            const size_t pixel = static_cast<size_t>(y) * s.width + x;
            const Color direct = caustics_->radiance(measurement(pixel, false));
            const Color specular = caustics_->radiance(measurement(pixel, true));
            for (int c = 0; c < 3; ++c) {
                seenDirectly.at(x, y, c) = direct[c];
                seenThroughSpecular.at(x, y, c) = specular[c];
                image.at(x, y, c) = direct[c] + specular[c];
            }
        }
    }
    context.contribute(type(), std::move(image));
    for (const std::string& aov : s.aovs) {
        if (aov == componentName(PathComponent::Indirect))
            context.addToLayer(aov, seenDirectly);
        if (aov == componentName(PathComponent::Specular))
            context.addToLayer(aov, seenThroughSpecular);
    }
}

PassStats ProgressiveCausticPass::stats() const {
    PassStats stats = parameters();
    stats.push_back({"seconds", formatStat(seconds_)});
    for (const auto& [key, value] : caustics_->stats())
        stats.push_back({"sppm " + key, value});
    return stats;
}

}  // namespace penumbra
