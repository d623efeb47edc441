// `penumbra bench SCENE -o DIR`: error against run time. Renders the scene with each pipeline at
// each time budget (or sample count), compares every image with a reference by the metrics of
// `penumbra diff` (core/image_metrics.h), writes DIR/results.csv row by row, DIR/summary.csv
// (mean and spread over the repeats) and DIR/error_vs_time.png, drawn by gnuplot from the summary
// with the script DIR/error_vs_time.gp. Ctrl-C ends the benchmark between sample passes and keeps
// what finished. docs/cli.md, "penumbra bench", documents the files.
#include "cli/commands.h"
#include "cli/pipeline_run.h"
#include "cli/scene_input.h"
#include "core/errors.h"
#include "core/film.h"
#include "core/image_io.h"
#include "core/image_metrics.h"
#include "core/stats.h"
#include "passes/pipeline.h"
#include "passes/planner.h"

#include <tbb/info.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <malloc.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

namespace penumbra::cli {

namespace {

namespace fs = std::filesystem;

// The sample target of a time-budget run: the budget ends it long before (1 << 24 samples of a
// 16 x 16 image would take days).
constexpr int kUnboundedSpp = 1 << 24;
// The reference rendered when none is given gets this many times the largest budget.
constexpr int kReferenceFactor = 16;
// Exit status after Ctrl-C, the shell's 128 + SIGINT.
constexpr int kInterruptedStatus = 130;

struct BenchOptions {
    SceneInput scene;
    std::vector<std::string> pipelines, budgets, sppList;
    std::string reference, output;
    int repeat = 1;
    bool keepImages = false;
    RenderSettings settings;
};

// Set by the SIGINT handler, read between sample passes. A lock-free atomic is
// async-signal-safe to store to.
std::atomic<bool> interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

extern "C" void onInterrupt(int) {
    interrupted.store(true);
}

// Catches Ctrl-C while the benchmark runs. SA_RESETHAND restores the default action after the
// first signal, so a second Ctrl-C ends the process at once for a user who will not wait for the
// current sample pass. A SIGINT ignored at start (a background job of a script, nohup) stays
// ignored, as shells expect.
class InterruptHandler {
  public:
    InterruptHandler() {
        interrupted.store(false);
        struct sigaction action {};
        action.sa_handler = onInterrupt;
        action.sa_flags = SA_RESETHAND;
        sigemptyset(&action.sa_mask);
        sigaction(SIGINT, &action, &previous_);
        if (previous_.sa_handler == SIG_IGN)
            sigaction(SIGINT, &previous_, nullptr);
    }
    ~InterruptHandler() { sigaction(SIGINT, &previous_, nullptr); }
    InterruptHandler(const InterruptHandler&) = delete;
    InterruptHandler& operator=(const InterruptHandler&) = delete;

