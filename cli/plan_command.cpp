// `penumbra plan SCENE_OR_SCRIPT [--pipeline NAME]`: what a render would do, without rendering:
// the passes with their parameters, the light paths each counts, the decisions taken for the
// scene (skipped passes with their reasons) and the paths no pass counts.
#include "cli/commands.h"
#include "cli/scene_input.h"
#include "core/errors.h"
#include "passes/pipeline.h"
#include "passes/planner.h"

#include <iostream>

namespace penumbra::cli {

namespace {

struct PlanOptions {
    CLI::App* command = nullptr;
    SceneInput scene;
    std::string pipeline = "reference";
};

void printPlan(PlanOptions& options) {
    std::optional<PassScript> script = readPassScript(options.scene);
    if (script)
        takePipelineOption(*script, options.command->count("--pipeline") > 0, options.pipeline);
    RenderSettings settings;
    Pipeline pipeline =
        script ? makeScriptPipeline(*script) : makePipelinePreset(options.pipeline, settings);
    const std::unique_ptr<Scene> scene = loadScene(options.scene);
    const SceneContents contents = analyseScene(*scene);
    const PipelinePlan plan = planForScene(pipeline, contents);

    std::cout << "pipeline:  " << pipeline.name() << (script ? " (pass script)" : " (preset)")
              << "\nscene:     " << options.scene.path << ": "
              << (contents.diffuse ? "diffuse" : "no diffuse") << " surfaces, "
              << (contents.specular ? "specular" : "no specular") << " surfaces, "
              << contents.areaLights << " emissive triangles, " << contents.punctualLights
              << " punctual lights" << (contents.environment ? ", an environment" : "")
              << (contents.medium ? ", a participating medium" : "")
              << "\npaths:     the scene can hold " << plan.universe << "\npasses:\n";
    for (size_t i = 0; i < pipeline.passes().size(); ++i) {
        const Pass& pass = *pipeline.passes()[i];
        std::cout << "  " << i + 1 << ". " << pass.type();
        if (pipeline.skipped(i))
            std::cout << " (skipped)";
        std::cout << "\n     paths: "
                  << (pass.lightPaths().empty() ? "none in the image" : pass.lightPaths());
        std::string separator = "\n     parameters: ";
        for (const auto& [key, value] : pass.parameters()) {
            std::cout << separator << key << " = " << value;
            separator = ", ";
        }
        std::cout << "\n";
    }
    std::cout << "decisions:\n";
    for (const std::string& decision : plan.decisions)
        std::cout << "  " << decision << "\n";
    std::cout << "warnings:" << (plan.warnings.empty() ? " none" : "") << "\n";
    for (const std::string& warning : plan.warnings)
        std::cout << "  " << warning << "\n";
}

}  // namespace

Command addPlanCommand(CLI::App& app) {
    auto* command = app.add_subcommand(
        "plan",
        "Print the plan of a render without rendering: passes, parameters, the light "
        "paths each counts, passes skipped for the scene and paths no pass counts");
    auto options = std::make_shared<PlanOptions>();
    options->command = command;
    addSceneInputOptions(*command, options->scene, PassScripts::Accepted);
    addPipelineOption(*command, options->pipeline);
    return [options] { printPlan(*options); };
}

}  // namespace penumbra::cli
