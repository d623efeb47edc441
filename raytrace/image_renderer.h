// Forms an image from a per-ray radiance estimator: whole passes of one sample per pixel over
// tiles in parallel (oneTBB), a filter-importance-sampled pixel footprint, NaN/Inf samples
// dropped and counted, and optional AOV layers from the first hit. Every image-forming pass that
// samples camera rays renders through it (passes/sampling_pass.h).
#pragma once

#include "core/camera.h"
#include "core/film.h"
#include "core/render_settings.h"
#include "raytrace/radiance_estimator.h"
#include "raytrace/sensor_irradiance.h"

#include <atomic>
#include <chrono>
#include <functional>
#include <limits>
#include <memory>

namespace penumbra {

// AOV names as the user lists them, with "components" standing for the four light-path
// components (core/path_components.h) in their order; repeats are dropped.
std::vector<std::string> expandAovNames(const std::vector<std::string>& names);
// The film layers for AOV names (albedo, normal, depth, spp, illuminance, luminance, and the
// components emission, direct, indirect, specular); UsageError for an unknown name.
std::vector<AovSpec> aovSpecs(const std::vector<std::string>& names);
// Whether an AOV is a light-path component: such layers sum to the beauty, so every pass adds its
// share to them instead of replacing them.
bool isComponentAov(const std::string& name);
// Whether an AOV is made from the beauty once the passes are composited (`luminance`, its Rec.
// 709 luminance Y in cd/m²), not by the passes' renderers.
bool isDerivedAov(const std::string& name);

// One sample of the irradiance (lux per channel) at a sensor lying on the first visible surface,
// for the `illuminance` AOV: sampleSensorIrradiance over the pass's own estimator, as Radiance's
// `rpict -i` computes irradiance in place of radiance at the surfaces it sees.
using SurfaceIrradiance = std::function<Color(const Sensor&, Sampler&, PathCounters&)>;

class ImageRenderer {
  public:
    // The camera and the settings are referred to, not copied: they must outlive the renderer.
    // correctionSigma > 0: the estimator's corrections (PathRadiance::corrections) are kept
    // apart and reconstructed with filterCorrection() (raytrace/correction_filter.h), of this
    // width in pixels at one sample per pixel, each pixel's width then chosen around it by
    // chooseFilterWidths(); 0: they stay in the image as they are.
    // surfaceIrradiance fills the `illuminance` AOV; it is needed when settings.aovs asks for it.
    // lightGroups: the names of the groups the estimator files its light by
    // (PathRadiance::groups, one entry per name), each kept in a layer of its own; empty for none.
    ImageRenderer(const Camera& camera, const RenderSettings& settings, RadianceEstimator estimator,
                  float correctionSigma = 0.0f, SurfaceIrradiance surfaceIrradiance = {},
                  std::vector<std::string> lightGroups = {});

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
    // took. With a correction kept apart, its reconstruction replaces its per-pixel mean in the
    // radiance and in the light-path components.
    Image resolve() const;
    Image resolveAov(size_t aov) const;
    // The width (pixels) of the correction's reconstruction filter now; 0 without one.
    float correctionSigma() const;
    // Seconds that reconstructing the correction would take now, for the resolve() and every
    // component layer's resolveAov() (an upper bound from reconstructionVisits); 0 without one.
    double reconstructionSeconds() const;
    // Narrows the correction's filter, if it must, so that its reconstruction takes at most
    // `seconds` by that bound (none at all below the filter's smallest width: the per-pixel
    // means, unbiased and noisier): under a time limit, a narrower filter rather than a late
    // image. Holds for every later resolve.
    void limitReconstruction(double seconds);
    // AOV names in film order.
    const std::vector<std::string>& aovNames() const { return aovNames_; }
    // The light groups' names, and the radiance of group `group` (an index into them).
    const std::vector<std::string>& lightGroups() const { return lightGroups_; }
    Image resolveLightGroup(size_t group) const;

  private:
    // What reconstructs the correction layers after the samples taken so far: the filter's guide
    // and each pixel's width, chosen from the correction's sum (chooseFilterWidths) and applied
    // to its share of each component too, so the components still sum to the image.
    struct CorrectionReconstruction {
        Image normal, depth, albedo;
        std::vector<float> widths;
        uint64_t samplesTaken = 0;
    };
    const CorrectionReconstruction& correctionReconstruction() const;
    // The per-pixel mean of film layer `layer`, minus its correction's mean plus the
    // correction's reconstruction (correctionLayer: its film layer).
    Image withReconstructedCorrection(Image image, int correctionLayer) const;
    // The film's layers: the user's AOVs, then those of a correction kept apart (filling
    // aovComponents_ and the layer indices below).
    std::vector<AovSpec> filmLayers();
    // One sample of the `illuminance` AOV at the first visible surface; 0 where the ray left the
    // scene.
    Color irradianceAt(const FirstHit& firstHit, Sampler& sampler, PathCounters& counters) const;
    // Adds a sample's correction and the guide layers the user did not ask for.
    void addCorrection(IVec2 pixel, const PathRadiance& L, const FirstHit& firstHit);

    const Camera& camera_;
    const RenderSettings& settings_;
    RadianceEstimator estimator_;
    SurfaceIrradiance surfaceIrradiance_;
    PixelFilter filter_;
    std::vector<std::string> aovNames_;
    std::vector<int> aovComponents_;  // per AOV: its PathComponent, or -1 for a first-hit AOV
    std::vector<std::string> lightGroups_;
    int firstLightGroupLayer_ = -1;  // the film layer of the first light group, the others after it
    float correctionSigma_;
    // The widest filter limitReconstruction() allows (pixels).
    float widestCorrectionSigma_ = std::numeric_limits<float>::infinity();
    // Film layers past the user's AOVs, with a correction kept apart: the correction's sum over
    // the components and its square (for the variance of its mean), its share of each component
    // AOV (per AOV, or -1), and the filter's guide (the first diffuse vertex's features:
    // FirstHit::firstDiffuse).
    int correctionLayer_ = -1, correctionSquaredLayer_ = -1;
    std::vector<int> componentCorrectionLayers_;
    int normalLayer_ = -1, depthLayer_ = -1, albedoLayer_ = -1;
    // The last reconstruction, kept while no sample is added: resolve() and each component's
    // resolveAov() share it (so those calls must not run concurrently).
    mutable std::unique_ptr<CorrectionReconstruction> reconstruction_;
    Film film_;
    std::vector<uint8_t> converged_;  // per pixel: no more samples (adaptive sampling)
    size_t activePixels_;
    uint64_t samplesTaken_ = 0;
    int samplesDone_ = 0;
    uint64_t rays_ = 0;
    uint64_t dropped_ = 0;
};

}  // namespace penumbra
