// What every pass that forms its image by sampling camera rays shares (path tracing, distribution
// ray tracing, the caustic pass's view): an ImageRenderer over the pass's radiance estimator,
// one sample per pixel per run() step until RenderSettings::spp or the time limit, a progress bar,
// the contribution published under the pass's type with the AOVs, and the figures of the image.
#pragma once

#include "core/progress.h"
#include "passes/pass.h"
#include "raytrace/image_renderer.h"

#include <chrono>
#include <memory>

namespace penumbra {

// Publishes the renderer's image as the contribution `name` of a pass, and its AOV layers (adding
// the light-path components to what earlier passes published: PassContext::addToLayer).
void publishRenderedImage(PassContext& context, const ImageRenderer& renderer,
                          const std::string& name);

class SamplingPass : public Pass {
  public:
    // Makes the estimator (makeEstimator()) and the renderer.
    void prepare(PassContext& context) override;
    // Renders one sample per pixel; finished after RenderSettings::spp of them or before a
    // sample pass that would end past the time limit. Then publishes the image.
    bool run(PassContext& context) override;
    // parameters(), then spp, seconds, rays, rays_per_second, dropped_samples.
    PassStats stats() const override;

  protected:
    // The estimator of one camera ray's radiance, built once the pipeline's products exist. The
    // objects it refers to must live as long as the pass.
    virtual RadianceEstimator makeEstimator(PassContext& context) = 0;
    // The label of the progress bar, e.g. "path tracing".
    virtual std::string activity() const = 0;
    // The samples per pixel to take, and whether the pass spends the time limit on more: a pass
    // whose image converges in few samples (the caustic map's view) takes a fixed number and
    // leaves the time to the passes after it.
    virtual int sampleTarget(const RenderSettings& settings) const { return settings.spp; }
    virtual bool usesTimeLimit() const { return true; }

  private:
    std::unique_ptr<ImageRenderer> renderer_;
    std::unique_ptr<Progress> progress_;
    std::chrono::steady_clock::time_point start_;
    double lastPassSeconds_ = 0.0;
    double seconds_ = 0.0;
};

}  // namespace penumbra
