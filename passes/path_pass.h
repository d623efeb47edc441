// The path-tracing pass: forms the image with the unbiased path tracer (raytrace/path_tracer.h).
// Alone it is the `reference` pipeline, the ground truth of every other pipeline.
//
// Product: image layers "beauty" (all light paths, L(D|S)*E) and the requested AOVs.
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
    explicit PathPass(PathTracerSettings settings) : settings_(settings) {}

    std::string type() const override { return "path"; }
    std::string lightPaths() const override { return "L(D|S)*E"; }
    void prepare(PassContext& context) override;
    bool run(PassContext& context) override;
    PassStats stats() const override;

  private:
    void publish(PassContext& context) const;

    PathTracerSettings settings_;
    std::unique_ptr<PathTracer> tracer_;
    std::unique_ptr<ImageRenderer> renderer_;
    std::unique_ptr<Progress> progress_;
    std::chrono::steady_clock::time_point start_;
    double lastPassSeconds_ = 0.0;
    double seconds_ = 0.0;
};

}  // namespace penumbra
