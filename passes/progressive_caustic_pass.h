// The caustic pass by stochastic progressive photon mapping (caustics/progressive_caustics.h;
// Hachisuka and Jensen 2009): each iteration traces one camera ray per pixel through specular
// vertices to its first diffuse vertex (the pixel's visible point), shoots a new batch of
// photons and updates every pixel's radius and flux, so that the caustic converges to the right
// answer as iterations are added instead of to a blurred one. `method = "progressive"` of a
// caustics pass.
//
// Contribution: image layer "caustics", light paths L S+ D S* E, like the photon-map pass (a path
// pass leaves those paths to it: countsCausticPaths), but no caustic map for a later pass to
// reuse.
// A visible point is the first vertex with a non-delta lobe: the caustic seen at a further vertex
// through a smooth coat's reflection (a surface with both kinds of lobe) is left out.
#pragma once

#include "caustics/progressive_caustics.h"
#include "passes/caustic_pass.h"

#include <memory>

namespace penumbra {

class ProgressiveCausticPass : public Pass {
  public:
    // Validates the settings (UsageError naming the key).
    ProgressiveCausticPass(ProgressiveCausticSettings settings, int iterations,
                           int maxSpecularDepth);
    ~ProgressiveCausticPass() override;
    // The pass of a [[pass]] table of type "caustics" with method = "progressive".
    static std::unique_ptr<Pass> fromScript(const ScriptTable& table, const PassOverrides&);

    std::string type() const override { return "caustics"; }
    std::string lightPaths() const override { return "L S+ D S* E"; }
    TransportFlags transportFlags() const override { return {true, false}; }
    std::string skipReason(const SceneContents& contents) const override {
        return causticPassSkipReason(contents);
    }
    PassStats parameters() const override;
    void prepare(PassContext& context) override;
    // One iteration; finished after `iterations` of them, or under a time limit once the
    // iterations have taken kTimeShare of it (at least one iteration).
    bool run(PassContext& context) override;
    // At the pipeline's deadline: the caustic of the iterations so far.
    bool stopEarly(PassContext& context) override;
    PassStats stats() const override;

  private:
    // The share of a time limit the iterations may take; the rest is the later passes'.
    static constexpr double kTimeShare = 0.25;

    // Contributes the image of the iterations so far.
    void publish(PassContext& context);

    ProgressiveCausticSettings settings_;
    int iterations_;
    int maxSpecularDepth_;
    std::unique_ptr<ProgressiveCaustics> caustics_;
    std::unique_ptr<class Progress> progress_;
    double seconds_ = 0.0;
};

}  // namespace penumbra