  private:
    struct sigaction previous_ {};
};

// One budget: seconds of --time-limit, or samples per pixel with --spp.
struct Budget {
    double value = 0.0;
    bool spp = false;
    std::string unit() const { return spp ? "spp" : "s"; }
};

std::string formatNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

std::vector<Budget> parseBudgets(const BenchOptions& options) {
    if (options.budgets.empty() == options.sppList.empty())
        throw UsageError("give exactly one of --budgets (seconds) and --spp (samples per pixel)");
    const bool spp = !options.sppList.empty();
    const std::string option = spp ? "--spp" : "--budgets";
    std::vector<Budget> budgets;
    for (const std::string& text : spp ? options.sppList : options.budgets) {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0' || !std::isfinite(value))
            throw UsageError(option + ": \"" + text + "\" is not a number");
        if (spp && (value < 1.0 || value != std::floor(value) || value > kUnboundedSpp)) {
            throw UsageError(option + ": \"" + text +
                             "\" is not a whole number of samples in [1, " +
                             std::to_string(kUnboundedSpp) + "]");
        }
        if (!(value > 0.0))
            throw UsageError(option + ": \"" + text + "\" is not a positive number of seconds");
        budgets.push_back({value, spp});
    }
    if (budgets.empty())
        throw UsageError(option + ": empty list");
    return budgets;
}

std::vector<std::string> checkPipelines(const std::vector<std::string>& given) {
    const std::vector<std::string> valid = pipelinePresetNames();
    if (given.empty())
        return valid;
    std::vector<std::string> pipelines;
    for (const std::string& name : given) {
        if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
            std::string names;
            for (const std::string& v : valid)
                names += (names.empty() ? "" : ", ") + v;
            throw UsageError("--pipelines: unknown pipeline '" + name + "'; valid: " + names);
        }
        if (std::find(pipelines.begin(), pipelines.end(), name) == pipelines.end())
            pipelines.push_back(name);
    }
    return pipelines;
}

// The reference image, refused unless it has R, G and B.
Image readReference(const std::string& path) {
    Image reference = readImage(path);
    for (const char* channel : {"R", "G", "B"}) {
        if (reference.channelIndex(channel) < 0)
            throw UsageError(path + ": the reference has no channel " + channel);
    }
    return reference;
}

// Starts a new peak of the resident set, so that peakMemoryMiB() (core/stats.h) after a run is the
// run's own peak (with the scene and the reference, which stay resident) rather than the largest
// of the benchmark so far. The heap that earlier runs freed is first given back to the system
// (glibc's malloc_trim), else it would stay in the resident set; then Linux >= 4.0 resets VmHWM,
// which getrusage reports, when "5" is written to /proc/self/clear_refs (proc(5)). False where
// that is not possible.
bool resetPeakMemory() {
    malloc_trim(0);
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.close();
    return !clear.fail();
}

// One finished run.
struct RunResult {
    std::string pipeline;
    Budget budget;
    int repeat = 0;
    uint32_t seed = 0;
    int spp = 0;
    double seconds = 0.0;
    double rays = 0.0;
    double peakMemoryMiB = 0.0;
    size_t nonFinite = 0;
    MetricValues metrics;  // on luminance
    // The whole image's mean over the reference's, less 1, per R, G, B channel: the bias a
    // pipeline's estimate keeps (noise averages out over the pixels).
    std::array<double, 3> meanBias{};
};

// Each of R, G, B: the image's mean over the reference's, less 1 (0 where the reference's mean is
// 0). Non-finite pixels are left out of both.
std::array<double, 3> meanBias(const Image& image, const Image& reference) {
    std::array<double, 3> bias{};
    for (int c = 0; c < 3; ++c) {
        double test = 0.0, ref = 0.0;
        for (int y = 0; y < image.height(); ++y) {
            for (int x = 0; x < image.width(); ++x) {
                const float t = image.at(x, y, c), r = reference.at(x, y, c);
                if (std::isfinite(t) && std::isfinite(r)) {
                    test += t;
                    ref += r;
                }
            }
        }
        bias[size_t(c)] = ref > 0.0 ? test / ref - 1.0 : 0.0;
    }
    return bias;
}

// Every pass's stat "rays" and "*_rays" (the radiosity pass's solver and view rays), summed.
double totalRays(const Pipeline& pipeline) {
    double rays = 0.0;
    for (size_t i = 0; i < pipeline.passes().size(); ++i) {
        if (pipeline.skipped(i))
            continue;
        for (const auto& [key, value] : pipeline.passes()[i]->stats()) {
            if (key == "rays" || (key.size() > 5 && key.ends_with("_rays")))
                rays += std::stod(value);
        }
    }
    return rays;
}

// The luminance metrics of `image` against the reference, with the defaults of `penumbra diff`
// (relMSE eps 0.01, SSIM on v / (1 + v)).
MetricReport compare(const Image& image, const Image& reference, const std::string& referenceName) {
    MetricOptions options;
    options.testName = "the render";
    options.referenceName = referenceName;
    return computeMetrics(image, reference, nullptr, options);
}

const std::vector<std::string>& quantityNames() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n = {"spp", "seconds", "rays", "peak_memory_mib",
                                      "nonfinite_pixels"};
        for (const Metric m : kAllMetrics)
            n.emplace_back(metricName(m));
        for (const char* channel : {"r", "g", "b"})
            n.push_back(std::string("mean_bias_") + channel);
        return n;
    }();
    return names;
}

