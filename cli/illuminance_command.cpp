// `penumbra illuminance SCENE --points IN.csv -o OUT.csv`: the illuminance at calculation points,
// as a light meter would read it, with each value's standard error.
#include "cli/calculation_points.h"
#include "cli/commands.h"
#include "cli/scene_input.h"
#include "core/camera.h"
#include "core/errors.h"
#include "core/heatmap.h"
#include "core/image_io.h"
#include "core/light_groups.h"
#include "core/progress.h"
#include "core/scene_contents.h"
#include "core/sky.h"
#include "core/stats.h"
#include "passes/pipeline.h"
#include "passes/planner.h"
#include "passes/sampling_pass.h"
#include "raytrace/sensor_irradiance.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>

namespace penumbra::cli {

namespace {

struct IlluminanceOptions {
    CLI::App* command = nullptr;
    SceneInput scene;
    std::string points;
    std::string output;
    std::string pipeline = "reference";
    IlluminanceSettings settings;
    int threads = 0;
    bool daylightFactor = false;
    bool lightGroups = false;
    std::string grid, gridPolygon, gridFloor;
    std::string picture;
};

// The workplane's illuminance as a false-colour picture (core/heatmap.h): a cell per point, north
// (-Z) up, scaled up to about 320 pixels across.
void writeGridPicture(const std::string& path, const Workplane& grid,
                      const std::vector<PointIlluminance>& results) {
    const int scale = std::max(1, 320 / std::max(grid.columns, grid.rows));
    Image lux(grid.columns * scale, grid.rows * scale, {"Y"});
    const auto cellPixels = [&](int cell, const auto& visit) {
        const int i = cell % grid.columns, j = cell / grid.columns;
        for (int y = 0; y < scale; ++y)
            for (int x = 0; x < scale; ++x)
                visit(i * scale + x, j * scale + y);
    };
    for (size_t k = 0; k < grid.cells.size(); ++k)
        cellPixels(grid.cells[k], [&](int x, int y) { lux.at(x, y, 0) = float(results[k].lux); });
    HeatmapLegend legend;
    Image picture = renderHeatmap(lux, "illuminance, lux (log scale)", legend);
    // The cells of the bounding rectangle off the workplane show the background.
    std::vector<bool> onWorkplane(size_t(grid.columns * grid.rows), false);
    for (const int cell : grid.cells)
        onWorkplane[size_t(cell)] = true;
    for (int cell = 0; cell < grid.columns * grid.rows; ++cell) {
        if (onWorkplane[size_t(cell)])
            continue;
        cellPixels(cell, [&](int x, int y) {
            for (int c = 0; c < 3; ++c)
                picture.at(x, y, c) = kFalseColourBackground;
        });
    }
    ImageMetadata metadata;
    metadata.set("penumbra:heatmap", std::string("illuminance_lux, log10 scale, viridis"));
    metadata.set("penumbra:heatmap_low", float(legend.low));
    metadata.set("penumbra:heatmap_high", float(legend.high));
    writeImage(path, picture, {}, metadata, ToneMapping{});
}

// The sky's unobstructed horizontal illuminance for --daylight-factor: defined under an overcast
// sky alone (CIE), whose E_h the user gave or took by default.
double daylightFactorBase(const EnvironmentInput& input) {
    if (!input.sky)
        throw UsageError(
            "--daylight-factor needs an overcast sky: --sky cie-overcast (or cie:1 "
            "to cie:5, uniform)");
    if (skyNeedsSun(*input.sky) || input.sunDirectNormal) {
        throw UsageError(
            "--daylight-factor is defined under an overcast sky without the sun: "
            "not with --sky " +
            *input.sky + (input.sunDirectNormal ? " and --sun-direct-normal" : ""));
    }
    if (input.scale)
        throw UsageError("--daylight-factor: the sky's --environment-scale would change E_h");
    return input.skyIlluminance.value_or(SkySettings{}.horizontalIlluminance);
}

// A pipeline run for its image-forming pass's estimator rather than for an image: it runs on an
// image of one pixel and one sample, so that the products the estimator reads (a radiosity
// solution, a caustic map) exist, and keeps alive everything the estimator refers to.
class PreparedPipeline {
  public:
    PreparedPipeline(Pipeline pipeline, const Scene& scene, const IlluminanceSettings& s,
                     bool quiet)
        : pipeline_(std::move(pipeline)),
          contents_(analyseScene(scene)),
          camera_(chooseCamera(scene.description().cameras, "", scene.bounds()), 1, 1) {
        settings_.width = settings_.height = 1;
        settings_.spp = 1;
        settings_.seed = s.seed;
        settings_.quiet = quiet;
        const PipelinePlan plan = planForScene(pipeline_, contents_);
        for (const std::string& warning : plan.warnings)
            std::cerr << "penumbra: warning: " << warning << "\n";
        context_ = std::make_unique<PassContext>(scene, contents_, camera_, settings_);
        pipeline_.run(*context_);
        for (size_t i = 0; i < pipeline_.passes().size(); ++i) {
            if (pipeline_.skipped(i))
                continue;
            if (const auto* pass = dynamic_cast<const SamplingPass*>(pipeline_.passes()[i].get())) {
                estimator_ = &pass->estimator();
                passType_ = pass->type();
            }
        }
        if (!estimator_)
            throw UsageError("pipeline " + pipeline_.name() +
                             ": no pass of it forms an image to measure by");
        // What the other image-forming passes add to the image (the caustic pass's caustics) is
        // not in the points: say so.
        if (!quiet) {
            for (const std::string& layer : context_->contributions) {
                if (layer != passType_) {
                    std::cerr << "penumbra: warning: the points count the " << passType_
                              << " pass's light; what the " << layer
                              << " pass adds to images is left out\n";
                }
            }
        }
    }

