#include "raytrace/image_renderer.h"

#include "core/errors.h"
#include "core/sampler.h"
#include "raytrace/correction_filter.h"

#include <algorithm>

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

namespace penumbra {

namespace {

// Tiles of 16 x 16 pixels balance the load on two to many cores without much scheduling cost.
constexpr int kTileSize = 16;

// The light-path component an AOV name stands for, or -1.
int componentIndex(const std::string& name) {
    const auto it = std::find(kPathComponentNames.begin(), kPathComponentNames.end(), name);
    return it == kPathComponentNames.end() ? -1
                                           : static_cast<int>(it - kPathComponentNames.begin());
}

}  // namespace

std::vector<std::string> expandAovNames(const std::vector<std::string>& names) {
    std::vector<std::string> expanded;
    const auto add = [&expanded](const std::string& name) {
        if (std::find(expanded.begin(), expanded.end(), name) == expanded.end())
            expanded.push_back(name);
    };
    for (const std::string& name : names) {
        if (name != "components") {
            add(name);
            continue;
        }
        for (const std::string_view component : kPathComponentNames)
            add(std::string(component));
    }
    return expanded;
}

bool isComponentAov(const std::string& name) {
    return componentIndex(name) >= 0;
}

bool isDerivedAov(const std::string& name) {
    return name == "luminance";
}

std::vector<AovSpec> aovSpecs(const std::vector<std::string>& names) {
    std::vector<AovSpec> specs;
    for (const std::string& name : names) {
        if (name != "albedo" && name != "normal" && name != "depth" && name != "spp" &&
            name != "illuminance" && !isDerivedAov(name) && !isComponentAov(name)) {
            throw UsageError("--aov: unknown layer '" + name +
                             "'; valid: albedo, normal, depth, spp, illuminance, luminance, "
                             "emission, direct, indirect, specular, components (the last four)");
        }
        if (name == "spp") {
            specs.push_back({name, {"N"}});
        } else if (name == "normal") {
            specs.push_back({name, {"X", "Y", "Z"}});
        } else if (name == "depth") {
            specs.push_back({name, {"Z"}});
        } else if (name == "luminance") {
            specs.push_back({name, {"Y"}});
        } else {
            specs.push_back({name, {"R", "G", "B"}});
        }
    }
    return specs;
}

namespace {

// The AOVs a renderer's film holds: all but the derived ones.
std::vector<std::string> rendererAovs(std::vector<std::string> names) {
    std::erase_if(names, isDerivedAov);
    return names;
}

Vec3 aovValue(const std::string& name, const SurfaceGuide& hit) {
    if (!hit.valid)
        return Vec3(0.0f);
    if (name == "albedo")
        return hit.albedo;
    if (name == "normal")
        return hit.normal;
    return Vec3(hit.depth);
}

}  // namespace

ImageRenderer::ImageRenderer(const Camera& camera, const RenderSettings& settings,
                             RadianceEstimator estimator, float correctionSigma,
                             SurfaceIrradiance surfaceIrradiance,
                             std::vector<std::string> lightGroups)
    : camera_(camera),
      settings_(settings),
      estimator_(std::move(estimator)),
      surfaceIrradiance_(std::move(surfaceIrradiance)),
      filter_(parseFilter(settings.filter)),
      aovNames_(rendererAovs(settings.aovs)),
      lightGroups_(std::move(lightGroups)),
      correctionSigma_(correctionSigma),
      film_(settings.width, settings.height, filmLayers()),
      converged_(static_cast<size_t>(settings.width) * settings.height, 0),
      activePixels_(converged_.size()) {
    const bool illuminance =
        std::find(aovNames_.begin(), aovNames_.end(), "illuminance") != aovNames_.end();
    if (illuminance && !surfaceIrradiance_)
        throw std::logic_error("ImageRenderer: the illuminance AOV needs a SurfaceIrradiance");
}

std::vector<AovSpec> ImageRenderer::filmLayers() {
    std::vector<AovSpec> layers = aovSpecs(aovNames_);
    for (const std::string& aov : aovNames_)
        aovComponents_.push_back(componentIndex(aov));
    const auto addLayer = [&layers](AovSpec spec) {
        layers.push_back(std::move(spec));
        return static_cast<int>(layers.size()) - 1;
    };
    for (const std::string& group : lightGroups_) {
        const int layer = addLayer({"light." + group});
        if (firstLightGroupLayer_ < 0)
            firstLightGroupLayer_ = layer;
    }
    if (correctionSigma_ <= 0.0f)
        return layers;
    correctionLayer_ = addLayer({"correction"});
    correctionSquaredLayer_ = addLayer({"correction_squared"});
    for (const int component : aovComponents_)
        componentCorrectionLayers_.push_back(component >= 0 ? addLayer({"correction"}) : -1);
    // The filter's guide: the first diffuse vertex's features (FirstHit::firstDiffuse).
    normalLayer_ = addLayer(aovSpecs({"normal"}).front());
    depthLayer_ = addLayer(aovSpecs({"depth"}).front());
    albedoLayer_ = addLayer(aovSpecs({"albedo"}).front());
    return layers;
}

float ImageRenderer::correctionSigma() const {
    if (correctionSigma_ <= 0.0f)
        return 0.0f;
    return std::min(correctionFilterSigma(correctionSigma_, samplesDone_), widestCorrectionSigma_);
}

double ImageRenderer::reconstructionSeconds() const {
    if (correctionLayer_ < 0)
        return 0.0;
    const int layers = 1 + static_cast<int>(std::count_if(componentCorrectionLayers_.begin(),
                                                          componentCorrectionLayers_.end(),
                                                          [](int layer) { return layer >= 0; }));
    return reconstructionVisits(film_.width(), film_.height(), correctionSigma(), layers) *
           secondsPerReconstructionVisit();
}

void ImageRenderer::limitReconstruction(double seconds) {
    seconds = std::max(seconds, 0.0);
    // Each narrowing by a fifth cuts the window's area by about a third.
    while (correctionSigma() > 0.0f && reconstructionSeconds() > seconds) {
        widestCorrectionSigma_ = 0.8f * correctionSigma();
        reconstruction_.reset();
    }
}

const ImageRenderer::CorrectionReconstruction& ImageRenderer::correctionReconstruction() const {
    if (reconstruction_ && reconstruction_->samplesTaken == samplesTaken_)
        return *reconstruction_;
    auto r = std::make_unique<CorrectionReconstruction>(
        CorrectionReconstruction{film_.resolveAov(normalLayer_),
                                 film_.resolveAov(depthLayer_),
                                 film_.resolveAov(albedoLayer_),
                                 {},
                                 samplesTaken_});
    // The variance of each pixel's mean correction: the sample variance over n - 1 samples
    // (unbiased), over n; unknown (negative) below two samples.
    const Image mean = film_.resolveAov(correctionLayer_);
    const Image meanSquare = film_.resolveAov(correctionSquaredLayer_);
    Image variance(mean.width(), mean.height(), mean.channelNames());
    for (int y = 0; y < mean.height(); ++y) {
        for (int x = 0; x < mean.width(); ++x) {
            const double n = film_.sampleCount({x, y});
            for (int c = 0; c < mean.channels(); ++c) {
                const double spread =
                    double(meanSquare.at(x, y, c)) - sqr(double(mean.at(x, y, c)));
                variance.at(x, y, c) = n >= 2.0 ? float(std::max(spread, 0.0) / (n - 1.0)) : -1.0f;
            }
        }
    }
    r->widths = chooseFilterWidths(NoisyImage{mean, variance},
                                   FilterGuide{r->normal, r->depth, r->albedo}, correctionSigma());
    reconstruction_ = std::move(r);
    return *reconstruction_;
}

Image ImageRenderer::withReconstructedCorrection(Image image, int correctionLayer) const {
    const CorrectionReconstruction& r = correctionReconstruction();
    const Image correction = film_.resolveAov(correctionLayer);
    const Image reconstructed =
        filterCorrection(correction, FilterGuide{r.normal, r.depth, r.albedo}, r.widths);
    const std::span<float> out = image.pixels();
    const std::span<const float> raw = correction.pixels(), smooth = reconstructed.pixels();
    for (size_t i = 0; i < out.size(); ++i)
        out[i] += smooth[i] - raw[i];
    return image;
}

void ImageRenderer::addCorrection(IVec2 pixel, const PathRadiance& L, const FirstHit& firstHit) {
    const Color correction = L.correction();
    film_.addAov(pixel, correctionLayer_, correction);
    film_.addAov(pixel, correctionSquaredLayer_, correction * correction);
    for (size_t a = 0; a < aovNames_.size(); ++a) {
        if (componentCorrectionLayers_[a] >= 0)
            film_.addAov(pixel, componentCorrectionLayers_[a],
                         L.corrections[static_cast<size_t>(aovComponents_[a])]);
    }
    // Where the path met no diffuse vertex (a mirror reflecting the void), the first hit.
    const SurfaceGuide& guide = firstHit.firstDiffuse.valid
                                    ? firstHit.firstDiffuse
                                    : static_cast<const SurfaceGuide&>(firstHit);
    film_.addAov(pixel, normalLayer_, aovValue("normal", guide));
    film_.addAov(pixel, depthLayer_, aovValue("depth", guide));
    film_.addAov(pixel, albedoLayer_, aovValue("albedo", guide));
}

Image ImageRenderer::resolve() const {
    if (correctionLayer_ < 0)
        return film_.resolve();
    return withReconstructedCorrection(film_.resolve(), correctionLayer_);
}

Image ImageRenderer::resolveAov(size_t aov) const {
    if (aovNames_.at(aov) == "spp")
        return film_.resolveSampleCounts();
    Image image = film_.resolveAov(static_cast<int>(aov));
    if (correctionLayer_ >= 0 && componentCorrectionLayers_[aov] >= 0)
        return withReconstructedCorrection(std::move(image), componentCorrectionLayers_[aov]);
    return image;
}

Image ImageRenderer::resolveLightGroup(size_t group) const {
    return film_.resolveAov(firstLightGroupLayer_ + static_cast<int>(group));
}

Color ImageRenderer::irradianceAt(const FirstHit& firstHit, Sampler& sampler,
                                  PathCounters& counters) const {
    if (!firstHit.valid)
        return Color(0.0f);
    const Color E =
        surfaceIrradiance_(Sensor{firstHit.position, firstHit.viewerSideNormal}, sampler, counters);
    // The film drops a sample whose radiance is not finite; a non-finite irradiance is dropped
    // from its layer the same way, as 0 (a bug, as there).
    return isFinite(E) ? E : Color(0.0f);
}

void ImageRenderer::renderSamplePass() {
    struct Counts {
        uint64_t rays = 0, dropped = 0, converged = 0;
    };
    const float threshold = settings_.noiseThreshold;
    const bool adaptive = threshold > 0.0f && samplesDone_ + 1 >= RenderSettings::kAdaptiveMinSpp;
    tbb::combinable<Counts> counts;
    const uint32_t sampleIndex = static_cast<uint32_t>(samplesDone_);
    const bool wantFirstHit = !aovNames_.empty() || correctionLayer_ >= 0;
    tbb::parallel_for(
        tbb::blocked_range2d<int>(0, settings_.height, kTileSize, 0, settings_.width, kTileSize),
        [&](const tbb::blocked_range2d<int>& tile) {
            Sampler sampler(settings_.seed);
            PathCounters counters;
            uint64_t dropped = 0, converged = 0;
            for (int y = tile.rows().begin(); y < tile.rows().end(); ++y) {
                for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
                    const IVec2 pixel(x, y);
                    uint8_t& pixelConverged =
                        converged_[static_cast<size_t>(y) * settings_.width + x];
                    if (pixelConverged)
                        continue;
                    sampler.startPixelSample(pixel, sampleIndex);
                    const Vec2 offset = filter_.sampleOffset(sampler.getPixel2D());
                    const Ray ray = camera_.generateRay(Vec2(pixel) + Vec2(0.5f) + offset);
                    FirstHit firstHit;
                    const PathRadiance components =
                        estimator_(ray, sampler, wantFirstHit ? &firstHit : nullptr, counters);
                    const Color L = components.total();
                    // NaN and Inf never reach the film: dropped and counted (CONTRIBUTING.md).
                    if (!isFinite(L)) {
                        ++dropped;
                        continue;
                    }
                    film_.addSample(pixel, L, 1.0f);
                    for (size_t a = 0; a < aovNames_.size(); ++a) {
                        const int component = aovComponents_[a];
                        if (component >= 0)
                            film_.addAov(pixel, static_cast<int>(a),
                                         components.components[static_cast<size_t>(component)]);
                        else if (aovNames_[a] == "illuminance")
                            film_.addAov(pixel, static_cast<int>(a),
                                         irradianceAt(firstHit, sampler, counters));
                        else if (aovNames_[a] != "spp")
                            film_.addAov(pixel, static_cast<int>(a),
                                         aovValue(aovNames_[a], firstHit));
                    }
                    for (size_t g = 0; g < lightGroups_.size(); ++g) {
                        film_.addAov(pixel, firstLightGroupLayer_ + static_cast<int>(g),
                                     components.groups.at(g));
                    }
                    if (correctionLayer_ >= 0)
                        addCorrection(pixel, components, firstHit);
                    // Each pixel decides from its own samples only: the image stays a function
                    // of the seed whatever the thread count.
                    if (adaptive && film_.relativeStandardError(pixel) < threshold) {
                        pixelConverged = 1;
                        ++converged;
                    }
                }
            }
            Counts& local = counts.local();
            local.rays += counters.rays;
            local.dropped += dropped;
            local.converged += converged;
        });
    samplesTaken_ += activePixels_;
    counts.combine_each([this](const Counts& c) {
        rays_ += c.rays;
        dropped_ += c.dropped;
        activePixels_ -= c.converged;
    });
    ++samplesDone_;
}

}  // namespace penumbra
