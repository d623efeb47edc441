#include "cli/scene_input.h"

#include "cli/commands.h"
#include "core/errors.h"
#include "core/gltf_loader.h"

#include <filesystem>
#include <iostream>

namespace penumbra::cli {

void addSceneInputOptions(CLI::App& command, SceneInput& input) {
    command.add_option("scene", input.path, "Scene file: .gltf or .glb")->required();
    command
        .add_option("--scene-index", input.sceneIndex,
                    "Which of the file's glTF scenes to use (default: the file's `scene`)")
        ->check(atLeast(0));
    command.add_flag("-q,--quiet", input.quiet, "Print nothing but errors");
}

std::unique_ptr<Scene> loadScene(const SceneInput& input) {
    const std::string extension = std::filesystem::path(input.path).extension().string();
    if (extension == ".toml") {
        throw UsageError(input.path +
                         ": pass scripts (.toml) are not supported yet; give a .gltf or .glb");
    }
    if (extension != ".gltf" && extension != ".glb") {
        throw UsageError(input.path + ": unknown scene format '" + extension +
                         "'; expected .gltf or .glb");
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
