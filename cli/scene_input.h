// The SCENE argument shared by the commands that read a scene, and loading it with warnings.
#pragma once

#include "core/scene.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <string>

namespace penumbra::cli {

struct SceneInput {
    std::string path;
    int sceneIndex = -1;  // glTF `scenes` index, -1 = the file's default scene
    bool quiet = false;
};

void addSceneInputOptions(CLI::App& command, SceneInput& input);

// Loads the glTF file (or the scene of a pass script), prints the loader's warnings to stderr
// unless quiet, and builds the scene. Throws SceneError on bad input.
std::unique_ptr<Scene> loadScene(const SceneInput& input);

}  // namespace penumbra::cli
