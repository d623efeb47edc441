// The distribution ray-tracing pass of the `distribution` pipeline (the seed's two-pass method):
// raytrace/distribution_tracer.h, with the ambient term from the indirect-only radiosity solution
// an earlier radiosity pass made.
//
// Contribution: image layer "distribution" (light paths of distributionLightPaths()), and the
// requested AOVs.
#pragma once

#include "passes/sampling_pass.h"
#include "raytrace/distribution_tracer.h"

namespace penumbra {

class DistributionPass : public SamplingPass {
  public:
    explicit DistributionPass(DistributionSettings settings) : settings_(settings) {}

    std::string type() const override { return "distribution"; }
    std::string lightPaths() const override { return distributionLightPaths(); }
    std::set<std::string> needs() const override { return {"radiosity"}; }
    PassStats parameters() const override;

  protected:
    RadianceEstimator makeEstimator(PassContext& context) override;
    std::string activity() const override { return "distribution ray tracing"; }

  private:
    DistributionSettings settings_;
    std::shared_ptr<const RadiositySolution> radiosity_;
    std::unique_ptr<DistributionTracer> tracer_;
};

}  // namespace penumbra
