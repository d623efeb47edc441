// The distribution ray-tracing pass of the `distribution` pipeline (the seed's two-pass method):
// raytrace/distribution_tracer.h, with the ambient term from the indirect-only radiosity solution
// an earlier radiosity pass made; or, as the `whitted` pass, with a constant ambient term (the
// crudest preview, the seed's Eq. 2).
//
// Contribution: image layer "distribution" (light paths of distributionLightPaths()), and the
// requested AOVs.
#pragma once

#include "passes/sampling_pass.h"
#include "raytrace/distribution_tracer.h"

namespace penumbra {

class DistributionPass : public SamplingPass {
  public:
    // With a constant ambient term instead of the radiosity solution (settings.ambient), the
    // pass is Whitted's ray tracing (type "whitted").
    enum class Ambient { Radiosity, Constant };

    DistributionPass(DistributionSettings settings, Ambient ambient = Ambient::Radiosity)
        : settings_(settings), ambient_(ambient) {}

    std::string type() const override {
        return ambient_ == Ambient::Radiosity ? "distribution" : "whitted";
    }
    // Whitted's ambient constant stands for no light path: the plan names L D D+ as missing.
    std::string lightPaths() const override {
        return ambient_ == Ambient::Radiosity ? distributionLightPaths() : "L S* E | L D S* E";
    }
    std::set<std::string> needs() const override {
        if (ambient_ == Ambient::Radiosity)
            return {"radiosity"};
        return {};
    }
    PassStats parameters() const override;

  protected:
    RadianceEstimator makeEstimator(PassContext& context) override;
    std::string activity() const override { return "distribution ray tracing"; }

  private:
    DistributionSettings settings_;
    Ambient ambient_;
    std::shared_ptr<const RadiositySolution> radiosity_;
    std::unique_ptr<DistributionTracer> tracer_;
};

}  // namespace penumbra
