// The SCENE argument shared by the commands that read a scene, and loading it with warnings.
#pragma once

#include "core/scene.h"
#include "passes/pass_script.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace penumbra::cli {

// The environment light the user gives or adjusts (--environment, --environment-scale,
// --environment-rotation, or a pass script's keys of the same names), or a sky (--sky,
// --sky-illuminance, --ground-reflectance: core/sky.h) in its place, and the sun: absent values
// leave the scene's own environment as it is.
struct EnvironmentInput {
    std::optional<std::string> file;
    std::optional<std::string> sky;
    std::optional<float> skyIlluminance;     // lux, > 0
    std::optional<float> groundReflectance;  // in [0, 1]
    std::optional<float> scale;              // > 0, multiplies the environment's radiance
    std::optional<float> illuminance;        // lux, > 0: scales it to this horizontal illuminance
    std::optional<float> rotationDegrees;    // about +Y, counter-clockwise seen from above
    // The sun (--site, --time, --north, --sun-direct-normal): its position places the sun's
    // disc (core/sun_disc.h) and the glow of the skies that depend on it.
    std::optional<std::string> site;       // "LAT,LON", degrees
    std::optional<std::string> time;       // ISO 8601 with the UTC offset
    std::optional<float> northDegrees;     // true north from -Z, counter-clockwise seen from above
    std::optional<float> sunDirectNormal;  // E_n, lux, >= 0
    // Portals (--portal): parallelograms "X0,Y0,Z0,X1,Y1,Z1,X2,Y2,Z2" in the file's world frame,
    // a corner and its two neighbours, or "auto": the scene's openings, found
    // (core/portal_detection.h).
    std::vector<std::string> portals;
};

struct SceneInput {
    std::string path;
    int sceneIndex = -1;  // glTF `scenes` index, -1 = the file's default scene
    bool quiet = false;
    EnvironmentInput environment;
    std::vector<ScriptLuminaire> luminaires;  // a pass script's [[luminaire]] tables
    std::optional<ScriptMedium> medium;       // a pass script's [[medium]] table
};

// Whether a command reads pass scripts as its SCENE (render, plan, info) or glTF only.
enum class PassScripts { Accepted, Refused };

void addSceneInputOptions(CLI::App& command, SceneInput& input, PassScripts scripts);

// When SCENE is a pass script (.toml), reads it (loadPassScript) and points `input` at the
// script's glTF scene, with the script's scene_index and environment unless the command line gave
// them. Nothing for a glTF file. Call it before loadScene().
std::optional<PassScript> readPassScript(SceneInput& input);

// The command line's --pipeline (given when `given`) with a pass script: it replaces the script's
// `pipeline`; refused (UsageError) when the script lists [[pass]] tables, which are its pipeline.
void takePipelineOption(PassScript& script, bool given, const std::string& pipeline);

// Loads the glTF file (after readPassScript, the scene of a pass script), sets or adjusts its
// environment light as `input.environment` says, adds the script's luminaires, prints the loader's
// warnings to stderr unless quiet, and builds the scene. Throws SceneError on a bad scene,
// InputError on a bad environment image, UsageError for a scale or rotation with no environment to
// apply it to.
std::unique_ptr<Scene> loadScene(const SceneInput& input);

}  // namespace penumbra::cli
