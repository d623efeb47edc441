#include "passes/sampling_pass.h"

#include "core/stats.h"

#include <algorithm>
#include <sstream>

namespace penumbra {

void publishRenderedImage(PassContext& context, const ImageRenderer& renderer,
                          const std::string& name) {
    context.contribute(name, renderer.resolve());
    const std::vector<std::string>& aovs = renderer.aovNames();
    for (size_t a = 0; a < aovs.size(); ++a) {
        if (isComponentAov(aovs[a]))
            context.addToLayer(aovs[a], renderer.resolveAov(a));
        else
            context.layers[aovs[a]] = renderer.resolveAov(a);
    }
}

void SamplingPass::prepare(PassContext& context) {
    renderer_ =
        std::make_unique<ImageRenderer>(context.camera, context.settings, makeEstimator(context));
    const RenderSettings& s = context.settings;
    // With a time limit the bar measures time (in milliseconds), else samples.
    const bool timed = s.timeLimit > 0.0 && usesTimeLimit();
    const uint64_t total = timed ? static_cast<uint64_t>(s.timeLimit * 1000.0)
                                 : static_cast<uint64_t>(sampleTarget(s));
    progress_ = std::make_unique<Progress>(activity(), total, s.quiet);
    start_ = std::chrono::steady_clock::now();
}

bool SamplingPass::run(PassContext& context) {
    const RenderSettings& s = context.settings;
    const auto passStart = std::chrono::steady_clock::now();
    renderer_->renderSamplePass();
    lastPassSeconds_ = secondsSince(passStart);
    seconds_ = secondsSince(start_);

    bool done = renderer_->samplesDone() >= sampleTarget(s) || renderer_->converged();
    if (s.timeLimit > 0.0 && usesTimeLimit()) {
        // Stop at whole passes: before a pass that would end past the limit.
        done = done || seconds_ + lastPassSeconds_ > s.timeLimit;
        progress_->advance(static_cast<uint64_t>(std::min(seconds_, s.timeLimit) * 1000.0) -
                           progress_->done());
    } else {
        progress_->advance(1);
    }
    if (!done)
        return false;
    progress_->finish();
    publishRenderedImage(context, *renderer_, type());
    return true;
}

PassStats SamplingPass::stats() const {
    const double seconds = seconds_ > 0.0 ? seconds_ : 1e-9;
    std::ostringstream raysPerSecond;
    raysPerSecond.precision(4);
    raysPerSecond << static_cast<double>(renderer_->rays()) / seconds;
    PassStats stats = parameters();
    const double pixels = static_cast<double>(renderer_->film().width()) *
                          static_cast<double>(renderer_->film().height());
    const PassStats figures = {
        {"spp", std::to_string(renderer_->samplesDone())},
        {"mean_spp",
         formatStat(static_cast<double>(renderer_->samplesTaken()) / std::max(pixels, 1.0))},
        {"seconds", std::to_string(seconds_)},
        {"rays", std::to_string(renderer_->rays())},
        {"rays_per_second", raysPerSecond.str()},
        {"dropped_samples", std::to_string(renderer_->droppedSamples())}};
    stats.insert(stats.end(), figures.begin(), figures.end());
    return stats;
}

}  // namespace penumbra
