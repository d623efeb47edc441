// The composite: the beauty image is the sum of the images the passes contribute (each counting
// a disjoint set of light paths, which the planner proved), and each contribution stays a layer
// of its own in a multi-layer EXR, so that a compositor can rebalance them.
//
// A pipeline composites after its last pass on its own; a script may place a `composite` pass
// explicitly (it must be the last).
#pragma once

#include "passes/pass.h"
#include "passes/pass_parameters.h"

#include <memory>

namespace penumbra {

// layers["beauty"] = the sum of context.contributions, in float, pixel by pixel; a black RGB
// image of the render's size when no pass contributed (every one skipped).
void compositeContributions(PassContext& context);

class CompositePass : public Pass {
  public:
    // The pass of a script's [[pass]] table of type "composite" (no parameters).
    static std::unique_ptr<Pass> fromScript(const ScriptTable&, const PassOverrides&) {
        return std::make_unique<CompositePass>();
    }
    std::string type() const override { return "composite"; }
    std::string lightPaths() const override { return ""; }
    bool rendersMedia() const override { return true; }  // it only sums the others' images
    void prepare(PassContext&) override {}
    bool run(PassContext& context) override;
    PassStats stats() const override { return stats_; }

  private:
    PassStats stats_;
};

}  // namespace penumbra
