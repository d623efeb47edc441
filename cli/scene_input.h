// The SCENE argument shared by the commands that read a scene, and loading it with warnings.
#pragma once

#include "core/scene.h"
#include "passes/pass_script.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>

namespace penumbra::cli {

struct SceneInput {
    std::string path;
    int sceneIndex = -1;  // glTF `scenes` index, -1 = the file's default scene
    bool quiet = false;
};

// Whether a command reads pass scripts as its SCENE (render, plan, info) or glTF only.
enum class PassScripts { Accepted, Refused };

void addSceneInputOptions(CLI::App& command, SceneInput& input, PassScripts scripts);

// When SCENE is a pass script (.toml), reads it (loadPassScript) and points `input` at the
// script's glTF scene, with the script's scene_index unless --scene-index was given. Nothing for
// a glTF file. Call it before loadScene().
std::optional<PassScript> readPassScript(SceneInput& input);

// Loads the glTF file (after readPassScript, the scene of a pass script), prints the loader's
// warnings to stderr unless quiet, and builds the scene. Throws SceneError on bad input.
std::unique_ptr<Scene> loadScene(const SceneInput& input);

}  // namespace penumbra::cli
