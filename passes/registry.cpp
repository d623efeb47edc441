// The registry of built-in pipelines: name -> the passes it runs. Adding a preset touches this
// file, the pass's own files and a test.
#include "core/errors.h"
#include "passes/path_pass.h"
#include "passes/pipeline.h"
#include "passes/radiosity_pass.h"

#include <functional>
#include <utility>

namespace penumbra {

namespace {

using PresetFactory = std::function<std::vector<std::unique_ptr<Pass>>(const RenderSettings&)>;

const std::vector<std::pair<std::string, PresetFactory>>& presets() {
    static const std::vector<std::pair<std::string, PresetFactory>> table = {
        {"reference",
         [](const RenderSettings& settings) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<PathPass>(PathTracerSettings{settings.maxDepth}));
             return passes;
         }},
        {"radiosity",
         [](const RenderSettings&) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<RadiosityPass>(RadiositySettings{}));
             return passes;
         }},
    };
    return table;
}

}  // namespace

std::vector<std::string> pipelinePresetNames() {
    std::vector<std::string> names;
    for (const auto& [name, factory] : presets())
        names.push_back(name);
    return names;
}

Pipeline makePipelinePreset(const std::string& name, const RenderSettings& settings) {
    std::string valid;
    for (const auto& [presetName, factory] : presets()) {
        if (presetName == name)
            return Pipeline(name, factory(settings));
        valid += (valid.empty() ? "" : ", ") + presetName;
    }
    throw UsageError("--pipeline: unknown pipeline '" + name + "'; valid: " + valid);
}

}  // namespace penumbra