// The run's figures in the order of quantityNames().
std::vector<double> quantities(const RunResult& r) {
    std::vector<double> q = {double(r.spp), r.seconds, r.rays, r.peakMemoryMiB,
                             double(r.nonFinite)};
    for (const Metric m : kAllMetrics)
        q.push_back(r.metrics[m]);
    for (const double bias : r.meanBias)
        q.push_back(bias);
    return q;
}

std::string csvHeader() {
    std::string header = "pipeline,budget,budget_unit,repeat,seed";
    for (const std::string& name : quantityNames())
        header += "," + name;
    return header;
}

std::string csvRow(const RunResult& r) {
    std::string row = r.pipeline + "," + formatNumber(r.budget.value) + "," + r.budget.unit() +
                      "," + std::to_string(r.repeat) + "," + std::to_string(r.seed);
    for (const double q : quantities(r))
        row += "," + formatNumber(q);
    return row;
}

// Writes `text` to `path` through a temporary file renamed over it, so that the file is whole or
// absent.
void writeWhole(const fs::path& path, const std::string& text) {
    const fs::path temporary =
        path.parent_path() / (path.filename().string() + ".tmp-" + std::to_string(getpid()));
    {
        std::ofstream out(temporary);
        out << text;
        out.close();
        if (out.fail()) {
            fs::remove(temporary);
            throw ImageIoError(path.string(), "cannot write");
        }
    }
    fs::rename(temporary, path);
}

// A pipeline's runs grouped by budget, in budget order.
std::map<double, std::vector<const RunResult*>> runsByBudget(const std::vector<RunResult>& results,
                                                             const std::string& pipeline) {
    std::map<double, std::vector<const RunResult*>> byBudget;
    for (const RunResult& r : results) {
        if (r.pipeline == pipeline)
            byBudget[r.budget.value].push_back(&r);
    }
    return byBudget;
}

// The mean of figure q of quantities() over `runs`.
double meanQuantity(const std::vector<const RunResult*>& runs, size_t q) {
    double sum = 0.0;
    for (const RunResult* r : runs)
        sum += quantities(*r)[q];
    return sum / double(runs.size());
}

// summary.csv: per pipeline and budget (sorted by budget, for the plot's lines), the number of
// runs and the mean and sample standard deviation (n - 1; "nan" for one run) of every figure.
std::string summaryCsv(const std::vector<RunResult>& results,
                       const std::vector<std::string>& pipelines) {
    std::string text = "pipeline,budget,budget_unit,runs";
    for (const std::string& name : quantityNames())
        text += "," + name + "_mean," + name + "_std";
    text += "\n";
    for (const std::string& pipeline : pipelines) {
        for (const auto& [budget, runs] : runsByBudget(results, pipeline)) {
            const size_t n = runs.size();
            text += pipeline + "," + formatNumber(budget) + "," + runs.front()->budget.unit() +
                    "," + std::to_string(n);
            for (size_t q = 0; q < quantityNames().size(); ++q) {
                const double mean = meanQuantity(runs, q);
                double squares = 0.0;
                for (const RunResult* r : runs)
                    squares += (quantities(*r)[q] - mean) * (quantities(*r)[q] - mean);
                const double std = n > 1 ? std::sqrt(squares / double(n - 1))
                                         : std::numeric_limits<double>::quiet_NaN();
                // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "," + string.
                text.append(",").append(formatNumber(mean)).append(",").append(formatNumber(std));
            }
            text += "\n";
        }
    }
    return text;
}

// The relMSE targets of time_to_error.csv.
constexpr std::array<double, 2> kErrorTargets = {0.01, 0.001};

