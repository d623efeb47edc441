// The path-tracing pass: forms the image with the path tracer (raytrace/path_tracer.h). Alone it
// is the `reference` pipeline, the ground truth of every other pipeline; in the `hybrid` pipeline
// it reuses the radiosity solution at the second diffuse vertex and leaves caustic paths to the
// caustic pass; when that pass comes first, its map also lights the second diffuse vertex, through
// the solution when the radiosity pass took the photons (PipelineShape::causticsInRadiosity;
// then the map is not read there: the glossy lobes' share is traced).
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
    // 8 pixels at one sample per pixel, 4 at 64 and 2 at 4096 (sigma_1 N^(-1/6)).
    static constexpr float kDefaultCorrectionSigma = 8.0f;

    // Whether caustic paths (L S+ D S* E) are counted: Auto leaves them out exactly when the
    // pipeline has a caustic pass.
    enum class Caustics { Auto, Include, Exclude };

    // correctionSigma: the width in pixels at one sample per pixel of the reconstruction filter
    // of the solution's correction (raytrace/correction_filter.h); 0 leaves it unfiltered.
    PathPass(PathTracerSettings settings, Caustics caustics = Caustics::Auto,
             float correctionSigma = kDefaultCorrectionSigma)
        : settings_(settings), caustics_(caustics), correctionSigma_(correctionSigma) {}
    // The pass of a script's [[pass]] table of type "path"; --max-depth replaces its max_depth.
    static std::unique_ptr<Pass> fromScript(const ScriptTable& table,
                                            const PassOverrides& overrides);

    std::string type() const override { return "path"; }
    std::string lightPaths() const override { return pathTracerLightPaths(settings_); }
    // A correcting pass (the hybrid) traces the light through specular surfaces at its reuse
    // vertices itself: unbiased either way, and on the modern hall the solution's specular
    // transfer (1.6 s of set-up) bought nothing at 64 s and cost a third of the path tracer's
    // time at 16 s. The preview takes it from a solution that holds it with the caustics.
    // Without the solution (a solve abandoned at the time limit) it traces every path on, as the
    // path tracer does: for a correcting pass the same estimate, for the preview a slower but
    // right one.
    // In caustics = "auto" it traces the caustic paths when no other pass counts them.
    TransportFlags transportFlags() const override {
        const bool tracesCaustics = caustics_ == Caustics::Auto;
        if (!settings_.reuseRadiosity)
            return {.tracesUncountedCaustics = tracesCaustics};
        const bool corrects = settings_.correctionProbability > 0.0f;
        return {
            .specularAtReuse = corrects ? SpecularAtReuse::kTraced : SpecularAtReuse::kFromSolution,
            .withoutSolution = corrects ? WithoutSolution::kSame : WithoutSolution::kTraces,
            .tracesUncountedCaustics = tracesCaustics};
    }
    std::set<std::string> needs() const override;
    void adapt(const PipelineShape& shape) override;
    // Without reuse: every contribution of the path tracer comes from one light.
    bool splitsLightGroups() const override { return !settings_.reuseRadiosity; }
    // Media are the path tracer's own (raytrace/path_tracer.h), the corrected reuse's too; the
    // uncorrected reuse and the caustic pass's share have no medium.
    bool rendersMedia() const override { return tracesMedia(settings_); }
    PassStats parameters() const override;

  protected:
    RadianceEstimator makeEstimator(PassContext& context) override;
    std::string activity() const override { return "path tracing"; }
    float correctionSigma() const override;
    std::vector<std::string> lightGroups() const override;

  private:
    PathTracerSettings settings_;
    Caustics caustics_;
    float correctionSigma_;
    std::shared_ptr<const RadiositySolution> radiosity_;
    bool reuses_ = false;  // reuses the solution: it asks to, and there is one (makeEstimator)
    std::shared_ptr<const CausticMap> causticMap_;
    std::optional<SolutionForTracers> reusedSolution_;  // radiosity_ as the tracer reads it
    std::optional<CausticsForTracers> reusedCaustics_;
    std::optional<LightGroupSplit> lightGroupSplit_;  // when the render files light by group
    std::unique_ptr<PathTracer> tracer_;
};

}  // namespace penumbra
