// A pipeline: an ordered list of passes run over one PassContext. The built-in presets are
// listed in passes/registry.cpp.
#pragma once

#include "passes/pass.h"
#include "passes/pass_parameters.h"
#include "passes/pass_script.h"

#include <functional>
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

    // Leaves pass `index` out of run() (the planner's decision for a scene that does not need
    // it); its products are then absent, which the passes that reuse them read as zero.
    void skip(size_t index) { skipped_.at(index) = true; }
    bool skipped(size_t index) const { return skipped_.at(index); }

    // Prepares and runs every pass that is not skipped, in order, each until it reports it has
    // finished; then composites (passes/composite.h) unless a composite pass already did.
    //
    // context.settings.timeLimit (seconds, 0 = none) holds the pipeline as a whole, from the
    // first prepare: when a pass's next step would end past it, assuming it takes as long as the
    // last one, the pass is asked to stop early (Pass::stopEarly), so images stop at whole steps.
    // A pass's prepare (such as the radiosity solve) cannot be cut short, and every pass takes at
    // least one step.
    //
    // `abandon`, when given, is asked before every pass and after every step; if it answers
    // true, the run ends at once and returns false (the layers are then incomplete).
    bool run(PassContext& context, const std::function<bool()>& abandon = {});

  private:
    std::string name_;
    std::vector<std::unique_ptr<Pass>> passes_;
    std::vector<bool> skipped_ = std::vector<bool>(passes_.size(), false);
};

// The names of the built-in pipelines, in the order `--help` lists them.
std::vector<std::string> pipelinePresetNames();

// A built-in pipeline by name; UsageError listing the valid names for an unknown one.
Pipeline makePipelinePreset(const std::string& name, const RenderSettings& settings);

// The pass types a script's [[pass]] may name, in the order messages list them.
std::vector<std::string> passTypeNames();

// The pipeline of a pass script, named after the script's file name: each [[pass]] is built by
// its type's constructor (the pass's fromScript, listed in passes/registry.cpp), which reads the
// table's parameters; keys nobody read are then refused. Throws ScriptError at the place of a
// missing or unknown type, a bad or unknown parameter, or an impossible combination of passes.
// A script that names a built-in `pipeline` instead gets that preset (ScriptError at the name if
// it is unknown), with the overrides' max_depth.
Pipeline makeScriptPipeline(const PassScript& script, const PassOverrides& overrides = {});

}  // namespace penumbra
