// A pipeline: an ordered list of passes run over one PassContext. The built-in presets are
// listed in passes/registry.cpp.
#pragma once

#include "core/pass.h"

#include <memory>
#include <string>
#include <vector>

namespace penumbra {

class Pipeline {
  public:
    Pipeline(std::string name, std::vector<std::unique_ptr<Pass>> passes)
        : name_(std::move(name)), passes_(std::move(passes)) {}

    const std::string& name() const { return name_; }
    const std::vector<std::unique_ptr<Pass>>& passes() const { return passes_; }

    // Prepares and runs every pass in order, each until it reports it has finished.
    void run(PassContext& context);

  private:
    std::string name_;
    std::vector<std::unique_ptr<Pass>> passes_;
};

// The names of the built-in pipelines, in the order `--help` lists them.
std::vector<std::string> pipelinePresetNames();

// A built-in pipeline by name; UsageError listing the valid names for an unknown one.
Pipeline makePipelinePreset(const std::string& name, const RenderSettings& settings);

}  // namespace penumbra