// When a pipeline's relMSE reached `target`, from its summary (mean seconds and mean relMSE per
// budget, in budget order): interpolated between the two budgets it fell past the target between,
// linearly in log(seconds) against log(relMSE) (an unbiased pipeline's relMSE falls as a power of
// time, 1 / t when the sample rate is steady). Not extrapolated: below the target at the smallest
// budget or above it at the largest is said, not guessed.
struct TimeToError {
    double seconds = std::numeric_limits<double>::quiet_NaN();
    std::string how;  // "interpolated", "below at the smallest budget", "not reached"
};

TimeToError timeToError(const std::vector<std::pair<double, double>>& secondsAndRelMse,
                        double target) {
    if (secondsAndRelMse.empty())
        return {std::numeric_limits<double>::quiet_NaN(), "not reached"};
    if (secondsAndRelMse.front().second <= target)
        return {secondsAndRelMse.front().first, "below at the smallest budget"};
    for (size_t i = 1; i < secondsAndRelMse.size(); ++i) {
        const auto [t0, e0] = secondsAndRelMse[i - 1];
        const auto [t1, e1] = secondsAndRelMse[i];
        if (!(e1 <= target) || !(e0 > 0.0) || !(e1 > 0.0) || !(t0 > 0.0) || !(t1 > 0.0))
            continue;
        const double f = (std::log(target) - std::log(e0)) / (std::log(e1) - std::log(e0));
        return {std::exp(std::log(t0) + f * (std::log(t1) - std::log(t0))), "interpolated"};
    }
    return {std::numeric_limits<double>::quiet_NaN(), "not reached"};
}

// time_to_error.csv: per pipeline and target relMSE, the seconds it took (timeToError()).
std::string timeToErrorCsv(const std::vector<RunResult>& results,
                           const std::vector<std::string>& pipelines) {
    std::string text = "pipeline,relmse_target,seconds,how\n";
    for (const std::string& pipeline : pipelines) {
        const auto index = [](const std::string& name) {
            const auto& names = quantityNames();
            return size_t(std::find(names.begin(), names.end(), name) - names.begin());
        };
        std::vector<std::pair<double, double>> curve;
        for (const auto& [budget, runs] : runsByBudget(results, pipeline))
            curve.emplace_back(meanQuantity(runs, index("seconds")),
                               meanQuantity(runs, index("relmse")));
        for (const double target : kErrorTargets) {
            const TimeToError t = timeToError(curve, target);
            text.append(pipeline)
                .append(",")
                .append(formatNumber(target))
                .append(",")
                .append(formatNumber(t.seconds))
                .append(",")
                .append(t.how)
                .append("\n");
        }
    }
    return text;
}

// The gnuplot script: log-log relMSE (luminance) against seconds from summary.csv, one line per
// pipeline, error bars of one standard deviation over the repeats.
std::string plotScript(const std::vector<std::string>& pipelines, const std::string& title) {
    std::string names;
    for (const std::string& p : pipelines)
        names += (names.empty() ? "" : " ") + p;
    std::ostringstream gp;
    gp << "# Written by `penumbra bench`; run `gnuplot error_vs_time.gp` in this folder to redraw\n"
          "# error_vs_time.png from summary.csv (gnuplot -e \"out='other.png'\" for another "
          "file).\n"
       << "pipelines = \"" << names << "\"\n"
       << "if (!exists(\"out\")) out = \"error_vs_time.png\"\n"
          "set terminal pngcairo size 900,600 font \"DejaVu Sans,11\"\n"
          "set output out\n"
          "set datafile separator \",\"\n"
          "set datafile columnheaders\n"
          "set logscale xy\n"
          "set format y \"10^{%L}\"\n"
          "set grid xtics ytics mxtics mytics lc rgb \"#dddddd\"\n"
          "set key top right box opaque\n"
       << "set title \"" << title << "\" noenhanced\n"
       << "set xlabel \"render time (s)\"\n"
          "set ylabel \"relMSE of luminance against the reference\"\n"
          "is(p) = strcol(\"pipeline\") eq p\n"
          "plot for [i=1:words(pipelines)] \"summary.csv\" \\\n"
          "         using (is(word(pipelines, i)) ? column(\"seconds_mean\") : NaN):"
          "(column(\"relmse_mean\")) \\\n"
          "         with linespoints lw 2 pt 7 lc i title word(pipelines, i) noenhanced, \\\n"
          "     for [i=1:words(pipelines)] \"summary.csv\" \\\n"
          "         using (is(word(pipelines, i)) ? column(\"seconds_mean\") : NaN):"
          "(column(\"relmse_mean\")):(column(\"relmse_std\")) \\\n"
          "         with yerrorbars lc i pt 7 notitle\n";
    return gp.str();
}

