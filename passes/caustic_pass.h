// The caustic pass of the `hybrid` pipeline: builds the caustic photon map (caustics/caustic_map.h:
// photons from the lights through specular vertices, stored at the first diffuse one) and forms
// its image by following camera rays through specular vertices to the first surface with a
// non-delta lobe, where the map's radiance estimate is taken.
//
// Contribution: image layer "caustics", light paths L S+ D S* E (the caustics seen directly or in
// mirrors); products "caustics" (those paths are counted: a path pass with `caustics = "auto"`
// leaves them out) and "caustic map" (the map, which a later radiosity pass takes into its
// solution and a later path pass reuses at its second diffuse vertex).
#pragma once

#include "caustics/caustic_map.h"
#include "passes/sampling_pass.h"

#include <algorithm>
#include <memory>

namespace penumbra {

class CausticPass : public SamplingPass {
  public:
    // Validates the settings (UsageError naming the key).
    explicit CausticPass(CausticSettings settings, int maxSpecularDepth = 16, int viewSpp = 16);

    std::string type() const override { return "caustics"; }
    std::string lightPaths() const override { return "L S+ D S* E"; }
    std::set<std::string> products() const override { return {"caustics", "caustic map"}; }
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
    CausticSettings settings_;
    int maxSpecularDepth_;
    int viewSpp_;
    std::shared_ptr<const CausticMap> map_;
};

}  // namespace penumbra