    const RadianceEstimator& estimator() const { return *estimator_; }
    const std::string& name() const { return pipeline_.name(); }

  private:
    Pipeline pipeline_;
    const SceneContents contents_;
    const Camera camera_;
    RenderSettings settings_;
    std::unique_ptr<PassContext> context_;
    const RadianceEstimator* estimator_ = nullptr;
    std::string passType_;
};

void measure(IlluminanceOptions& options) {
    IlluminanceSettings& settings = options.settings;
    std::optional<PassScript> script = readPassScript(options.scene);
    if (script) {
        takePipelineOption(*script, options.command->count("--pipeline") > 0, options.pipeline);
        if (options.command->count("--spp") == 0 && script->spp)
            settings.samples = *script->spp;
        if (options.command->count("--seed") == 0 && script->seed)
            settings.seed = *script->seed;
    }
    if (settings.samples < 2)
        throw UsageError("--spp: at least 2 (a standard error needs two samples)");
    std::optional<double> skyHorizontalIlluminance;
    if (options.daylightFactor) {
        try {
            skyHorizontalIlluminance = daylightFactorBase(options.scene.environment);
        } catch (const std::invalid_argument& e) {
            const std::string message = e.what();
            throw UsageError("--sky: " + message);
        }
    }
    checkPointsOutputPath(options.output);
    const int given = int(!options.points.empty()) + int(!options.grid.empty()) +
                      int(!options.gridPolygon.empty()) + int(!options.gridFloor.empty());
    if (given != 1) {
        throw UsageError(
            "give the points with one of --points IN.csv, --grid, --grid-polygon and "
            "--grid-floor");
    }
    const bool workplane = options.points.empty();
    if (!options.picture.empty()) {
        if (!workplane)
            throw UsageError(
                "--picture draws a workplane: give --grid, --grid-polygon or "
                "--grid-floor");
        checkOutputPath(options.picture);
    }
    // Every form is checked before the scene is loaded; the floor's cells need the scene.
    Workplane grid;
    std::optional<FloorWorkplane> floor;
    if (!options.grid.empty())
        grid = workplaneGrid(options.grid);
    else if (!options.gridPolygon.empty())
        grid = workplanePolygon(options.gridPolygon);
    else if (!options.gridFloor.empty())
        floor = parseFloorWorkplane(options.gridFloor);
    const std::vector<CalculationPoint> givenPoints =
        workplane ? std::vector<CalculationPoint>{} : readCalculationPoints(options.points);

    const auto start = std::chrono::steady_clock::now();
    const std::unique_ptr<Scene> scene = loadScene(options.scene);
    if (floor)
        grid = workplaneOverFloor(*floor, scene->description());
    if (workplane && grid.points.empty())
        throw UsageError("the workplane has no cell: its spacing is larger than the area");
    const std::vector<CalculationPoint>& points = workplane ? grid.points : givenPoints;
    const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
    // The points are in the file's world frame; the scene is stored relative to its origin
    // (core/scene_description.h).
    const glm::dvec3 origin = scene->description().origin;
    std::vector<Sensor> sensors;
    sensors.reserve(points.size());
    for (const CalculationPoint& point : points) {
        const glm::dvec3 p(point.given[0], point.given[1], point.given[2]);
        sensors.push_back(Sensor{Vec3(p - origin), point.normal});
    }
    // The sensors' readings in `lit` (the scene, or one light group's), with the pipeline
    // prepared over it; its solve counts against `budget` (seconds, 0 = none), the samples get
    // what is left (at least a round).
    std::string pipelineName;
    const auto readingsIn = [&](const Scene& lit, double budget, const std::string& what) {
        const auto begin = std::chrono::steady_clock::now();
        const PreparedPipeline pipeline(
            script ? makeScriptPipeline(*script, PassOverrides{})
                   : makePipelinePreset(options.pipeline, RenderSettings{}),
            lit, settings, options.scene.quiet);
        pipelineName = pipeline.name();
        IlluminanceSettings share = settings;
        share.timeLimit = budget > 0.0 ? std::max(budget - secondsSince(begin), 1e-9) : 0.0;
        Progress progress(what, uint64_t(sensors.size()) * uint64_t(settings.samples),
                          options.scene.quiet);
        std::vector<SensorReading> readings =
            measureIlluminance(lit, pipeline.estimator(), sensors, share, &progress);
        progress.finish();
        return readings;
    };
    const double budget =
        settings.timeLimit > 0.0 ? std::max(settings.timeLimit - secondsSince(start), 1e-9) : 0.0;
    std::vector<SensorReading> readings;
    // Per light group (core/light_groups.h): its readings, which sum to the whole scene's.
    GroupColumns groupColumns;
    if (!options.lightGroups) {
        readings = readingsIn(*scene, budget, "illuminance");
    } else {
        const std::vector<LightGroup> groups = lightGroups(scene->description());
        if (groups.empty()) {
            throw UsageError(scene->description().file +
                             ": --light-groups: the scene has no light source to split into "
                             "groups");
        }
        readings.assign(sensors.size(), SensorReading{});
        for (size_t k = 0; k < readings.size(); ++k)
            readings[k].samples = std::numeric_limits<int>::max();
        for (const LightGroup& group : groups) {
            const Scene lit(litOnlyBy(scene->description(), group));
            const std::vector<SensorReading> part =
                readingsIn(lit, budget / double(groups.size()), "illuminance, " + group.name);
            std::vector<PointIlluminance> column;
            for (size_t k = 0; k < part.size(); ++k) {
                column.push_back({part[k].lux, part[k].standardError});
                SensorReading& sum = readings[k];
                sum.lux += part[k].lux;
                // Independent estimates: their variances add.
                sum.standardError = std::hypot(sum.standardError, part[k].standardError);
                sum.samples = std::min(sum.samples, part[k].samples);
                sum.dropped += part[k].dropped;
            }
            groupColumns.emplace_back(group.name, std::move(column));
        }
    }

    std::vector<PointIlluminance> results;
    int samples = readings.front().samples;
    int dropped = 0;
    for (const SensorReading& r : readings) {
        results.push_back({r.lux, r.standardError});
        samples = std::min(samples, r.samples);
        dropped += r.dropped;
    }
    writePointIlluminance(options.output, points, results, skyHorizontalIlluminance, groupColumns);
    if (!options.picture.empty())
        writeGridPicture(options.picture, grid, results);
    if (dropped > 0) {
        std::cerr << "penumbra: warning: " << dropped
                  << " non-finite samples dropped (a bug: please report it)\n";
    }
    if (!options.scene.quiet) {
        std::cerr << "penumbra: wrote " << options.output << ": " << points.size() << " points, "
                  << samples << " samples each, pipeline " << pipelineName << ", "
                  << secondsSince(start) << " s\n";
    }
}

}  // namespace

Command addIlluminanceCommand(CLI::App& app) {
    auto* command = app.add_subcommand(
        "illuminance",
        "Illuminance (lux) at calculation points read from a CSV file, with standard errors");
    auto options = std::make_shared<IlluminanceOptions>();
    options->command = command;
    addSceneInputOptions(*command, options->scene, PassScripts::Accepted);
    command
        ->add_option("--points", options->points,
                     "Calculation points: a CSV file of rows x,y,z,nx,ny,nz (metres in the glTF "
                     "world frame, the sensor's normal; a header row allowed)")
        ->check(CLI::ExistingFile);
    command->add_option("--grid", options->grid,
                        "A workplane instead of --points: X0,Z0,X1,Z1,HEIGHT,SPACING, upward "
                        "sensors at the centres of square cells over x in [X0, X1], z in "
                        "[Z0, Z1] at y = HEIGHT (metres)");
    command->add_option(
        "--grid-polygon", options->gridPolygon,
        "A workplane over a polygon: HEIGHT,SPACING,X0,Z0,X1,Z1,X2,Z2[,...], upward sensors at "
        "y = HEIGHT at the centres of the square cells inside it");
    command->add_option(
        "--grid-floor", options->gridFloor,
        "A workplane over a room's floor: NAME,HEIGHT,SPACING, upward sensors HEIGHT above the "
        "faces facing up of the meshes whose material or mesh is NAME");
    command->add_option("--picture", options->picture,
                        "With a workplane: its illuminance as a false-colour picture "
                        "(.png, .exr, ...) with its legend");
    command
        ->add_option("-o,--output", options->output,
                     "Results: a CSV file with the header "
                     "x,y,z,nx,ny,nz,illuminance_lux,stderr_lux, one row per point in order")
        ->required();
    addPipelineOption(*command, options->pipeline);
    command
        ->add_option("--spp", options->settings.samples,
                     "Samples per point (the target with --time-limit), at least 2")
        ->check(atLeast(2))
        ->capture_default_str();
    command->add_option("--seed", options->settings.seed, "Random seed; same seed, same results")
        ->capture_default_str();
    command->add_option("--threads", options->threads, "Worker threads (default: all cores)")
        ->check(atLeast(0));
    command
        ->add_option("--time-limit", options->settings.timeLimit,
                     "Stop after about this many seconds, at a whole round of samples (every "
                     "point gets the same number)")
        ->check(CLI::NonNegativeNumber);
    command->add_flag("--daylight-factor", options->daylightFactor,
                      "Also write each point's daylight factor, 100 E / E_h in percent, E_h the "
                      "overcast sky's unobstructed horizontal illuminance (--sky-illuminance)");
    command->add_flag("--light-groups", options->lightGroups,
                      "Measure each light source group alone (as render --light-groups) and add "
                      "the columns illuminance_lux_GROUP,stderr_lux_GROUP per group; the "
                      "illuminance is their sum. Costs a measurement per group: --time-limit is "
                      "shared among them");
    return [options] { measure(*options); };
}

}  // namespace penumbra::cli
