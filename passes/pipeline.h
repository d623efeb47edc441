// A pipeline: an ordered list of passes run over one PassContext. The built-in presets are
// listed in passes/registry.cpp.
#pragma once

#include "core/pass.h"
#include "passes/pass_script.h"

#include <memory>
#include <optional>
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

// Command-line values that replace a pass parameter in every pass of a script that has it
// (docs/pass-scripts.md, "Precedence"); absent = the script's value.
struct PassOverrides {
    std::optional<int> maxDepth;  // --max-depth: `max_depth` of the path passes
};

// The pass types a script's [[pass]] may name, in the order messages list them.
std::vector<std::string> passTypeNames();

// The pipeline of a pass script, named after the script's file name: each [[pass]] is built by
// its type's factory in passes/registry.cpp, which reads the table's parameters; keys nobody
// read are then refused. Throws ScriptError at the place of a missing or unknown type, a bad or
// unknown parameter, or an impossible combination of passes.
Pipeline makeScriptPipeline(const PassScript& script, const PassOverrides& overrides = {});

}  // namespace penumbra