// Runs gnuplot on the script in `directory`, drawing to a temporary file renamed to
// error_vs_time.png when gnuplot succeeds. False (with a message) when gnuplot is not installed;
// throws std::runtime_error when it fails.
bool drawPlot(const fs::path& directory) {
    const std::string temporary = "error_vs_time.tmp-" + std::to_string(getpid()) + ".png";
    const std::string setOutput = "out='" + temporary + "'";
    const char* argv[] = {"gnuplot", "-e", setOutput.c_str(), "error_vs_time.gp", nullptr};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addchdir_np(&actions, directory.c_str());
    pid_t pid = 0;
    const int error =
        posix_spawnp(&pid, "gnuplot", &actions, nullptr, const_cast<char* const*>(argv), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (error == ENOENT) {
        std::cerr << "penumbra bench: gnuplot is not installed (Debian: gnuplot-nox, which "
                     "scripts/setup installs), so there is no plot; the results are kept: run "
                     "`gnuplot error_vs_time.gp` in "
                  << directory.string() << " once it is\n";
        return false;
    }
    if (error != 0)
        throw std::runtime_error(std::string("cannot run gnuplot: ") + std::strerror(error));
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    const fs::path drawn = directory / temporary;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(drawn)) {
        fs::remove(drawn);
        throw std::runtime_error("gnuplot failed on " + (directory / "error_vs_time.gp").string());
    }
    fs::rename(drawn, directory / "error_vs_time.png");
    return true;
}

// Everything a run needs that stays the same across runs.
struct BenchSetup {
    const Scene* scene = nullptr;
    const Camera* camera = nullptr;
    SceneContents contents;   // what decides the passes a pipeline skips (core/scene_contents.h)
    RenderSettings settings;  // size, threads, camera, depth, filter; quiet
};

// A render and the pipeline that made it (whose passes hold the stats).
struct Rendered {
    Pipeline pipeline;
    PipelineRun run;  // run.stopped when Ctrl-C stopped it
};

Rendered renderOnce(const BenchSetup& setup, const std::string& pipelineName, const Budget& budget,
                    uint32_t seed) {
    RenderSettings settings = setup.settings;
    settings.seed = seed;
    settings.spp = budget.spp ? int(budget.value) : kUnboundedSpp;
    settings.timeLimit = budget.spp ? 0.0 : budget.value;
    Rendered rendered{makePipelinePreset(pipelineName, settings), {}};
    planForScene(rendered.pipeline, setup.contents);
    rendered.run = runPipeline(rendered.pipeline, *setup.scene, setup.contents, *setup.camera,
                               settings, [] { return interrupted.load(); });
    return rendered;
}

std::string describeBudget(const Budget& budget) {
    return formatNumber(budget.value) + (budget.spp ? " spp" : " s");
}

// Writes a run's beauty as EXR with the metadata `penumbra render` gives it.
void writeRendered(const Rendered& rendered, const BenchSetup& setup, uint32_t seed,
                   const std::string& scenePath, const std::string& cameraName,
                   const fs::path& path) {
    RenderSettings settings = setup.settings;
    settings.seed = seed;
    ImageMetadata metadata =
        renderMetadata(rendered.pipeline, settings, rendered.run.seconds, scenePath, cameraName);
    metadata.set("penumbra:max_depth", settings.maxDepth);
    writeImage(path.string(), rendered.run.layers.at("beauty"), {}, metadata, ToneMapping{});
}

