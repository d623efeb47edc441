// Forms an image from a per-ray radiance estimator: whole passes of one sample per pixel over
// tiles in parallel (oneTBB), a filter-importance-sampled pixel footprint, NaN/Inf samples
// dropped and counted, and optional AOV layers from the first hit. Every image-forming pass
// (path tracing now; distribution ray tracing later) renders through it.
#pragma once

#include "core/camera.h"
#include "core/film.h"
#include "core/render_settings.h"
#include "raytrace/path_tracer.h"

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>

namespace penumbra {

// The film layers for AOV names (albedo, normal, depth); UsageError for an unknown name.
std::vector<AovSpec> aovSpecs(const std::vector<std::string>& names);

// Radiance estimate for one camera ray (see PathTracer::Li for the contract).
using RadianceEstimator = std::function<Color(const Ray&, Sampler&, FirstHit*, PathCounters&)>;

class ImageRenderer {
  public:
    ImageRenderer(const Camera& camera, const RenderSettings& settings,
                  RadianceEstimator estimator);

    // Renders one more sample per pixel (sample index samplesDone()).
    void renderSamplePass();
    int samplesDone() const { return samplesDone_; }
    uint64_t rays() const { return rays_; }
    uint64_t droppedSamples() const { return dropped_; }

    const Film& film() const { return film_; }
    // AOV names in film order (a subset of albedo, normal, depth).
    const std::vector<std::string>& aovNames() const { return aovNames_; }

  private:
    const Camera& camera_;
    const RenderSettings& settings_;
    RadianceEstimator estimator_;
    PixelFilter filter_;
    std::vector<std::string> aovNames_;
    Film film_;
    int samplesDone_ = 0;
    uint64_t rays_ = 0;
    uint64_t dropped_ = 0;
};

}  // namespace penumbra
