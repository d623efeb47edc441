#include "cli/scene_input.h"

#include "cli/commands.h"
#include "core/environment_source.h"
#include "core/errors.h"
#include "core/gltf_loader.h"
#include "core/sky.h"

#include <filesystem>
#include <iostream>
#include <sstream>

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
    command
        .add_option("--environment", input.environment.file,
                    "Environment light: an equirectangular image of radiance in cd/m² (EXR or "
                    ".hdr), replacing the scene's own")
        ->check(CLI::ExistingFile);
    command
        .add_option("--environment-scale", input.environment.scale,
                    "Multiplies the environment's radiance (default 1)")
        ->check(CLI::PositiveNumber);
    command.add_option("--environment-rotation", input.environment.rotationDegrees,
                       "Turns the environment about the up axis (+Y), degrees, counter-clockwise "
                       "seen from above (default 0)");
    command.add_option("--sky", input.environment.sky,
                       std::string("A sky as the environment light: ") + skyModelNames());
    command
        .add_option("--sky-illuminance", input.environment.skyIlluminance,
                    "The sky's unobstructed horizontal illuminance, lux, the ground excluded "
                    "(default 10000)")
        ->check(CLI::PositiveNumber);
    command
        .add_option("--ground-reflectance", input.environment.groundReflectance,
                    "Below the horizon a ground of luminance R E_h / pi (default 0.2)")
        ->check(CLI::Range(0.0, 1.0));
}

std::optional<PassScript> readPassScript(SceneInput& input) {
    if (std::filesystem::path(input.path).extension() != ".toml")
        return std::nullopt;
    PassScript script = loadPassScript(input.path);
    input.path = script.scene;
    if (input.sceneIndex < 0 && script.sceneIndex)
        input.sceneIndex = *script.sceneIndex;
    // The command line's environment options win over the script's.
    const auto unlessGiven = [](auto& option, const auto& fromScript) {
        if (!option)
            option = fromScript;
    };
    EnvironmentInput& environment = input.environment;
    unlessGiven(environment.file, script.environment);
    unlessGiven(environment.scale, script.environmentScale);
    unlessGiven(environment.rotationDegrees, script.environmentRotation);
    unlessGiven(environment.sky, script.sky);
    unlessGiven(environment.skyIlluminance, script.skyIlluminance);
    unlessGiven(environment.groundReflectance, script.groundReflectance);
    return script;
}

namespace {

// The environment the user asked for: a new one from a file, or the scene's own scaled and
// turned.
// The sky of `input.sky`, with its options' defaults.
EnvironmentDesc makeSky(const EnvironmentInput& input, float scale, const Mat3& turn) {
    SkySettings settings;
    settings.model = *input.sky;
    settings.horizontalIlluminance = input.skyIlluminance.value_or(settings.horizontalIlluminance);
    settings.groundReflectance = input.groundReflectance.value_or(settings.groundReflectance);
    EnvironmentDesc sky;
    try {
        sky.radiance = skyMap(settings);
    } catch (const std::invalid_argument& e) {
        const std::string message = e.what();
        throw UsageError("--sky: " + message);
    }
    std::ostringstream name;
    name << "sky " << settings.model << ", " << settings.horizontalIlluminance
         << " lux, ground reflectance " << settings.groundReflectance;
    sky.file = name.str();
    sky.scale = scale;
    sky.worldToLocal = turn;
    return sky;
}

void applyEnvironment(const EnvironmentInput& input, SceneDescription& description) {
    const float scale = input.scale.value_or(1.0f);
    const Mat3 turn = environmentRotation(input.rotationDegrees.value_or(0.0f));
    if (input.file && input.sky)
        throw UsageError("--environment and --sky: give one environment light, not both");
    if (!input.sky && (input.skyIlluminance || input.groundReflectance))
        throw UsageError("--sky-illuminance and --ground-reflectance need --sky");
    if (input.sky) {
        description.environment = makeSky(input, scale, turn);
        return;
    }
    if (input.file) {
        description.environment = readEnvironment(*input.file, scale, turn);
        return;
    }
    if (!input.scale && !input.rotationDegrees)
        return;
    if (!description.environment) {
        throw UsageError(description.file +
                         ": --environment-scale and --environment-rotation need an environment: "
                         "the scene has none; give one with --environment FILE");
    }
    // Turning the map by R about +Y: the map's frame sees world direction d where it saw R^T d.
    description.environment->scale *= scale;
    description.environment->worldToLocal = description.environment->worldToLocal * turn;
}

}  // namespace

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
    applyEnvironment(input.environment, description);
    if (!input.quiet) {
        for (const std::string& warning : description.report.warnings) {
            std::cerr << "penumbra: warning: " << warning << "\n";
        }
    }
    auto scene = std::make_unique<Scene>(std::move(description));
    if (!input.quiet && scene->lights().empty()) {
        std::cerr << "penumbra: warning: " << input.path
                  << ": the scene has no lights and no emissive surfaces; the image will be "
                     "black (light it with --environment FILE or --sky MODEL)\n";
    }
    return scene;
}

}  // namespace penumbra::cli