// Where --keep-images puts a run's image: DIR/images/PIPELINE-BUDGET-rREPEAT.exr, e.g.
// hybrid-16s-r0.exr.
fs::path runImagePath(const fs::path& directory, const RunResult& r) {
    return directory / "images" /
           (r.pipeline + "-" + formatNumber(r.budget.value) + r.budget.unit() + "-r" +
            std::to_string(r.repeat) + ".exr");
}

// Renders the reference with the `reference` pipeline at kReferenceFactor times the largest
// budget and writes it to DIR/reference.exr. Nothing when Ctrl-C stopped it.
std::optional<Image> renderReference(const BenchSetup& setup, const BenchOptions& options,
                                     const std::vector<Budget>& budgets, const fs::path& path,
                                     const std::string& cameraName) {
    Budget budget = budgets.front();
    for (const Budget& b : budgets)
        budget.value = std::max(budget.value, b.value);
    budget.value *= kReferenceFactor;
    const uint32_t seed = options.settings.seed + uint32_t(options.repeat);
    if (!options.scene.quiet) {
        std::cerr << "penumbra bench: no --reference: rendering one with `reference` for "
                  << kReferenceFactor << " x the largest budget = " << describeBudget(budget)
                  << " (seed " << seed << ", not one of the runs') to " << path.string() << "\n";
    }
    Rendered rendered = renderOnce(setup, "reference", budget, seed);
    if (rendered.run.stopped)
        return std::nullopt;
    writeRendered(rendered, setup, seed, options.scene.path, cameraName, path);
    Image& image = rendered.run.layers.at("beauty");
    if (!options.scene.quiet) {
        std::cerr << "penumbra bench: reference: " << passStat(rendered.pipeline, "spp")
                  << " spp in " << formatNumber(rendered.run.seconds) << " s\n";
    }
    return std::move(image);
}

// The output folder (and its images/ folder for --keep-images), created if need be; refused
// when it cannot hold the results.
fs::path prepareOutput(const std::string& output, bool keepImages) {
    const fs::path directory(output);
    std::error_code error;
    if (fs::exists(directory, error) && !fs::is_directory(directory, error))
        throw UsageError("-o " + output + ": exists and is not a folder");
    fs::create_directories(directory, error);
    if (error)
        throw UsageError("-o " + output + ": cannot create the folder: " + error.message());
    // Refuses a folder that cannot be written to, before any time is spent.
    checkOutputPath((directory / "reference.exr").string());
    if (keepImages) {
        fs::create_directories(directory / "images", error);
        if (error) {
            throw UsageError("-o " + output +
                             ": cannot create the folder images in it: " + error.message());
        }
        checkOutputPath((directory / "images" / "run.exr").string());
    }
    return directory;
}

