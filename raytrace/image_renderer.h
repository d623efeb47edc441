// Forms an image from a per-ray radiance estimator: whole passes of one sample per pixel over
// tiles in parallel (oneTBB), a filter-importance-sampled pixel footprint, NaN/Inf samples
// dropped and counted, and optional AOV layers from the first hit. Every image-forming pass that
// samples camera rays renders through it (passes/sampling_pass.h).
#pragma once

#include "core/camera.h"
#include "core/film.h"
#include "core/render_settings.h"
#include "raytrace/radiance_estimator.h"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>

namespace penumbra {

// AOV names as the user lists them, with "components" standing for the four light-path
// components (core/path_components.h) in their order; repeats are dropped.
std::vector<std::string> expandAovNames(const std::vector<std::string>& names);
// The film layers for AOV names (albedo, normal, depth, spp, and the components emission,
// direct, indirect, specular); UsageError for an unknown name.
std::vector<AovSpec> aovSpecs(const std::vector<std::string>& names);
// Whether an AOV is a light-path component: such layers sum to the beauty, so every pass adds its
// share to them instead of replacing them.
bool isComponentAov(const std::string& name);

class ImageRenderer {
  public:
    // The camera and the settings are referred to, not copied: they must outlive the renderer.
    ImageRenderer(const Camera& camera, const RenderSettings& settings,
                  RadianceEstimator estimator);

    // Renders one more sample per pixel (sample index samplesDone()), for every pixel that has
    // not converged under adaptive sampling (RenderSettings::noiseThreshold).
    void renderSamplePass();
    int samplesDone() const { return samplesDone_; }
    // Camera samples taken over all pixels and passes (below samplesDone() x pixels when
    // adaptive sampling stopped some).
    uint64_t samplesTaken() const { return samplesTaken_; }
    // Whether adaptive sampling has stopped every pixel.
    bool converged() const { return activePixels_ == 0; }
    uint64_t rays() const { return rays_; }
    uint64_t droppedSamples() const { return dropped_; }

    const Film& film() const { return film_; }
    // The radiance, and AOV layer `aov` (index into aovNames()); "spp" is the samples each pixel
    // took.
    Image resolve() const { return film_.resolve(); }
    Image resolveAov(size_t aov) const;
    // AOV names in film order.
    const std::vector<std::string>& aovNames() const { return aovNames_; }

  private:
    const Camera& camera_;
    const RenderSettings& settings_;
    RadianceEstimator estimator_;
    PixelFilter filter_;
    std::vector<std::string> aovNames_;
    std::vector<int> aovComponents_;  // per AOV: its PathComponent, or -1 for a first-hit AOV
    Film film_;
    std::vector<uint8_t> converged_;  // per pixel: no more samples (adaptive sampling)
    size_t activePixels_;
    uint64_t samplesTaken_ = 0;
    int samplesDone_ = 0;
    uint64_t rays_ = 0;
    uint64_t dropped_ = 0;
};

}  // namespace penumbra
