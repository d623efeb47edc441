// The path-tracing pass: forms the image with the path tracer (raytrace/path_tracer.h). Alone it
// is the `reference` pipeline, the ground truth of every other pipeline; in the `hybrid` pipeline
// it reuses the radiosity solution at the second diffuse vertex and leaves caustic paths to the
// caustic pass; when that pass comes first, its map also lights the second diffuse vertex, through
// the solution when the radiosity pass took the photons (PipelineShape::causticsInRadiosity;
// then the map adds only the glossy lobes' share there).
//
// Contribution: image layer "path" (the light paths of pathTracerLightPaths()), and the
// requested AOVs.
#pragma once

#include "passes/pass_parameters.h"
#include "passes/reused_products.h"
#include "passes/sampling_pass.h"
#include "raytrace/path_tracer.h"

#include <optional>

namespace penumbra {

class PathPass : public SamplingPass {
  public:
    // Whether caustic paths (L S+ D S* E) are counted: Auto leaves them out exactly when the
    // pipeline has a caustic pass.
    enum class Caustics { Auto, Include, Exclude };

    PathPass(PathTracerSettings settings, Caustics caustics = Caustics::Auto)
        : settings_(settings), caustics_(caustics) {}
    // The pass of a script's [[pass]] table of type "path"; --max-depth replaces its max_depth.
    static std::unique_ptr<Pass> fromScript(const ScriptTable& table,
                                            const PassOverrides& overrides);

    std::string type() const override { return "path"; }
    std::string lightPaths() const override { return pathTracerLightPaths(settings_); }
    std::set<std::string> needs() const override;
    void adapt(const PipelineShape& shape) override;
    PassStats parameters() const override;

  protected:
    RadianceEstimator makeEstimator(PassContext& context) override;
    std::string activity() const override { return "path tracing"; }

  private:
    PathTracerSettings settings_;
    Caustics caustics_;
    std::shared_ptr<const RadiositySolution> radiosity_;
    std::shared_ptr<const CausticMap> causticMap_;
    std::optional<SolutionForTracers> reusedSolution_;  // radiosity_ as the tracer reads it
    std::optional<CausticsForTracers> reusedCaustics_;
    std::unique_ptr<PathTracer> tracer_;
};

}  // namespace penumbra
