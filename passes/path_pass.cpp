#include "passes/path_pass.h"

#include "core/stats.h"
#include "radiosity/radiosity_solution.h"

#include <sstream>

namespace penumbra {

std::set<std::string> PathPass::needs() const {
    if (settings_.reuseRadiosity)
        return {"radiosity"};
    return {};
}

void PathPass::adapt(const PipelineShape& shape) {
    settings_.excludeCaustics = caustics_ == Caustics::Exclude ||
                                (caustics_ == Caustics::Auto && shape.products.count("caustics"));
}

PassStats PathPass::parameters() const {
    return {{"max_depth", std::to_string(settings_.maxDepth)},
            {"radiosity", settings_.reuseRadiosity ? "true" : "false"},
            {"caustics", caustics_ == Caustics::Auto      ? "auto"
                         : caustics_ == Caustics::Include ? "include"
                                                          : "exclude"}};
}

void PathPass::prepare(PassContext& context) {
    radiosity_ = context.product<RadiositySolution>("radiosity");
    tracer_ = std::make_unique<PathTracer>(context.scene, settings_, radiosity_.get());
    renderer_ = std::make_unique<ImageRenderer>(
        context.camera, context.settings,
        [tracer = tracer_.get()](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                 PathCounters& counters) {
            return tracer->Li(ray, sampler, firstHit, counters);
        });
    const RenderSettings& s = context.settings;
    // With a time limit the bar measures time (in milliseconds), else samples.
    const uint64_t total = s.timeLimit > 0.0 ? static_cast<uint64_t>(s.timeLimit * 1000.0)
                                             : static_cast<uint64_t>(s.spp);
    progress_ = std::make_unique<Progress>("path tracing", total, s.quiet);
    start_ = std::chrono::steady_clock::now();
}

bool PathPass::run(PassContext& context) {
    const RenderSettings& s = context.settings;
    const auto passStart = std::chrono::steady_clock::now();
    renderer_->renderSamplePass();
    lastPassSeconds_ = secondsSince(passStart);
    seconds_ = secondsSince(start_);

    bool done = renderer_->samplesDone() >= s.spp;
    if (s.timeLimit > 0.0) {
        // Stop at whole passes: before a pass that would end past the limit.
        done = done || seconds_ + lastPassSeconds_ > s.timeLimit;
        progress_->advance(static_cast<uint64_t>(std::min(seconds_, s.timeLimit) * 1000.0) -
                           progress_->done());
    } else {
        progress_->advance(1);
    }
    if (done) {
        progress_->finish();
        publish(context);
    }
    return done;
}

void PathPass::publish(PassContext& context) const {
    context.contribute(type(), renderer_->film().resolve());
    const auto& aovs = renderer_->aovNames();
    for (size_t a = 0; a < aovs.size(); ++a) {
        context.layers[aovs[a]] = renderer_->film().resolveAov(static_cast<int>(a));
    }
}

PassStats PathPass::stats() const {
    const double seconds = seconds_ > 0.0 ? seconds_ : 1e-9;
    std::ostringstream raysPerSecond;
    raysPerSecond.precision(4);
    raysPerSecond << static_cast<double>(renderer_->rays()) / seconds;
    PassStats stats = parameters();
    const PassStats figures = {{"spp", std::to_string(renderer_->samplesDone())},
                               {"seconds", std::to_string(seconds_)},
                               {"rays", std::to_string(renderer_->rays())},
                               {"rays_per_second", raysPerSecond.str()},
                               {"dropped_samples", std::to_string(renderer_->droppedSamples())}};
    stats.insert(stats.end(), figures.begin(), figures.end());
    return stats;
}

}  // namespace penumbra
