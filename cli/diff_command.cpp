// `penumbra diff TEST REFERENCE`: image-difference metrics (core/image_metrics.h) as a table or
// one JSON object, thresholds that decide the exit status (for CI), and a heat map.
#include "cli/commands.h"
#include "core/errors.h"
#include "core/heatmap.h"
#include "core/image_io.h"
#include "core/image_metrics.h"
#include "core/version.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

namespace penumbra::cli {

namespace {

// Keys in the order written, for people reading the output.
using Json = nlohmann::ordered_json;

struct DiffOptions {
    std::string test, reference, mask, heatmap;
    std::vector<std::string> metrics, channels, failAbove, failBelow;
    int downsample = 1;
    double epsilon = 1e-2;
    double peak = 0.0;
    bool json = false;
};

// One --fail-above / --fail-below check: METRIC[:ROW]=VALUE.
struct Threshold {
    std::string given;  // as on the command line
    Metric metric = Metric::Rmse;
    std::string row = "all";
    double limit = 0.0;
    bool above = true;  // fails when the value is above the limit (else below)
    double value = 0.0;
    bool passed = false;
};

Threshold parseThreshold(const std::string& text, bool above) {
    const std::string option = above ? "--fail-above" : "--fail-below";
    Threshold threshold;
    threshold.given = text;
    threshold.above = above;
    const size_t equals = text.find('=');
    if (equals == std::string::npos) {
        throw UsageError(option + " " + text + ": expected METRIC=VALUE or METRIC:ROW=VALUE");
    }
    std::string name = text.substr(0, equals);
    if (const size_t colon = name.find(':'); colon != std::string::npos) {
        threshold.row = name.substr(colon + 1);
        name.resize(colon);
    }
    const std::optional<Metric> metric = findMetric(name);
    if (!metric) {
        throw UsageError(option + " " + text + ": unknown metric \"" + name +
                         "\" (metrics: " + metricNameList() + ")");
    }
    threshold.metric = *metric;
    const std::string value = text.substr(equals + 1);
    char* end = nullptr;
    threshold.limit = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || std::isnan(threshold.limit)) {
        throw UsageError(option + " " + text + ": \"" + value + "\" is not a number");
    }
    return threshold;
}

// PNG, JPEG and TIFF hold display values in [0, 1] (core/image_io.h: penumbra writes them
// tone-mapped); anything else (EXR, HDR) scene-linear values.
bool holdsDisplayValues(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff";
}

std::string formatValue(double value) {
    if (std::isnan(value))
        return "-";
    if (std::isinf(value))
        return value > 0 ? "inf" : "-inf";
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", value);
    return text;
}

std::string formatDescription(const Threshold& t) {
    return std::string(metricName(t.metric)) + " (" + t.row + ") = " + formatValue(t.value) +
           (t.above ? " is above " : " is below ") + formatValue(t.limit);
}

// Table of `metrics` (columns) for `rows`, aligned for reading.
void printTable(const std::vector<std::string>& names, const std::vector<MetricValues>& rows,
                const std::vector<Metric>& metrics, const std::string& firstColumn) {
    size_t nameWidth = firstColumn.size();
    for (const std::string& name : names)
        nameWidth = std::max(nameWidth, name.size());
    std::printf("%-*s", int(nameWidth), firstColumn.c_str());
    for (const Metric m : metrics)
        std::printf("  %11s", std::string(metricName(m)).c_str());
    std::printf("\n");
    for (size_t r = 0; r < rows.size(); ++r) {
        std::printf("%-*s", int(nameWidth), names[r].c_str());
        for (const Metric m : metrics)
            std::printf("  %11s", formatValue(rows[r][m]).c_str());
        std::printf("\n");
    }
}

Json metricsJson(const MetricReport& report, const std::vector<MetricValues>& rows,
                 const std::vector<Metric>& metrics) {
    // NaN and infinities are written as null (JSON has no such numbers): PSNR of identical
    // images, metrics of a region without pixels.
    Json object = Json::object();
    for (size_t r = 0; r < rows.size(); ++r) {
        Json row = Json::object();
        for (const Metric m : metrics)
            row[std::string(metricName(m))] = rows[r][m];
        object[report.rowNames[r]] = row;
    }
    return object;
}

// What one comparison found, for the printers.
struct Comparison {
    std::vector<Metric> metrics;  // the columns to print
    std::vector<Threshold> thresholds;
    MetricReport report;
    int testWidth = 0, testHeight = 0;
    bool display = false;   // SSIM on the stored values (else on v / (1 + v))
    std::string blockName;  // "pixel" or "K x K block"
    HeatmapLegend legend;
    std::vector<std::string> failures;  // failed checks, for the exit status
};

std::vector<Metric> selectMetrics(const std::vector<std::string>& names) {
    std::vector<Metric> metrics;
    for (const std::string& name : names) {
        const std::optional<Metric> m = findMetric(name);
        if (!m) {
            throw UsageError("--metric: unknown metric \"" + name +
                             "\" (metrics: " + metricNameList() + ")");
        }
        if (std::find(metrics.begin(), metrics.end(), *m) == metrics.end())
            metrics.push_back(*m);
    }
    if (metrics.empty())
        metrics.assign(kAllMetrics.begin(), kAllMetrics.end());
    return metrics;
}

// Every threshold, and no NaN or infinite pixel in either input.
void check(Comparison& c, const DiffOptions& options) {
    for (Threshold& t : c.thresholds) {
        const int row = c.report.rowIndex(t.row);
        if (row < 0) {
            std::string rows;
            for (const std::string& name : c.report.rowNames)
                rows += (rows.empty() ? "" : ", ") + name;
            throw UsageError((t.above ? "--fail-above " : "--fail-below ") + t.given +
                             ": no row \"" + t.row + "\" (rows: " + rows + ")");
        }
        t.value = c.report.rows[size_t(row)][t.metric];
        // A NaN value (no pixels compared) fails: nothing was verified.
        t.passed = t.above ? t.value <= t.limit : t.value >= t.limit;
        if (!t.passed)
            c.failures.push_back(formatDescription(t));
    }
    if (c.report.testNonFinite > 0)
        c.failures.push_back(options.test + ": " + std::to_string(c.report.testNonFinite) +
                             " pixels are NaN or infinite");
    if (c.report.referenceNonFinite > 0)
        c.failures.push_back(options.reference + ": " +
                             std::to_string(c.report.referenceNonFinite) +
                             " pixels are NaN or infinite");
}

void writeHeatmap(Comparison& c, const DiffOptions& options, const Image& errorMap) {
    std::string channels;
    for (size_t i = 0; i + 1 < c.report.rowNames.size(); ++i) {
        if (c.report.rowNames[i] != "luminance")
            channels += (channels.empty() ? "" : ", ") + c.report.rowNames[i];
    }
    const Image picture = renderHeatmap(
        errorMap, "relMSE per " + c.blockName + ", mean of " + channels + " (log scale)", c.legend);
    ImageMetadata metadata;
    metadata.set("penumbra:version", std::string(kVersion));
    metadata.set("penumbra:heatmap", std::string("relmse, log10 scale, viridis"));
    metadata.set("penumbra:heatmap_low", float(c.legend.low));
    metadata.set("penumbra:heatmap_high", float(c.legend.high));
    writeImage(options.heatmap, picture, {}, metadata, ToneMapping{});
    if (!c.legend.labelled) {
        std::cerr << "penumbra diff: warning: OpenImageIO found no font (install "
                     "fonts-dejavu-core), so the heat map's legend has no values: the bar "
                     "runs from "
                  << formatValue(c.legend.low) << " to " << formatValue(c.legend.high) << "\n";
    }
}

void printJson(const Comparison& c, const DiffOptions& options) {
    const MetricReport& report = c.report;
    Json out;
    out["test"] = options.test;
    out["reference"] = options.reference;
    out["mask"] = options.mask.empty() ? Json(nullptr) : Json(options.mask);
    out["width"] = report.width;
    out["height"] = report.height;
    out["downsample"] = options.downsample;
    out["compared_pixels"] = report.comparedPixels;
    out["nonfinite"] = {{"test", report.testNonFinite}, {"reference", report.referenceNonFinite}};
    out["relmse_epsilon"] = options.epsilon;
    out["psnr_peak"] = report.peak;
    out["ssim_input"] = c.display ? "display" : "reinhard";
    out["metrics"] = metricsJson(report, report.rows, c.metrics);
    if (report.masked) {
        out["mixed_blocks"] = report.mixedBlocks;
        Json regions = Json::array();
        for (const RegionMetrics& region : report.regions) {
            regions.push_back({{"mask_value", region.maskValue},
                               {"pixels", region.pixels},
                               {"metrics", metricsJson(report, region.rows, c.metrics)}});
        }
        out["regions"] = regions;
    }
    if (!options.heatmap.empty()) {
        out["heatmap"] = {{"path", options.heatmap},
                          {"low", c.legend.low},
                          {"high", c.legend.high},
                          {"labelled", c.legend.labelled}};
    }
    Json checks = Json::array();
    for (const Threshold& t : c.thresholds) {
        checks.push_back({{"metric", metricName(t.metric)},
                          {"row", t.row},
                          {"kind", t.above ? "above" : "below"},
                          {"limit", t.limit},
                          {"value", t.value},
                          {"passed", t.passed}});
    }
    out["thresholds"] = checks;
    out["failures"] = c.failures;
    out["passed"] = c.failures.empty();
    std::cout << out.dump(2) << std::endl;  // before the failures on stderr
}

void printText(const Comparison& c, const DiffOptions& options) {
    const MetricReport& report = c.report;
    std::printf("test        %s (%d x %d)\n", options.test.c_str(), c.testWidth, c.testHeight);
    std::printf("reference   %s\n", options.reference.c_str());
    std::printf("compared    %d x %d %s, %zu of them; relMSE eps %g; PSNR peak %s; SSIM on %s\n",
                report.width, report.height,
                options.downsample > 1 ? (c.blockName + "s").c_str() : "pixels",
                report.comparedPixels, options.epsilon, formatValue(report.peak).c_str(),
                c.display ? "the stored values" : "v / (1 + v)");
    std::printf("non-finite  %zu pixels in the test, %zu in the reference\n", report.testNonFinite,
                report.referenceNonFinite);
    if (report.masked) {
        std::printf(
            "mask        %s: %zu regions, %zu mixed blocks left out; each value is the "
            "mean of the per-region values\n",
            options.mask.c_str(), report.regions.size(), report.mixedBlocks);
    }
    std::printf("\n");
    printTable(report.rowNames, report.rows, c.metrics, "channel");
    if (report.masked) {
        std::printf("\nper region, all channels:\n");
        std::vector<std::string> names;
        std::vector<MetricValues> rows;
        for (const RegionMetrics& region : report.regions) {
            names.push_back(formatValue(region.maskValue) + " (" + std::to_string(region.pixels) +
                            " px)");
            rows.push_back(region.rows.back());
        }
        printTable(names, rows, c.metrics, "mask value");
    }
    if (!options.heatmap.empty()) {
        std::printf("\nheat map    %s (relMSE, log scale %s .. %s)\n", options.heatmap.c_str(),
                    formatValue(c.legend.low).c_str(), formatValue(c.legend.high).c_str());
    }
    std::fflush(stdout);  // before the failures on stderr
}

int diff(const DiffOptions& options) {
    // Everything that can be refused is refused before any output is written.
    Comparison c;
    c.metrics = selectMetrics(options.metrics);
    for (const std::string& text : options.failAbove)
        c.thresholds.push_back(parseThreshold(text, true));
    for (const std::string& text : options.failBelow)
        c.thresholds.push_back(parseThreshold(text, false));
    if (!options.heatmap.empty())
        checkOutputPath(options.heatmap);

    const Image test = readImage(options.test);
    const Image reference = readImage(options.reference);
    std::unique_ptr<Image> mask;
    if (!options.mask.empty())
        mask = std::make_unique<Image>(readImage(options.mask));
    c.testWidth = test.width();
    c.testHeight = test.height();

    MetricOptions metricOptions;
    metricOptions.channels = options.channels;
    metricOptions.relMseEpsilon = options.epsilon;
    metricOptions.downsample = options.downsample;
    metricOptions.peak = options.peak;
    metricOptions.computeSsim =
        std::find(c.metrics.begin(), c.metrics.end(), Metric::Ssim) != c.metrics.end() ||
        std::any_of(c.thresholds.begin(), c.thresholds.end(),
                    [](const Threshold& t) { return t.metric == Metric::Ssim; });
    c.display = holdsDisplayValues(options.test) && holdsDisplayValues(options.reference);
    metricOptions.ssimInput = c.display ? SsimInput::Display : SsimInput::Reinhard;
    metricOptions.testName = options.test;
    metricOptions.referenceName = options.reference;
    metricOptions.maskName = options.mask;
    Image errorMap;
    c.report = computeMetrics(test, reference, mask.get(), metricOptions,
                              options.heatmap.empty() ? nullptr : &errorMap);
    const std::string k = std::to_string(options.downsample);
    c.blockName = options.downsample > 1 ? k + " x " + k + " block" : "pixel";

    check(c, options);
    if (!options.heatmap.empty())
        writeHeatmap(c, options, errorMap);
    if (options.json)
        printJson(c, options);
    else
        printText(c, options);
    for (const std::string& failure : c.failures)
        std::cerr << "penumbra diff: FAIL: " << failure << "\n";
    return c.failures.empty() ? 0 : 1;
}

}  // namespace

