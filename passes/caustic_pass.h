// The caustic pass of the `hybrid` pipeline: builds the caustic photon map (caustics/caustic_map.h:
// photons from the lights through specular vertices, stored at the first diffuse one) and forms
// its image by following camera rays through specular vertices to the first surface with a
// non-delta lobe, where the map's radiance estimate is taken.
//
// Contribution: image layer "caustics", light paths L S+ D S* E (the caustics seen directly or in
// mirrors), which a path pass with `caustics = "auto"` then leaves out (countsCausticPaths);
// product: the caustic map, which a later radiosity pass takes into its solution and a later
// path pass reuses at its second diffuse vertex.
#pragma once

#include "caustics/caustic_map.h"
#include "passes/pass_parameters.h"
#include "passes/products.h"
#include "passes/sampling_pass.h"

#include <algorithm>
#include <memory>

namespace penumbra {

// Why a caustic pass has nothing to do for a scene: no specular surface, so no caustic path.
inline std::string causticPassSkipReason(const SceneContents& contents) {
    return contents.specular ? "" : "no surface has a specular lobe, so there are no caustic paths";
}

class CausticPass : public SamplingPass {
  public:
    // Specular vertices followed from the eye, and the view's samples per pixel.
    static constexpr int kDefaultMaxSpecularDepth = 16, kDefaultViewSpp = 16;
    // CausticSettings::photons and k of the pass's defaults, `photons = "auto"` and `k = "auto"`:
    // a count that grows with the render's budget (buildMap()), so that the map's bias vanishes
    // as the budget grows, and nearest photons that grow as its square root, so that its noise
    // does too.
    static constexpr int64_t kAutoPhotons = 0;
    static constexpr int kAutoK = 0;
    // The automatic count: kBasePhotons for up to kBaseSpp samples per pixel, in proportion to
    // the samples above; with a time limit, as many as the first kBasePhotons' rate fits in
    // kTimeShare of it, if more. Never more than kMaxStoredPhotons are kept (their memory).
    static constexpr int64_t kBasePhotons = 200000;
    static constexpr int kBaseSpp = 64;
    static constexpr double kTimeShare = 1.0 / 16.0;
    static constexpr double kMaxStoredPhotons = 8.0e6;
    // The automatic k: kBaseK with kBasePhotons, as the square root of the photons above, at
    // most kMaxAutoK (each estimate's cost grows with it).
    static constexpr int kBaseK = 50, kMaxAutoK = 500;
    static int automaticK(int64_t photons);
    // The pass's defaults: CausticSettings' with the automatic photon count and k.
    static CausticSettings defaultSettings() {
        CausticSettings settings;
        settings.photons = kAutoPhotons;
        settings.k = kAutoK;
        return settings;
    }

    // Validates the settings (UsageError naming the key).
    explicit CausticPass(CausticSettings settings, int maxSpecularDepth = kDefaultMaxSpecularDepth,
                         int viewSpp = kDefaultViewSpp);
    // The pass of a script's [[pass]] table of type "caustics": `method` picks the
    // reconstruction, a photon map (this pass) or stochastic progressive photon mapping
    // (ProgressiveCausticPass), and so the keys that are valid; each set is checked by its
    // validate function.
    static std::unique_ptr<Pass> fromScript(const ScriptTable& table, const PassOverrides&);

    std::string type() const override { return "caustics"; }
    std::string lightPaths() const override { return "L S+ D S* E"; }
    std::set<std::string> products() const override { return {products::kCausticMap}; }
    TransportFlags transportFlags() const override { return {true, false}; }
    std::string skipReason(const SceneContents& contents) const override;
    void adapt(const PipelineShape& shape) override {
        causticsTracedLater_ = shape.causticsTracedLater;
    }
    // Lets the pass step aside where a path pass after it would trace the caustics itself and
    // the lights look large from the specular surfaces, or the scene has a medium, which the
    // photons do not cross (skipReason): the corrected hybrid's.
    void yieldToPathTracerForLargeLights() { yields_ = true; }
    PassStats parameters() const override;
    PassStats stats() const override;

  protected:
    RadianceEstimator makeEstimator(PassContext& context) override;
    std::string activity() const override { return "caustics view"; }
    // The map is smooth: its view needs samples for the pixel footprint and the lobe choices of
    // specular chains only, and leaves a time limit to the path pass.
    int sampleTarget(const RenderSettings& settings) const override {
        return std::min(settings.spp, viewSpp_);
    }
    bool usesTimeLimit() const override { return false; }

  private:
    // Builds the map with the automatic photon count (kAutoPhotons) resolved for the render.
    std::shared_ptr<const CausticMap> buildMap(PassContext& context,
                                               const CausticSettings& seeded) const;

    CausticSettings settings_;
    int maxSpecularDepth_;
    int viewSpp_;
    bool yields_ = false;               // yieldToPathTracerForLargeLights()
    bool causticsTracedLater_ = false;  // PipelineShape::causticsTracedLater
    std::shared_ptr<const CausticMap> map_;
};

}  // namespace penumbra