int bench(BenchOptions& options) {
    // Everything that can be refused is refused before any rendering or writing.
    const std::vector<Budget> budgets = parseBudgets(options);
    const std::vector<std::string> pipelines = checkPipelines(options.pipelines);
    std::optional<Image> reference;
    if (!options.reference.empty())
        reference = readReference(options.reference);
    const std::unique_ptr<Scene> scene = loadScene(options.scene);

    BenchSetup setup;
    setup.scene = scene.get();
    setup.contents = analyseScene(*scene);
    setup.settings = options.settings;
    setup.settings.quiet = true;  // one line per run instead of the passes' progress bars
    RenderSettings& s = setup.settings;
    const CameraDesc cameraDesc =
        chooseCamera(scene->description().cameras, s.camera, scene->bounds());
    if (reference && s.width == 0 && s.height == 0) {
        s.width = reference->width();
        s.height = reference->height();
    }
    const IVec2 size = chooseImageSize(cameraDesc, s.width, s.height);
    s.width = size.x;
    s.height = size.y;
    if (reference && (reference->width() != size.x || reference->height() != size.y)) {
        throw UsageError(options.reference + ": the reference is " +
                         std::to_string(reference->width()) + "x" +
                         std::to_string(reference->height()) + " but the benchmark renders " +
                         std::to_string(size.x) + "x" + std::to_string(size.y) +
                         " (--width, --height); leave them out to render at the reference's size");
    }
    parseFilter(s.filter);
    const Camera camera(cameraDesc, size.x, size.y);
    setup.camera = &camera;
    const bool quiet = options.scene.quiet;
    // Each pipeline built once before the folder is made, which also prints the plan's warnings
    // (light paths a pipeline leaves out of this scene) as `penumbra render` does.
    for (const std::string& name : pipelines) {
        Pipeline pipeline = makePipelinePreset(name, s);
        for (const std::string& warning : planForScene(pipeline, setup.contents).warnings) {
            if (!quiet)
                std::cerr << "penumbra bench: " << name << ": warning: " << warning << "\n";
        }
    }
    const fs::path directory = prepareOutput(options.output, options.keepImages);

    const InterruptHandler interruptHandler;
    const int threads = s.threads > 0 ? s.threads : tbb::info::default_concurrency();
    if (!quiet) {
        std::cerr << "penumbra bench: " << options.scene.path << ", " << size.x << "x" << size.y
                  << ", " << threads << " threads, " << pipelines.size() << " pipelines x "
                  << budgets.size() << " budgets x " << options.repeat << " repeats (seeds "
                  << s.seed << ".." << s.seed + uint32_t(options.repeat) - 1
                  << "); Ctrl-C stops and keeps what finished\n";
    }
    std::string referenceName = options.reference;
    if (!reference) {
        referenceName = (directory / "reference.exr").string();
        reference = renderReference(setup, options, budgets, referenceName, cameraDesc.name);
        if (!reference) {
            std::cerr << "penumbra bench: interrupted while rendering the reference; nothing "
                         "written\n";
            return kInterruptedStatus;
        }
    }

    const fs::path csvPath = directory / "results.csv";
    std::ofstream csv(csvPath);
    csv << csvHeader() << std::endl;
    if (!csv)
        throw ImageIoError(csvPath.string(), "cannot write");
    std::vector<RunResult> results;
    const size_t total = budgets.size() * size_t(options.repeat) * pipelines.size();
    // Budgets outermost and pipelines innermost, so that the pipelines compared alternate in time
    // on a shared machine (docs/benchmarks.md) and a stopped benchmark has every pipeline at the
    // smaller budgets.
    for (const Budget& budget : budgets) {
        for (int repeat = 0; repeat < options.repeat && !interrupted; ++repeat) {
            for (const std::string& name : pipelines) {
                RunResult r;
                r.pipeline = name;
                r.budget = budget;
                r.repeat = repeat;
                r.seed = s.seed + uint32_t(repeat);
                resetPeakMemory();
                const Rendered rendered = renderOnce(setup, name, budget, r.seed);
                if (rendered.run.stopped)
                    break;
                r.peakMemoryMiB = peakMemoryMiB();
                r.seconds = rendered.run.seconds;
                const std::string spp = passStat(rendered.pipeline, "spp");
                r.spp = spp.empty() ? 0 : std::stoi(spp);
                r.rays = totalRays(rendered.pipeline);
                const MetricReport report =
                    compare(rendered.run.layers.at("beauty"), *reference, referenceName);
                r.metrics = report.rows[size_t(report.rowIndex("luminance"))];
                r.meanBias = meanBias(rendered.run.layers.at("beauty"), *reference);
                r.nonFinite = report.testNonFinite;
                if (options.keepImages) {
                    writeRendered(rendered, setup, r.seed, options.scene.path, cameraDesc.name,
                                  runImagePath(directory, r));
                }
                csv << csvRow(r) << std::endl;  // flushed: a stopped benchmark keeps the row
                results.push_back(r);
                if (!quiet) {
                    std::cerr << "penumbra bench: [" << results.size() << "/" << total << "] "
                              << name << ", " << describeBudget(budget) << ", repeat " << repeat + 1
                              << "/" << options.repeat << " (seed " << r.seed << "): " << r.spp
                              << " spp in " << formatNumber(r.seconds) << " s, relMSE "
                              << formatNumber(r.metrics[Metric::RelMse]) << ", SSIM "
                              << formatNumber(r.metrics[Metric::Ssim]) << "\n";
                }
            }
        }
    }
    csv.close();
    if (interrupted) {
        std::cerr << "penumbra bench: interrupted after " << results.size() << " of " << total
                  << " runs; " << csvPath.string() << " keeps them\n";
    }
    if (!results.empty()) {
        writeWhole(directory / "summary.csv", summaryCsv(results, pipelines));
        writeWhole(directory / "time_to_error.csv", timeToErrorCsv(results, pipelines));
        const std::string title = fs::path(options.scene.path).filename().string() + ", " +
                                  std::to_string(size.x) + "x" + std::to_string(size.y) + ", " +
                                  std::to_string(threads) + " threads";
        writeWhole(directory / "error_vs_time.gp", plotScript(pipelines, title));
        if (drawPlot(directory) && !quiet) {
            std::cerr << "penumbra bench: wrote " << csvPath.string() << ", summary.csv, "
                      << "time_to_error.csv, error_vs_time.png\n";
        }
    }
    return interrupted ? kInterruptedStatus : 0;
}

}  // namespace

