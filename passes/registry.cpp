// The registries of passes: built-in pipelines (name -> the passes it runs) and pass types of
// scripts (name -> the pass's constructor from a [[pass]] table). Adding a pass type touches its
// own files, one row here, one line in passes/CMakeLists.txt, its test and its docs
// (CONTRIBUTING.md shows how).
#include "core/errors.h"
#include "passes/caustic_pass.h"
#include "passes/composite.h"
#include "passes/distribution_pass.h"
#include "passes/path_pass.h"
#include "passes/pipeline.h"
#include "passes/planner.h"
#include "passes/radiosity_pass.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <stdexcept>
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
        // Whitted's ray tracing (the seed's Eq. 2): direct light, mirror and refraction
        // recursion, no ambient term unless a script sets one. The crudest preview.
        {"whitted",
         [](const RenderSettings&) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<DistributionPass>(
                 DistributionSettings{}, DistributionPass::Ambient::Constant));
             return passes;
         }},
        // The seed's two-pass method: an indirect-only radiosity solution as the ambient term
        // of distribution ray tracing; the caustic photon map before it (skipped without
        // specular surfaces) for the light through glass and off mirrors, which the solution
        // takes as well.
        {"distribution",
         [](const RenderSettings&) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<CausticPass>(CausticPass::defaultSettings()));
             passes.push_back(std::make_unique<RadiosityPass>(RadiositySettings{}));
             passes.push_back(std::make_unique<DistributionPass>(DistributionSettings{}));
             return passes;
         }},
        // The seed's three-pass method: the caustic photon map, radiosity that takes the
        // photons' flux as well, then path tracing that takes the solution at the second
        // diffuse vertex and corrects it (docs/light-paths.md); the planner skips the caustic
        // pass for a scene without specular surfaces. The correction makes a cheaper solve pay.
        {"hybrid",
         [](const RenderSettings& settings) {
             std::vector<std::unique_ptr<Pass>> passes;
             // The caustic map only where the lights look small from the specular surfaces:
             // large ones the corrected path tracer finds itself, faster (CausticPass).
             auto caustics = std::make_unique<CausticPass>(CausticPass::defaultSettings());
             caustics->yieldToPathTracerForLargeLights();
             passes.push_back(std::move(caustics));
             passes.push_back(
                 std::make_unique<RadiosityPass>(RadiositySettings::forCorrectedReuse()));
             PathTracerSettings path{settings.maxDepth};
             path.reuseRadiosity = true;
             passes.push_back(std::make_unique<PathPass>(path));
             return passes;
         }},
        // The same passes with the solution taken as it is at the second diffuse vertex, not
        // corrected (PathTracerSettings::correctionProbability 0): less noise in the first
        // seconds, a bias that samples do not remove.
        {"hybrid-preview",
         [](const RenderSettings& settings) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<CausticPass>(CausticPass::defaultSettings()));
             passes.push_back(std::make_unique<RadiosityPass>(RadiositySettings{}));
             PathTracerSettings path{settings.maxDepth};
             path.reuseRadiosity = true;
             path.correctionProbability = 0.0f;
             passes.push_back(std::make_unique<PathPass>(path));
             return passes;
         }},
    };
    return table;
}

using PassFactory =
    std::function<std::unique_ptr<Pass>(const ScriptTable& parameters, const PassOverrides&)>;

// One row per pass type: the name a script's `type` gives and the pass's own constructor from
// its [[pass]] table, which reads its keys.
const std::vector<std::pair<std::string, PassFactory>>& passTypes() {
    static const std::vector<std::pair<std::string, PassFactory>> table = {
        {"radiosity", RadiosityPass::fromScript},
        {"path", PathPass::fromScript},
        {"distribution", DistributionPass::fromScript},
        {"whitted", DistributionPass::whittedFromScript},
        {"caustics", CausticPass::fromScript},
        {"composite", CompositePass::fromScript},
    };
    return table;
}

// The pass of one [[pass]] table, its parameters read and the unread ones refused.
std::unique_ptr<Pass> makeScriptPass(const ScriptPass& entry, const PassOverrides& overrides) {
    const ScriptTable& parameters = entry.parameters;
    const std::string valid = joinedNames(passTypeNames());
    if (entry.type.empty())
        throw parameters.error("type", "missing; valid pass types: " + valid);
    for (const auto& [type, factory] : passTypes()) {
        if (type == entry.type) {
            std::unique_ptr<Pass> pass = factory(parameters, overrides);
            parameters.reportUnused();
            return pass;
        }
    }
    throw parameters.error("type", "unknown pass type '" + entry.type + "'; valid: " + valid);
}

}  // namespace

std::vector<std::string> passTypeNames() {
    std::vector<std::string> names;
    for (const auto& [name, factory] : passTypes())
        names.push_back(name);
    return names;
}

Pipeline makeScriptPipeline(const PassScript& script, const PassOverrides& overrides) {
    if (script.pipeline) {
        const std::vector<std::string> names = pipelinePresetNames();
        if (std::find(names.begin(), names.end(), *script.pipeline) == names.end()) {
            throw script.topLevel.error("pipeline", "unknown pipeline '" + *script.pipeline +
                                                        "'; valid: " + joinedNames(names));
        }
        RenderSettings settings;
        settings.maxDepth = overrides.maxDepth.value_or(settings.maxDepth);
        return makePipelinePreset(*script.pipeline, settings);
    }
    std::vector<std::unique_ptr<Pass>> passes;
    for (const ScriptPass& entry : script.passes) {
        // The composite sums what the passes before it made: a pass after it would be lost.
        if (!passes.empty() && passes.back()->type() == "composite") {
            throw entry.parameters.error(
                "", "a pass after the composite pass: the composite must be the last pass");
        }
        passes.push_back(makeScriptPass(entry, overrides));
    }
    Pipeline pipeline(std::filesystem::path(script.file).filename().string(), std::move(passes));
    if (const auto problem = checkPipeline(pipeline))
        throw script.passes.at(problem->pass).parameters.error("", problem->message);
    return pipeline;
}

std::vector<std::string> pipelinePresetNames() {
    std::vector<std::string> names;
    for (const auto& [name, factory] : presets())
        names.push_back(name);
    return names;
}

Pipeline makePipelinePreset(const std::string& name, const RenderSettings& settings) {
    std::string valid;
    for (const auto& [presetName, factory] : presets()) {
        if (presetName == name) {
            Pipeline pipeline(name, factory(settings));
            // A preset is consistent by construction; a problem here is a bug in this file.
            if (const auto problem = checkPipeline(pipeline))
                throw std::logic_error("pipeline preset " + name + ": " + problem->message);
            return pipeline;
        }
        valid += (valid.empty() ? "" : ", ") + presetName;
    }
    throw UsageError("--pipeline: unknown pipeline '" + name + "'; valid: " + valid);
}

}  // namespace penumbra
