// What every pass that forms its image by sampling camera rays shares (path tracing, distribution
// ray tracing, the caustic pass's view, the radiosity view): an ImageRenderer over the pass's
// radiance estimator, one sample per pixel per run() step until RenderSettings::spp or the
// pipeline's time limit (Pipeline::run asks stopEarly()), a progress bar (of samples, or of the
// time left when there is a limit), the contribution published under the pass's type with the
// AOVs, and the figures of the image.
#pragma once

#include "core/progress.h"
#include "passes/pass.h"
#include "raytrace/image_renderer.h"

#include <chrono>
#include <memory>

namespace penumbra {

class SamplingPass : public Pass {
  public:
    // Makes the estimator (makeEstimator()) and the renderer.
    void prepare(PassContext& context) override;
    // Renders one sample per pixel; finished after sampleTarget() of them, or when adaptive
    // sampling has stopped every pixel. Then publishes the image.
    bool run(PassContext& context) override;
    // Publishes the image of the samples taken so far, if the pass usesTimeLimit().
    bool stopEarly(PassContext& context) override;
    // The renderer's reconstruction of its correction (ImageRenderer::reconstructionSeconds).
    std::chrono::steady_clock::duration publishingTime() const override;
    // parameters(), then samplingFigures().
    PassStats stats() const override;

    // The estimator the pass forms its image with, once prepared: what else measures the scene
    // as this pass sees it (the sensors of `penumbra illuminance`) uses the same one. It refers
    // to the pass and to the pipeline's products, so it is valid while they live.
    const RadianceEstimator& estimator() const { return estimator_; }

  protected:
    // spp, mean_spp, seconds, rays, rays_per_second, dropped_samples.
    PassStats samplingFigures() const;
    // The estimator of one camera ray's radiance, built once the pipeline's products exist. The
    // objects it refers to must live as long as the pass.
    virtual RadianceEstimator makeEstimator(PassContext& context) = 0;
    // The label of the progress bar, e.g. "path tracing".
    virtual std::string activity() const = 0;
    // The samples per pixel to take, and whether the pipeline's time limit stops the pass: a
    // pass whose image converges in few samples (the caustic map's view) takes a fixed number
    // and leaves the time to the passes after it.
    virtual int sampleTarget(const RenderSettings& settings) const { return settings.spp; }
    virtual bool usesTimeLimit() const { return true; }
    // The width in pixels, at one sample per pixel, of the reconstruction filter of the
    // estimator's corrections (ImageRenderer); 0 for none.
    virtual float correctionSigma() const { return 0.0f; }
    // The names of the light groups the estimator files its light by (PathRadiance::groups), once
    // it is made: each is published as the layer "light.NAME", added to the other passes' layer
    // of that name. Empty for an estimator that does not.
    virtual std::vector<std::string> lightGroups() const { return {}; }

  private:
    RadianceEstimator estimator_;
    std::unique_ptr<ImageRenderer> renderer_;
    std::unique_ptr<Progress> progress_;
    void publish(PassContext& context);

    std::chrono::steady_clock::time_point start_;
    bool timed_ = false;  // the progress bar measures milliseconds to the deadline, not samples
    double seconds_ = 0.0;
};

}  // namespace penumbra
