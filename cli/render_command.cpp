// `penumbra render SCENE -o OUT`: renders a scene with a pipeline and writes the image.
#include "cli/commands.h"
#include "cli/pipeline_run.h"
#include "cli/scene_input.h"
#include "core/errors.h"
#include "core/film.h"
#include "core/image_io.h"
#include "core/light_groups.h"
#include "core/stats.h"
#include "core/tonemap.h"
#include "passes/pipeline.h"
#include "passes/planner.h"
#include "raytrace/image_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <optional>
#include <sstream>

namespace penumbra::cli {

namespace {

struct RenderOptions {
    CLI::App* command = nullptr;  // to tell options given from defaults
    SceneInput scene;
    std::vector<std::string> outputs;
    std::string pipeline = "reference";
    RenderSettings settings;
    std::string exposure = "0";  // EV, or "auto"
    std::string tonemap = "clamp";
    std::string aovList;
    bool lightGroups = false;
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

// Takes the script's values for what the command line does not give: options given on the
// command line win (docs/pass-scripts.md, "Precedence").
void applyScript(PassScript& script, RenderOptions& options) {
    const auto given = [&options](const std::string& name) {
        return options.command->count(name) > 0;
    };
    takePipelineOption(script, given("--pipeline"), options.pipeline);
    RenderSettings& s = options.settings;
    if (!given("--camera") && script.camera)
        s.camera = *script.camera;
    // The image size is one setting: --width or --height replaces both of the script's values.
    if (!given("--width") && !given("--height")) {
        s.width = script.width.value_or(0);
        s.height = script.height.value_or(0);
    }
    if (!given("--spp") && script.spp)
        s.spp = *script.spp;
    if (!given("--seed") && script.seed)
        s.seed = *script.seed;
    if (options.outputs.empty())
        options.outputs = script.outputs;
}

// The light groups of `scene`; UsageError when it has no light to split.
std::vector<LightGroup> requireLightGroups(const Scene& scene) {
    std::vector<LightGroup> groups = lightGroups(scene.description());
    if (groups.empty()) {
        throw UsageError(scene.description().file +
                         ": --light-groups: the scene has no light source to split into groups");
    }
    return groups;
}

// Whether every pass of `pipeline` that runs files its image by light group within one render.
bool splitsLightGroupsAtOnce(const Pipeline& pipeline) {
    for (size_t i = 0; i < pipeline.passes().size(); ++i) {
        if (!pipeline.skipped(i) && !pipeline.passes()[i]->splitsLightGroups())
            return false;
    }
    return true;
}

// Renders `scene` once with `pipeline`, whose passes all split their images by light group
// (splitsLightGroupsAtOnce), each group's layer "light.GROUP".
PipelineRun renderLightGroupsAtOnce(Pipeline& pipeline, const Scene& scene,
                                    const SceneContents& contents, const Camera& camera,
                                    const RenderSettings& settings) {
    const std::vector<LightGroup> groups = requireLightGroups(scene);
    if (!settings.quiet) {
        std::string names;
        for (const LightGroup& group : groups)
            names += (names.empty() ? "" : ", ") + group.name;
        std::cerr << "penumbra: light groups, in one render: " << names << "\n";
    }
    RenderSettings splitSettings = settings;
    splitSettings.lightGroups = true;
    PipelineRun run = runPipeline(pipeline, scene, contents, camera, splitSettings);
    for (const LightGroup& group : groups)
        run.lightGroups.push_back("light." + group.name);
    return run;
}

// Renders `scene` once per light group (core/light_groups.h), each group alone with a pipeline
// of its own from `makePipeline`, at `settings` with an equal share of the time limit: the run's
// layers are the sums of the groups' (beauty, light-path components, passes' contributions and
// samples per pixel; the other AOVs, which do not depend on the light, are the first group's),
// and a layer "light.GROUP" per group, the group's beauty.
// `report` is called after each group's run with its pipeline, settings and "GROUP: ".
PipelineRun renderLightGroups(
    const Scene& scene, const Camera& camera, const RenderSettings& settings,
    const std::function<Pipeline()>& makePipeline,
    const std::function<void(const Pipeline&, const RenderSettings&, const std::string&)>& report) {
    const std::vector<LightGroup> groups = requireLightGroups(scene);
    RenderSettings groupSettings = settings;
    groupSettings.timeLimit = settings.timeLimit / double(groups.size());
    PipelineRun sum;
    for (size_t g = 0; g < groups.size(); ++g) {
        const LightGroup& group = groups[g];
        if (!settings.quiet) {
            std::cerr << "penumbra: light group " << g + 1 << " of " << groups.size() << ": "
                      << group.name << "\n";
        }
        const Scene lit(litOnlyBy(scene.description(), group));
        const SceneContents contents = analyseScene(lit);
        Pipeline pipeline = makePipeline();
        planForScene(pipeline, contents);
        PipelineRun run = runPipeline(pipeline, lit, contents, camera, groupSettings);
        report(pipeline, groupSettings, group.name + ": ");
        const std::string layer = "light." + group.name;
        if (g == 0) {
            sum = run;
        } else {
            for (auto& [name, image] : sum.layers) {
                const bool additive = name == "beauty" || name == "spp" || name == "luminance" ||
                                      isComponentAov(name) ||
                                      std::find(sum.contributions.begin(), sum.contributions.end(),
                                                name) != sum.contributions.end();
                if (additive)
                    addPixels(image, run.layers.at(name));
            }
            sum.seconds += run.seconds;
        }
        sum.layers[layer] = run.layers.at("beauty");
        sum.lightGroups.push_back(layer);
    }
    return sum;
}

// --exposure: EV, or nothing for "auto".
std::optional<float> parseExposure(const std::string& text) {
    if (text == "auto")
        return std::nullopt;
    char* end = nullptr;
    const float ev = std::strtof(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(ev))
        throw UsageError("--exposure " + text + ": expected a number of EV or auto");
    return ev;
}

// The scene's camera; a bad camera name from a script is reported at its place in the script.
CameraDesc scriptCamera(const Scene& scene, const RenderOptions& options,
                        const std::optional<PassScript>& script) {
    try {
        return chooseCamera(scene.description().cameras, options.settings.camera, scene.bounds());
    } catch (const UsageError& e) {
        if (!script || options.command->count("--camera") > 0)
            throw;
        const std::string message = e.what();
        throw script->topLevel.error("camera", message.substr(message.find(": ") + 2));
    }
}

void render(RenderOptions& options) {
    RenderSettings& settings = options.settings;
    settings.quiet = options.scene.quiet;
    std::optional<PassScript> script = readPassScript(options.scene);
    if (script)
        applyScript(*script, options);
    if (options.outputs.empty())
        throw UsageError("--output is required (a pass script may give `output` instead)");
    settings.aovs = expandAovNames(splitList(options.aovList));
    // Adaptive sampling records what it did: the samples each pixel took.
    if (settings.noiseThreshold > 0.0f &&
        std::find(settings.aovs.begin(), settings.aovs.end(), "spp") == settings.aovs.end())
        settings.aovs.push_back("spp");
    // Refuse bad outputs and option values before spending time on loading and rendering.
    for (const std::string& output : options.outputs)
        checkOutputPath(output);
    const std::optional<float> exposure = parseExposure(options.exposure);
    ToneMapping toneMapping{exposure.value_or(0.0f), parseToneMapOperator(options.tonemap)};
    parseFilter(settings.filter);
    aovSpecs(settings.aovs);
    PassOverrides overrides;
    if (options.command->count("--max-depth") > 0)
        overrides.maxDepth = settings.maxDepth;
    Pipeline pipeline = script ? makeScriptPipeline(*script, overrides)
                               : makePipelinePreset(options.pipeline, settings);

    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<Scene> scene = loadScene(options.scene);
    const CameraDesc cameraDesc = scriptCamera(*scene, options, script);
    const IVec2 size = chooseImageSize(cameraDesc, settings.width, settings.height);
    settings.width = size.x;
    settings.height = size.y;
    const Camera camera(cameraDesc, size.x, size.y);

    const SceneContents contents = analyseScene(*scene);
    const PipelinePlan plan = planForScene(pipeline, contents);
    for (const std::string& warning : plan.warnings)
        std::cerr << "penumbra: warning: " << warning << "\n";
    if (!settings.quiet) {
        for (const std::string& decision : plan.decisions)
            std::cerr << "penumbra: plan: " << decision << "\n";
    }

    // What each pipeline that ran reports, read while its scene and settings still exist: the
    // image's metadata (the first run's) and the passes' stats.
    std::optional<ImageMetadata> metadata;
    std::vector<std::string> statLines;
    const auto report = [&](const Pipeline& ran, const RenderSettings& ranSettings,
                            const std::string& group) {
        if (!metadata)
            metadata = renderMetadata(ran, ranSettings, 0.0, options.scene.path, cameraDesc.name);
        for (size_t i = 0; i < ran.passes().size(); ++i) {
            if (ran.skipped(i))
                continue;
            const Pass& pass = *ran.passes()[i];
            for (const auto& [key, value] : pass.stats())
                statLines.push_back(group + pass.type() + " " + key + ": " + value);
        }
    };
    PipelineRun run;
    if (options.lightGroups && splitsLightGroupsAtOnce(pipeline)) {
        run = renderLightGroupsAtOnce(pipeline, *scene, contents, camera, settings);
        report(pipeline, settings, "");
    } else if (options.lightGroups) {
        const auto makePipeline = [&] {
            return script ? makeScriptPipeline(*script, overrides)
                          : makePipelinePreset(options.pipeline, settings);
        };
        run = renderLightGroups(*scene, camera, settings, makePipeline, report);
    } else {
        run = runPipeline(pipeline, *scene, contents, camera, settings);
        report(pipeline, settings, "");
    }
    const double seconds = secondsSince(start);
    metadata->set("penumbra:seconds", static_cast<float>(seconds));
    // A script's passes record their own depth (penumbra:path.max_depth).
    if (script)
        metadata->set("penumbra:script", script->file);
    else
        metadata->set("penumbra:max_depth", settings.maxDepth);
    if (options.lightGroups) {
        std::string groups;
        for (const std::string& layer : run.lightGroups)
            groups += (groups.empty() ? "" : " ") + layer.substr(layer.find('.') + 1);
        metadata->set("penumbra:light_groups", groups);
    }
    // Each pass's contribution is a layer of its own when there are several (they sum to the
    // beauty), then the AOVs.
    std::vector<NamedLayer> aovs;
    if (run.contributions.size() > 1) {
        for (const std::string& name : run.contributions)
            aovs.push_back({name, run.layers.at(name)});
    }
    for (const std::string& name : settings.aovs)
        aovs.push_back({name, run.layers.at(name)});
    for (const std::string& name : run.lightGroups)
        aovs.push_back({name, run.layers.at(name)});
    // The histogram adjustment sizes the eye's foveal samples by the view's field.
    if (cameraDesc.projection == ProjectionType::Perspective) {
        const float aspect = float(size.x) / float(size.y);
        toneMapping.horizontalFieldOfViewDegrees =
            glm::degrees(2.0f * std::atan(std::tan(0.5f * cameraDesc.yfov) * aspect));
    }
    if (!exposure) {
        toneMapping.exposure = automaticExposure(run.layers.at("beauty"));
        if (!settings.quiet)
            std::cerr << "penumbra: automatic exposure " << toneMapping.exposure << " EV\n";
    }
    // Ward's operator adapts to the image: its world adaptation luminance.
    if (toneMapping.op == ToneMapOperator::Ward)
        toneMapping.adaptationLuminance = wardAdaptationLuminance(run.layers.at("beauty"));
    for (const std::string& output : options.outputs) {
        const size_t replaced =
            writeImage(output, run.layers.at("beauty"), aovs, *metadata, toneMapping);
        // The film drops non-finite samples, so this is a bug if it happens: say so.
        if (replaced > 0) {
            std::cerr << "penumbra: warning: " << replaced << " non-finite values written as 0 in "
                      << output << "\n";
        }
    }

    if (!settings.quiet) {
        for (const std::string& output : options.outputs)
            std::cerr << "penumbra: wrote " << output << "\n";
        std::cerr << "penumbra: " << size.x << "x" << size.y << ", pipeline " << pipeline.name()
                  << ", " << seconds << " s\n";
        for (const std::string& line : statLines)
            std::cerr << "  " << line << "\n";
    }
}

}  // namespace

void addPipelineOption(CLI::App& command, std::string& pipeline) {
    std::string pipelines;
    for (const std::string& name : pipelinePresetNames())
        pipelines += " " + name;
    command
        .add_option("--pipeline", pipeline,
                    "Pipeline preset (not with a .toml pass script):" + pipelines)
        ->capture_default_str();
}

Command addRenderCommand(CLI::App& app) {
    auto* command = app.add_subcommand("render",
                                       "Render a scene to an image (.exr linear, "
                                       ".png tone-mapped sRGB)");
    auto options = std::make_shared<RenderOptions>();
    options->command = command;
    RenderSettings& s = options->settings;
    addSceneInputOptions(*command, options->scene, PassScripts::Accepted);
    command
        ->add_option("-o,--output", options->outputs,
                     "Output image; the extension picks the format (.exr linear float, .png "
                     "tone-mapped sRGB, ...); repeat to write several. Required unless a pass "
                     "script gives `output`")
        ->take_all();
    addPipelineOption(*command, options->pipeline);
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
    command
        ->add_option("--exposure", options->exposure,
                     "Exposure in EV for tone-mapped output, or auto (the image's log-average "
                     "luminance at middle grey, 0.18)")
        ->capture_default_str();
    command
        ->add_option("--tonemap", options->tonemap,
                     "Tone-mapping operator for 8-bit output: clamp, reinhard, aces, ward (Ward "
                     "1994: a scale factor from the image's adaptation luminance, display "
                     "white at 100 cd/m²), histogram (Ward Larson et al. 1997: histogram "
                     "adjustment within the eye's contrast sensitivity), human (the same and "
                     "the eye's loss of acuity in dim light)")
        ->capture_default_str();
    command
        ->add_option("--noise-threshold", s.noiseThreshold,
                     "Adaptive sampling: a pixel stops taking samples once the standard error of "
                     "its mean luminance is below this fraction of the mean (after 16 samples); "
                     "0 = off. Adds the `spp` layer")
        ->check(CLI::Range(0.0f, 1.0f));
    command->add_option("--aov", options->aovList,
                        "Extra EXR layers, comma separated: albedo, normal, depth, spp, and the "
                        "light-path components emission, direct, indirect, specular (which sum "
                        "to the beauty; `components` = all four)");
    command->add_flag("--light-groups", options->lightGroups,
                      "Split the image by light source group, a layer light.GROUP per group "
                      "(light-NAME, luminaire-NAME, emissive-MATERIAL, sky or environment, "
                      "sun); the beauty is their sum. The path tracer splits them in one "
                      "render; the pipelines that reuse a radiosity solution render once per "
                      "group, --time-limit shared among them");
    return [options] { render(*options); };
}

}  // namespace penumbra::cli
