// The path-tracing pass: forms the image with the path tracer (raytrace/path_tracer.h). Alone it
// is the `reference` pipeline, the ground truth of every other pipeline; in the `hybrid` pipeline
// it reuses the radiosity solution at the second diffuse vertex and leaves caustic paths to the
// caustic pass.
//
// Contribution: image layer "path" (the light paths of pathTracerLightPaths()), and the
// requested AOVs.
#pragma once

#include "core/pass.h"
#include "core/progress.h"
#include "raytrace/image_renderer.h"
#include "raytrace/path_tracer.h"

#include <chrono>
#include <memory>

namespace penumbra {

class PathPass : public Pass {
  public:
    // Whether caustic paths (L S+ D S* E) are counted: Auto leaves them out exactly when the
    // pipeline has a caustic pass.
    enum class Caustics { Auto, Include, Exclude };

    PathPass(PathTracerSettings settings, Caustics caustics = Caustics::Auto)
        : settings_(settings), caustics_(caustics) {}

    std::string type() const override { return "path"; }
    std::string lightPaths() const override { return pathTracerLightPaths(settings_); }
    std::set<std::string> needs() const override;
    void adapt(const PipelineShape& shape) override;
    PassStats parameters() const override;
    void prepare(PassContext& context) override;
    bool run(PassContext& context) override;
    PassStats stats() const override;

  private:
    void publish(PassContext& context) const;

    PathTracerSettings settings_;
    Caustics caustics_;
    std::shared_ptr<const RadiositySolution> radiosity_;
    std::unique_ptr<PathTracer> tracer_;
    std::unique_ptr<ImageRenderer> renderer_;
    std::unique_ptr<Progress> progress_;
    std::chrono::steady_clock::time_point start_;
    double lastPassSeconds_ = 0.0;
    double seconds_ = 0.0;
};

}  // namespace penumbra
