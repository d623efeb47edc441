#include "cli/scene_input.h"

#include "cli/commands.h"
#include "core/errors.h"
#include "core/gltf_loader.h"

#include <filesystem>
#include <iostream>

namespace penumbra::cli {

void addSceneInputOptions(CLI::App& command, SceneInput& input, PassScripts scripts) {
    command
        .add_option("scene", input.path,
                    scripts == PassScripts::Accepted
                        ? "Scene file: .gltf or .glb, or a .toml pass script"
                        : "Scene file: .gltf or .glb")
        ->required();
    command
        .add_option("--scene-index", input.sceneIndex,
                    "Which of the file's glTF scenes to use (default: the file's `scene`)")
        ->check(atLeast(0));
    command.add_flag("-q,--quiet", input.quiet, "Print nothing but errors");
}

std::optional<PassScript> readPassScript(SceneInput& input) {
    if (std::filesystem::path(input.path).extension() != ".toml")
        return std::nullopt;
    PassScript script = loadPassScript(input.path);
    input.path = script.scene;
    if (input.sceneIndex < 0 && script.sceneIndex)
        input.sceneIndex = *script.sceneIndex;
    return script;
}

std::unique_ptr<Scene> loadScene(const SceneInput& input) {
    const std::string extension = std::filesystem::path(input.path).extension().string();
    // render, plan and info read a pass script first (readPassScript); the other commands take
    // glTF only.
    if (extension == ".toml") {
        throw UsageError(
            input.path +
            ": pass scripts are for `render`, `plan` and `info`; give a .gltf or .glb");
    }
    if (extension != ".gltf" && extension != ".glb") {
        throw UsageError(input.path + ": unknown scene format '" + extension +
                         "'; expected .gltf or .glb (render, plan and info: or a .toml pass "
                         "script)");
    }
    SceneDescription description = loadGltf(input.path, input.sceneIndex);
    if (!input.quiet) {
        for (const std::string& warning : description.report.warnings) {
            std::cerr << "penumbra: warning: " << warning << "\n";
        }
    }
    auto scene = std::make_unique<Scene>(std::move(description));
    if (!input.quiet && scene->lights().empty()) {
        std::cerr << "penumbra: warning: " << input.path
                  << ": the scene has no lights and no emissive surfaces; the image will be "
                     "black\n";
    }
    return scene;
}

}  // namespace penumbra::cli
