// `penumbra render SCENE -o OUT`: renders a scene with a pipeline and writes the image.
#include "cli/commands.h"
#include "cli/scene_input.h"
#include "core/errors.h"
#include "core/film.h"
#include "core/image_io.h"
#include "core/tonemap.h"
#include "core/version.h"
#include "passes/pipeline.h"
#include "raytrace/image_renderer.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <iostream>
#include <sstream>

namespace penumbra::cli {

namespace {

struct RenderOptions {
    SceneInput scene;
    std::vector<std::string> outputs;
    std::string pipeline = "reference";
    RenderSettings settings;
    float exposure = 0.0f;
    std::string tonemap = "clamp";
    std::string aovList;
};

std::vector<std::string> splitList(const std::string& list) {
    std::vector<std::string> items;
    std::stringstream stream(list);
    std::string item;
    while (std::getline(stream, item, ',')) {
        if (!item.empty())
            items.push_back(item);
    }
    return items;
}

void render(RenderOptions& options) {
    RenderSettings& settings = options.settings;
    settings.quiet = options.scene.quiet;
    settings.aovs = splitList(options.aovList);
    // Refuse bad outputs and option values before spending time on loading and rendering.
    for (const std::string& output : options.outputs)
        checkOutputPath(output);
    const ToneMapping toneMapping{options.exposure, parseToneMapOperator(options.tonemap)};
    parseFilter(settings.filter);
    aovSpecs(settings.aovs);

    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<Scene> scene = loadScene(options.scene);
    const CameraDesc cameraDesc =
        chooseCamera(scene->description().cameras, settings.camera, scene->bounds());
    const IVec2 size = chooseImageSize(cameraDesc, settings.width, settings.height);
    settings.width = size.x;
    settings.height = size.y;
    const Camera camera(cameraDesc, size.x, size.y);
    Pipeline pipeline = makePipelinePreset(options.pipeline, settings);

    const int threads = settings.threads > 0 ? settings.threads : tbb::info::default_concurrency();
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
    PassContext context(*scene, camera, settings);
    pipeline.run(context);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    ImageMetadata metadata;
    metadata.set("penumbra:version", std::string(kVersion));
    metadata.set("penumbra:pipeline", pipeline.name());
    metadata.set("penumbra:seed", static_cast<int>(settings.seed));
    metadata.set("penumbra:seconds", static_cast<float>(seconds));
    metadata.set("penumbra:scene", options.scene.path);
    metadata.set("penumbra:camera", cameraDesc.name);
    metadata.set("penumbra:filter", settings.filter);
    metadata.set("penumbra:max_depth", settings.maxDepth);
    for (const auto& pass : pipeline.passes()) {
        for (const auto& [key, value] : pass->stats()) {
            metadata.set("penumbra:" + pass->type() + "." + key, value);
            if (key == "spp")
                metadata.set("penumbra:spp", std::stoi(value));
        }
    }
    std::vector<NamedLayer> aovs;
    for (const std::string& name : settings.aovs)
        aovs.push_back({name, context.layers.at(name)});
    for (const std::string& output : options.outputs) {
        writeImage(output, context.layers.at("beauty"), aovs, metadata, toneMapping);
    }

    if (!settings.quiet) {
        for (const std::string& output : options.outputs)
            std::cerr << "penumbra: wrote " << output << "\n";
        std::cerr << "penumbra: " << size.x << "x" << size.y << ", pipeline " << pipeline.name()
                  << ", " << seconds << " s\n";
        for (const auto& pass : pipeline.passes()) {
            for (const auto& [key, value] : pass->stats()) {
                std::cerr << "  " << pass->type() << " " << key << ": " << value << "\n";
            }
        }
    }
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
    auto* command = app.add_subcommand("render",
                                       "Render a scene to an image (.exr linear, "
                                       ".png tone-mapped sRGB)");
    auto options = std::make_shared<RenderOptions>();
    RenderSettings& s = options->settings;
    addSceneInputOptions(*command, options->scene);
    command
        ->add_option("-o,--output", options->outputs,
                     "Output image; the extension picks the format (.exr linear float, .png "
                     "tone-mapped sRGB, ...); repeat to write several")
        ->required()
        ->take_all();
    std::string pipelines;
    for (const std::string& name : pipelinePresetNames())
        pipelines += " " + name;
    command->add_option("--pipeline", options->pipeline, "Pipeline preset:" + pipelines)
        ->capture_default_str();
    command->add_option("--spp", s.spp, "Samples per pixel (the target with --time-limit)")
        ->check(atLeast(1))
        ->capture_default_str();
    command
        ->add_option("--width", s.width,
                     "Image width in pixels (default: from --height and "
                     "the camera's aspect ratio, else 640)")
        ->check(atLeast(1));
    command->add_option("--height", s.height, "Image height in pixels")->check(atLeast(1));
    command->add_option("--seed", s.seed, "Random seed; same seed, same image")
        ->capture_default_str();
    command->add_option("--threads", s.threads, "Worker threads (default: all cores)")
        ->check(atLeast(0));
    command
        ->add_option("--time-limit", s.timeLimit,
                     "Stop after this many seconds, at a whole pass of samples")
        ->check(CLI::NonNegativeNumber);
    command->add_option("--camera", s.camera, "Name of the glTF camera (default: the first)");
    command
        ->add_option("--max-depth", s.maxDepth,
                     "Maximum number of bounces (default -1: unlimited, ended by Russian "
                     "roulette)")
        ->check(CLI::Range(-1, 1 << 20))
        ->capture_default_str();
    command->add_option("--filter", s.filter, "Pixel filter: box, gaussian, blackman-harris")
        ->capture_default_str();
    command->add_option("--exposure", options->exposure, "Exposure in EV for tone-mapped output")
        ->capture_default_str();
    command
        ->add_option("--tonemap", options->tonemap,
                     "Tone-mapping operator for 8-bit output: clamp, reinhard, aces")
        ->capture_default_str();
    command->add_option("--aov", options->aovList,
                        "Extra EXR layers, comma separated: albedo,normal,depth");
    return [options] { render(*options); };
}

}  // namespace penumbra::cli
