// The distribution ray-tracing pass of the `distribution` pipeline (the seed's two-pass method):
// raytrace/distribution_tracer.h, with the ambient term from the indirect-only radiosity solution
// an earlier radiosity pass made; or, as the `whitted` pass, with a constant ambient term (the
// crudest preview, the seed's Eq. 2), set by the user or taken from a radiosity solution's mean.
//
// Contribution: image layer "distribution" (light paths of distributionLightPaths()), and the
// requested AOVs. Without its solution (a solve abandoned at the time limit) the layer is the
// path tracer's instead: every path but the caustics L S+ D S* E another pass counts.
#pragma once

#include "passes/pass_parameters.h"
#include "passes/products.h"
#include "passes/reused_products.h"
#include "passes/sampling_pass.h"
#include "raytrace/distribution_tracer.h"

#include <optional>

namespace penumbra {

class DistributionPass : public SamplingPass {
  public:
    // With a constant ambient term instead of the radiosity solution, the pass is Whitted's ray
    // tracing (type "whitted"): the user's settings.ambient, or the mean reflected radiance of
    // an earlier radiosity pass's solution (meanReflectedRadiance()).
    enum class Ambient { Radiosity, Constant, RadiosityMean };

    DistributionPass(DistributionSettings settings, Ambient ambient = Ambient::Radiosity)
        : settings_(settings), ambient_(ambient) {}
    // The passes of a script's [[pass]] tables of types "distribution" and "whitted" (whose
    // `ambient` is a radiance or "radiosity", the solution's mean).
    static std::unique_ptr<Pass> fromScript(const ScriptTable& table, const PassOverrides&);
    static std::unique_ptr<Pass> whittedFromScript(const ScriptTable& table, const PassOverrides&);

    std::string type() const override {
        return ambient_ == Ambient::Radiosity ? "distribution" : "whitted";
    }
    // The user's ambient constant stands for no light path: the plan names L D D+ as missing. The
    // radiosity solution's mean stands, crudely, for the indirect light it averages. Whitted's
    // pass previews a medium: its single scattering of the lights (L V S* E), or as a linear fog,
    // which, like the ambient term, counts no light path.
    std::string lightPaths() const override {
        if (ambient_ != Ambient::Constant)
            return distributionLightPaths(causticsInRadiosity_, specularTransfer_);
        return settings_.mediumPreview == DistributionSettings::MediumPreview::LinearFog
                   ? "L S* E | L D S* E"
                   : "L S* E | L D S* E | L V S* E";
    }
    // Whitted's pass with a constant ambient term attenuates every ray by the medium and adds its
    // single scattering (DistributionSettings::mediumSteps); the radiosity solution, which the
    // other forms take, has no medium yet.
    bool rendersMedia() const override { return ambient_ == Ambient::Constant; }
    // Without the solution (a solve abandoned because it would not end within the time limit)
    // the pass traces the indirect light: makeEstimator().
    TransportFlags transportFlags() const override {
        const bool solution = ambient_ == Ambient::Radiosity;
        return {.withoutSolution = solution ? WithoutSolution::kTraces : WithoutSolution::kCannot,
                .showsSolution = solution};
    }
    void adapt(const PipelineShape& shape) override {
        causticsInRadiosity_ = shape.causticsInRadiosity;
        specularTransfer_ = shape.specularTransferInRadiosity;
        causticPathsCounted_ = shape.causticPathsCounted;
    }
    std::set<std::string> needs() const override {
        if (ambient_ == Ambient::Constant)
            return {};
        return {products::kRadiositySolution};
    }
    PassStats parameters() const override;
    // SamplingPass's figures and, with the radiosity mean, the ambient radiance it gave.
    PassStats stats() const override;

  protected:
    RadianceEstimator makeEstimator(PassContext& context) override;
    std::string activity() const override { return "distribution ray tracing"; }

  private:
    DistributionSettings settings_;
    Ambient ambient_;
    bool causticsInRadiosity_ = false;  // the solution holds the caustic photons (L S+ D+)
    bool specularTransfer_ = false;     // the solution holds D S+ D too
    bool causticPathsCounted_ = false;  // another pass counts L S+ D S* E
    std::shared_ptr<const RadiositySolution> radiosity_;
    std::optional<SolutionForTracers> reusedSolution_;  // radiosity_ as the tracer reads it
    std::unique_ptr<DistributionTracer> tracer_;
    std::unique_ptr<PathTracer> pathTracer_;  // instead of tracer_ without the solution
};

// Whitted's ambient radiance from a radiosity solution: the area-weighted mean of the reflected
// radiance (light paths L D+) leaving the surfaces the solution holds (the opaque ones; front
// faces, and back faces of double-sided materials). It is the radiance a surface would receive
// from its surroundings if they were uniform: exact in a closed box of uniform walls, a crude
// average elsewhere. Each triangle's mean is taken by the edge-midpoint rule, exact for
// quadratic polynomials (the three-point rule of finite elements; Strang and Fix 1973, "An
// Analysis of the Finite Element Method").
Color meanReflectedRadiance(const Scene& scene, const RadiositySolution& solution);

}  // namespace penumbra
