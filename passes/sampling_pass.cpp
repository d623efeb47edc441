#include "passes/sampling_pass.h"

#include "core/stats.h"

#include <algorithm>
#include <sstream>

namespace penumbra {

namespace {

// Publishes the renderer's image as the contribution `name` of a pass, and its AOV layers (adding
// the light-path components and the light groups to what earlier passes published:
// PassContext::addToLayer).
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
    const std::vector<std::string>& groups = renderer.lightGroups();
    for (size_t g = 0; g < groups.size(); ++g)
        context.addToLayer("light." + groups[g], renderer.resolveLightGroup(g));
}

}  // namespace

void SamplingPass::prepare(PassContext& context) {
    // The estimator first: it may find that there is nothing to correct (correctionSigma()).
    estimator_ = makeEstimator(context);
    const Scene& scene = context.scene;
    const RadianceEstimator& estimator = estimator_;
    const SurfaceIrradiance surfaceIrradiance =
        [&scene, &estimator](const Sensor& sensor, Sampler& sampler, PathCounters& counters) {
            return sampleSensorIrradiance(scene, estimator, sensor, sampler, counters);
        };
    renderer_ =
        std::make_unique<ImageRenderer>(context.camera, context.settings, estimator_,
                                        correctionSigma(), surfaceIrradiance, lightGroups());
    start_ = std::chrono::steady_clock::now();
    // With a time limit the bar measures the time left (in milliseconds), else samples.
    timed_ = context.deadline && usesTimeLimit();
    const double secondsLeft =
        timed_ ? std::max(std::chrono::duration<double>(*context.deadline - start_).count(), 0.0)
               : 0.0;
    const uint64_t total = timed_ ? static_cast<uint64_t>(secondsLeft * 1000.0)
                                  : static_cast<uint64_t>(sampleTarget(context.settings));
    progress_ = std::make_unique<Progress>(activity(), total, context.settings.quiet);
}

bool SamplingPass::run(PassContext& context) {
    renderer_->renderSamplePass();
    seconds_ = secondsSince(start_);
    if (timed_) {
        const uint64_t elapsed = static_cast<uint64_t>(seconds_ * 1000.0);
        progress_->advance(std::min(elapsed, progress_->total()) - progress_->done());
    } else {
        progress_->advance(1);
    }
    if (renderer_->samplesDone() < sampleTarget(context.settings) && !renderer_->converged())
        return false;
    publish(context);
    return true;
}

bool SamplingPass::stopEarly(PassContext& context) {
    if (!usesTimeLimit())
        return false;
    publish(context);
    return true;
}

std::chrono::steady_clock::duration SamplingPass::publishingTime() const {
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(renderer_->reconstructionSeconds()));
}

void SamplingPass::publish(PassContext& context) {
    progress_->finish();
    // What time is left bounds the correction's reconstruction: a narrower filter, not a late
    // image (the pipeline stopped the samples early enough for the full one, unless the first
    // step alone took the time).
    if (context.deadline) {
        renderer_->limitReconstruction(
            std::chrono::duration<double>(*context.deadline - std::chrono::steady_clock::now())
                .count());
    }
    publishRenderedImage(context, *renderer_, type());
}

PassStats SamplingPass::stats() const {
    PassStats stats = parameters();
    const PassStats figures = samplingFigures();
    stats.insert(stats.end(), figures.begin(), figures.end());
    return stats;
}

PassStats SamplingPass::samplingFigures() const {
    const double seconds = seconds_ > 0.0 ? seconds_ : 1e-9;
    const double pixels = static_cast<double>(renderer_->film().width()) *
                          static_cast<double>(renderer_->film().height());
    PassStats figures = {
        {"spp", std::to_string(renderer_->samplesDone())},
        {"mean_spp",
         formatStat(static_cast<double>(renderer_->samplesTaken()) / std::max(pixels, 1.0))},
        {"seconds", std::to_string(seconds_)},
        {"rays", std::to_string(renderer_->rays())},
        {"rays_per_second", formatStat(static_cast<double>(renderer_->rays()) / seconds)},
        {"dropped_samples", std::to_string(renderer_->droppedSamples())}};
    if (renderer_->correctionSigma() > 0.0f)
        figures.push_back({"correction_filter_sigma", formatStat(renderer_->correctionSigma())});
    return figures;
}

}  // namespace penumbra