StatusCommand addBenchCommand(CLI::App& app) {
    auto* command = app.add_subcommand(
        "bench",
        "Error against run time: render with each pipeline at each time budget (or --spp), "
        "compare with a reference, write results.csv and error_vs_time.png");
    auto options = std::make_shared<BenchOptions>();
    RenderSettings& s = options->settings;
    addSceneInputOptions(*command, options->scene, PassScripts::Refused);
    command->add_option("-o,--output", options->output, "Folder for the results (created)")
        ->required();
    std::string pipelines;
    for (const std::string& name : pipelinePresetNames())
        pipelines += " " + name;
    command
        ->add_option("--pipelines", options->pipelines,
                     "Pipelines to compare, comma separated (default: all):" + pipelines)
        ->delimiter(',')
        ->allow_extra_args(false);
    command
        ->add_option("--budgets", options->budgets,
                     "Time budgets in seconds, comma separated (each run's --time-limit)")
        ->delimiter(',')
        ->allow_extra_args(false);
    command
        ->add_option("--spp", options->sppList,
                     "Samples per pixel, comma separated, instead of --budgets")
        ->delimiter(',')
        ->allow_extra_args(false);
    command->add_option("--reference", options->reference,
                        "Reference image (EXR, same size); default: render one with `reference` "
                        "at 16 x the largest budget, saved as reference.exr in the folder");
    command
        ->add_option("--repeat", options->repeat,
                     "Runs per pipeline and budget, with seeds S, S+1, ...")
        ->check(atLeast(1))
        ->capture_default_str();
    command->add_flag("--keep-images", options->keepImages,
                      "Also write every run's image to images/PIPELINE-BUDGET-rREPEAT.exr in the "
                      "folder");
    command
        ->add_option("--width", s.width,
                     "Image width (default: the reference's, else from --height and the camera)")
        ->check(atLeast(1));
    command->add_option("--height", s.height, "Image height")->check(atLeast(1));
    command->add_option("--seed", s.seed, "First random seed S")->capture_default_str();
    command->add_option("--threads", s.threads, "Worker threads (default: all cores)")
        ->check(atLeast(0));
    command->add_option("--camera", s.camera, "Name of the glTF camera (default: the first)");
    command
        ->add_option("--max-depth", s.maxDepth,
                     "Maximum number of bounces of the path tracer (-1: unlimited)")
        ->check(CLI::Range(-1, 1 << 20))
        ->capture_default_str();
    command->add_option("--filter", s.filter, "Pixel filter: box, gaussian, blackman-harris")
        ->capture_default_str();
    return [options] { return bench(*options); };
}

}  // namespace penumbra::cli