StatusCommand addDiffCommand(CLI::App& app) {
    auto* command = app.add_subcommand(
        "diff",
        "Compare an image with a reference: RMSE, relMSE, MAE, MRE, PSNR, SSIM per channel and "
        "on luminance; exit 1 when a --fail-above/--fail-below check fails");
    auto options = std::make_shared<DiffOptions>();
    command->add_option("test", options->test, "The image to check (any format OpenImageIO reads)")
        ->required();
    command->add_option("reference", options->reference, "The reference image, same size")
        ->required();
    command
        ->add_option("--metric", options->metrics,
                     "Metrics to print, comma separated (default: all): " + metricNameList())
        ->delimiter(',')
        ->allow_extra_args(false);
    command
        ->add_option("--fail-above", options->failAbove,
                     "METRIC[:ROW]=VALUE: exit 1 if the metric (of ROW, default \"all\") is above "
                     "VALUE; repeatable")
        ->allow_extra_args(false);
    command
        ->add_option("--fail-below", options->failBelow,
                     "METRIC[:ROW]=VALUE: exit 1 if the metric is below VALUE (for psnr, ssim); "
                     "repeatable")
        ->allow_extra_args(false);
    command->add_option("--heatmap", options->heatmap,
                        "Write the per-pixel relMSE in false colour with a legend (.png, .exr)");
    command->add_option("--mask", options->mask,
                        "Mask image, same size: each distinct value of its first channel is a "
                        "region; metrics become the mean of the per-region values");
    command
        ->add_option("--channel", options->channels,
                     "Channels to compare, comma separated (default: R,G,B if present, else all)")
        ->delimiter(',')
        ->allow_extra_args(false);
    command
        ->add_option("--downsample", options->downsample,
                     "Compare K x K block means instead of pixels (Monte Carlo noise falls by "
                     "K^2; docs/testing.md)")
        ->check(atLeast(1))
        ->capture_default_str();
    command
        ->add_option("--epsilon", options->epsilon,
                     "eps of relMSE (x-y)^2/(y^2+eps) and MRE |x-y|/sqrt(y^2+eps)")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    command
        ->add_option("--peak", options->peak,
                     "PSNR peak value (default: the reference's largest compared value)")
        ->check(CLI::PositiveNumber);
    command->add_flag("--json", options->json, "Print one JSON object instead of the table");
    return [options] { return diff(*options); };
}

}  // namespace penumbra::cli
