// `penumbra bench` through the real binary: the CSV files (header, one row per run, the summary of
// the repeats), the reference it renders when none is given, the error falling as 1/spp, time
// budgets that end every pipeline, Ctrl-C keeping the finished runs, the plot, the images kept
// with --keep-images, and bad options
// refused with exit status 2 and nothing written.
#include "core/image_io.h"
#include "core/image_metrics.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

namespace penumbra::test {
namespace {

namespace fs = std::filesystem;

const std::string kCornellBox =
    std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.gltf";
const std::string kCornellReference =
    std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/reference.exr";

const std::string kHeader =
    "pipeline,budget,budget_unit,repeat,seed,spp,seconds,rays,peak_memory_mib,nonfinite_pixels,"
    "rmse,relmse,mae,mre,psnr,ssim,mean_bias_r,mean_bias_g,mean_bias_b";

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

// A CSV file as rows of named fields (the header's names).
struct Csv {
    std::vector<std::string> header;
    std::vector<std::map<std::string, std::string>> rows;
    std::vector<size_t> fieldCounts;  // of every row, to catch a half-written one

    double number(size_t row, const std::string& column) const {
        return std::stod(rows.at(row).at(column));
    }
};

std::vector<std::string> splitFields(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream stream(line);
    std::string field;
    while (std::getline(stream, field, ','))
        fields.push_back(field);
    return fields;
}

Csv readCsv(const std::string& path) {
    Csv csv;
    std::ifstream in(path);
    std::string line;
    if (!std::getline(in, line))
        return csv;
    csv.header = splitFields(line);
    while (std::getline(in, line)) {
        const std::vector<std::string> fields = splitFields(line);
        csv.fieldCounts.push_back(fields.size());
        std::map<std::string, std::string> row;
        for (size_t i = 0; i < fields.size() && i < csv.header.size(); ++i)
            row[csv.header[i]] = fields[i];
        csv.rows.push_back(row);
    }
    return csv;
}

size_t lineCount(const std::string& path) {
    std::ifstream in(path);
    size_t lines = 0;
    std::string line;
    while (std::getline(in, line))
        ++lines;
    return lines;
}

bool gnuplotInstalled() {
    return std::system("command -v gnuplot > /dev/null 2>&1") == 0;
}

// The closed unit box (walls of albedo 0.5) lit by a ceiling light, seen from inside: its radiosity
// solve takes milliseconds, unlike the Cornell box's seconds.
class BenchCli : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir("bench-cli");
        GltfBuilder scene;
        const int wall = scene.addMaterial({.baseColor = Color(0.5f)});
        addClosedBox(scene, wall, wall);
        addCeilingLight(scene, 0.3f, 0.99f, 10.0f);
        scene.setPerspectiveCamera({0.0f, 0.0f, 0.9f}, {0, 0, 0, 1}, 1.2f);
        scene.write(file("box.gltf"));
        const CliResult reference =
            runPenumbra("render " + file("box.gltf") + " --spp 256 --width 16 --height 16 -q -o " +
                        file("box-reference.exr"));
        ASSERT_EQ(reference.status, 0) << reference.output;
    }
    static void TearDownTestSuite() { delete dir_; }

    static std::string file(const std::string& name) { return dir_->file(name); }
    static CliResult bench(const std::string& arguments) {
        return runPenumbra("bench " + file("box.gltf") + " --threads 2 " + arguments);
    }

    static TempDir* dir_;
};

TempDir* BenchCli::dir_ = nullptr;

TEST_F(BenchCli, WritesOneRowPerRunAndTheSummaryOfTheRepeats) {
    const std::string out = file("rows");
    const CliResult r = bench(
        "--pipelines reference,radiosity --spp 1,2 --repeat 2 --width 16 "
        "--height 16 -o " +
        out);
    ASSERT_EQ(r.status, 0) << r.output;
    // No --reference: one was rendered at 16 x the largest budget, with a seed no run uses.
    EXPECT_TRUE(contains(r.output, "16 x the largest budget = 32 spp (seed 2")) << r.output;
    const Image reference = readImage(out + "/reference.exr");
    EXPECT_EQ(reference.width(), 16);
    EXPECT_EQ(reference.height(), 16);
    EXPECT_TRUE(contains(r.output, "[8/8] radiosity, 2 spp, repeat 2/2 (seed 1)")) << r.output;

    std::ifstream in(out + "/results.csv");
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, kHeader);
    const Csv results = readCsv(out + "/results.csv");
    ASSERT_EQ(results.rows.size(), 8u);
    std::map<std::string, int> perPipeline;
    for (size_t i = 0; i < results.rows.size(); ++i) {
        EXPECT_EQ(results.fieldCounts[i], results.header.size());
        ++perPipeline[results.rows[i].at("pipeline")];
        EXPECT_EQ(results.rows[i].at("budget_unit"), "spp");
        // In spp mode every run reaches its budget exactly; seed = first seed + repeat.
        EXPECT_EQ(results.number(i, "spp"), results.number(i, "budget"));
        EXPECT_EQ(results.number(i, "seed"), results.number(i, "repeat"));
        EXPECT_GT(results.number(i, "rays"), 0.0);
        EXPECT_GT(results.number(i, "peak_memory_mib"), 1.0);
        EXPECT_EQ(results.number(i, "nonfinite_pixels"), 0.0);
        for (const char* metric : {"rmse", "relmse", "mae", "mre", "psnr", "ssim"})
            EXPECT_TRUE(std::isfinite(results.number(i, metric))) << metric << " in row " << i;
    }
    EXPECT_EQ(perPipeline["reference"], 4);
    EXPECT_EQ(perPipeline["radiosity"], 4);

    const Csv summary = readCsv(out + "/summary.csv");
    ASSERT_EQ(summary.rows.size(), 4u);
    for (size_t i = 0; i < summary.rows.size(); ++i) {
        EXPECT_EQ(summary.number(i, "runs"), 2.0);
        // The mean of the two rows of results.csv with this pipeline and budget.
        double sum = 0.0;
        for (size_t j = 0; j < results.rows.size(); ++j) {
            if (results.rows[j].at("pipeline") == summary.rows[i].at("pipeline") &&
                results.rows[j].at("budget") == summary.rows[i].at("budget"))
                sum += results.number(j, "relmse");
        }
        EXPECT_NEAR(summary.number(i, "relmse_mean"), sum / 2.0, 1e-5 * sum);
        // Different seeds make different path-traced images, so the repeats spread.
        if (summary.rows[i].at("pipeline") == "reference") {
            EXPECT_GT(summary.number(i, "relmse_std"), 0.0);
        }
    }

    // The plot, drawn by gnuplot from the summary with the script kept next to it.
    EXPECT_TRUE(fs::exists(out + "/error_vs_time.gp"));
    if (gnuplotInstalled()) {
        const Image plot = readImage(out + "/error_vs_time.png");
        EXPECT_EQ(plot.width(), 900);
        EXPECT_EQ(plot.height(), 600);
    } else {
        EXPECT_TRUE(contains(r.output, "gnuplot is not installed")) << r.output;
        EXPECT_FALSE(fs::exists(out + "/error_vs_time.png"));
    }
    for (const auto& entry : fs::directory_iterator(out))
        EXPECT_FALSE(contains(entry.path().filename().string(), ".tmp-")) << entry.path();
}

// --keep-images writes every run's image, the one the row measured: its metrics, recomputed as
// `penumbra diff` does, are the row's (to the CSV's 6 significant digits), and it carries the
// run's seed and spp in its metadata.
TEST_F(BenchCli, KeepImagesWritesTheImageEachRowMeasured) {
    const std::string out = file("kept");
    const CliResult r =
        bench("--pipelines reference,radiosity --spp 1,2 --keep-images --reference " +
              file("box-reference.exr") + " -o " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    const Image reference = readImage(file("box-reference.exr"));
    const Csv results = readCsv(out + "/results.csv");
    ASSERT_EQ(results.rows.size(), 4u);
    for (size_t i = 0; i < results.rows.size(); ++i) {
        const std::string name = results.rows[i].at("pipeline") + "-" +
                                 results.rows[i].at("budget") + "spp-r" +
                                 results.rows[i].at("repeat") + ".exr";
        ImageMetadata metadata;
        const Image kept = readImage(out + "/images/" + name, &metadata);
        const MetricReport report = computeMetrics(kept, reference, nullptr, MetricOptions{});
        const double relMse = report.rows[size_t(report.rowIndex("luminance"))][Metric::RelMse];
        EXPECT_NEAR(relMse, results.number(i, "relmse"), 1e-5 * relMse) << name;
        EXPECT_EQ(std::get<int>(*metadata.find("penumbra:seed")), results.number(i, "seed"))
            << name;
        EXPECT_EQ(std::get<int>(*metadata.find("penumbra:spp")), results.number(i, "spp")) << name;
    }
    EXPECT_EQ(std::distance(fs::directory_iterator(out + "/images"), fs::directory_iterator()), 4);
}

// The expected relMSE of an unbiased estimate against a converged reference falls as 1/spp
// (docs/testing.md, "Setting a threshold from the sample count"): from 1 to 16 samples per pixel
// the ratio is 1/16, accepted within a factor of 4 either way (measured: 0.039 at seed 0, where
// the bright light's pixels fall a little faster than 1/spp). The path tracer is unbiased, as the
// reference is: at 64 spp the whole image's mean bias per channel is noise (measured within
// 0.02 %; 0.5 % allowed, the 1/sqrt(spp) scale of 16 spp's 0.16 %). Its relMSE crosses 0.01
// between 16 and 64 spp (measured 0.039 and 0.0083): time_to_error.csv interpolates the time
// there on the log-log line through those two runs, and says that 0.001 was not reached.
TEST(BenchCliCornell, RelMseOfTheReferencePipelineFallsAsOneOverSpp) {
    const TempDir dir("bench-cornell");
    const CliResult r =
        runPenumbra("bench " + kCornellBox + " --pipelines reference --spp 1,16,64 --threads 2 " +
                    "--reference " + kCornellReference + " -q -o " + dir.file("out"));
    ASSERT_EQ(r.status, 0) << r.output;
    const Csv results = readCsv(dir.file("out/results.csv"));
    ASSERT_EQ(results.rows.size(), 3u);
    for (const char* channel : {"mean_bias_r", "mean_bias_g", "mean_bias_b"})
        EXPECT_NEAR(results.number(2, channel), 0.0, 0.005) << channel;
    const Csv times = readCsv(dir.file("out/time_to_error.csv"));
    ASSERT_EQ(times.rows.size(), 2u);
    EXPECT_EQ(times.number(0, "relmse_target"), 0.01);
    ASSERT_GT(results.number(1, "relmse"), 0.01);
    ASSERT_LT(results.number(2, "relmse"), 0.01);
    EXPECT_EQ(times.rows[0].at("how"), "interpolated");
    const double f = std::log(0.01 / results.number(1, "relmse")) /
                     std::log(results.number(2, "relmse") / results.number(1, "relmse"));
    const double expected =
        results.number(1, "seconds") *
        std::pow(results.number(2, "seconds") / results.number(1, "seconds"), f);
    EXPECT_NEAR(times.number(0, "seconds"), expected, 1e-4 * expected);
    EXPECT_GT(times.number(0, "seconds"), results.number(1, "seconds"));
    EXPECT_LT(times.number(0, "seconds"), results.number(2, "seconds"));
    EXPECT_EQ(times.number(1, "relmse_target"), 0.001);
    EXPECT_EQ(times.rows[1].at("how"), "not reached");
    // The stored reference is 128 x 128: the runs take its size.
    EXPECT_EQ(results.number(0, "spp"), 1.0);
    EXPECT_EQ(results.number(1, "spp"), 16.0);
    const double ratio = results.number(1, "relmse") / results.number(0, "relmse");
    EXPECT_GT(ratio, 1.0 / 64.0);
    EXPECT_LT(ratio, 1.0 / 4.0);
    EXPECT_LT(results.number(1, "rmse"), results.number(0, "rmse"));
    EXPECT_GT(results.number(1, "ssim"), results.number(0, "ssim"));
    const Image reference = readImage(kCornellReference);
    EXPECT_FALSE(fs::exists(dir.file("out/reference.exr")));  // the given one is used
    EXPECT_EQ(reference.width(), 128);
}

// A time budget ends every pipeline, the radiosity view's too, which does not watch the time
// limit itself: without the bench holding it, its 2^24-sample target would run for hours.
TEST_F(BenchCli, TimeBudgetsEndEveryPipeline) {
    const std::string out = file("time");
    const CliResult r = bench("--pipelines reference,radiosity --budgets 0.3 --reference " +
                              file("box-reference.exr") + " -o " + out);
    ASSERT_EQ(r.status, 0) << r.output;
    const Csv results = readCsv(out + "/results.csv");
    ASSERT_EQ(results.rows.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(results.rows[i].at("budget_unit"), "s");
        EXPECT_GE(results.number(i, "spp"), 1.0);
        // Generous: the machine is shared, and a step may overrun by one sample pass.
        EXPECT_LT(results.number(i, "seconds"), 0.3 + 5.0);
    }
    // 16 x 16 pixels take well under a millisecond per sample pass: many fit in 0.3 s.
    EXPECT_GT(results.number(0, "spp"), 8.0);
}

// Ctrl-C during the third run: the benchmark ends at once with status 130, keeping the two
// finished rows whole, their summary and the plot.
TEST_F(BenchCli, CtrlCStopsAndKeepsTheFinishedRuns) {
    const std::string out = file("interrupted");
    fs::create_directories(out);
    const std::string binary = std::string(PENUMBRA_BINARY_DIR) + "/bin/penumbra";
    const std::string reference = file("box-reference.exr");
    const std::string scene = file("box.gltf");
    std::vector<std::string> args = {binary,      "bench",     scene,        "--pipelines",
                                     "reference", "--budgets", "0.2,0.3,60", "--reference",
                                     reference,   "--threads", "2",          "-o",
                                     out};
    std::vector<char*> argv;
    for (std::string& arg : args)
        argv.push_back(arg.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const std::string log = file("interrupted.log");
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_t pid = 0;
    ASSERT_EQ(posix_spawn(&pid, binary.c_str(), &actions, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&actions);

    // Wait for the header and two rows, then let the 60 s run start.
    const auto start = std::chrono::steady_clock::now();
    while (lineCount(out + "/results.csv") < 3 &&
           std::chrono::steady_clock::now() - start < std::chrono::seconds(60))
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ASSERT_EQ(kill(pid, SIGINT), 0);
    const auto interrupted = std::chrono::steady_clock::now();
    int status = 0;
    while (waitpid(pid, &status, WNOHANG) == 0) {
        if (std::chrono::steady_clock::now() - interrupted > std::chrono::seconds(20)) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            FAIL() << "penumbra bench did not stop within 20 s of SIGINT";
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    std::ifstream logFile(log);
    const std::string output((std::istreambuf_iterator<char>(logFile)),
                             std::istreambuf_iterator<char>());
    EXPECT_TRUE(contains(output, "interrupted after 2 of 3 runs")) << output;

    const Csv results = readCsv(out + "/results.csv");
    ASSERT_EQ(results.rows.size(), 2u);
    for (size_t i = 0; i < 2; ++i)
        EXPECT_EQ(results.fieldCounts[i], results.header.size());
    EXPECT_EQ(results.number(0, "budget"), 0.2);
    EXPECT_EQ(results.number(1, "budget"), 0.3);
    EXPECT_EQ(readCsv(out + "/summary.csv").rows.size(), 2u);
    if (gnuplotInstalled()) {
        EXPECT_TRUE(fs::exists(out + "/error_vs_time.png"));
    }
}

// Bad options: exit 2, a message naming the problem, and no output folder or file.
TEST_F(BenchCli, RefusesBadOptionsWithNothingWritten) {
    Image small(8, 8, {"R", "G", "B"});
    writeImage(file("small.exr"), small, {}, {}, ToneMapping{});
    std::ofstream(file("blocker")) << "a file, not a folder\n";
    struct Case {
        std::string arguments, message;
    };
    const std::vector<Case> cases = {
        {"--pipelines reference,nosuch --spp 1", "--pipelines: unknown pipeline 'nosuch'; valid: "},
        {"--budgets 1,abc", "--budgets: \"abc\" is not a number"},
        {"--budgets 0", "--budgets: \"0\" is not a positive number of seconds"},
        {"--spp 1.5", "--spp: \"1.5\" is not a whole number of samples"},
        {"--pipelines reference", "give exactly one of --budgets (seconds) and --spp"},
        {"--budgets 1 --spp 1", "give exactly one of --budgets (seconds) and --spp"},
        {"--spp 1 --width 16 --height 16 --reference " + file("small.exr"),
         "the reference is 8x8 but the benchmark renders 16x16"},
        {"--spp 1 --reference " + file("missing.exr"), "missing.exr"},
    };
    for (const Case& c : cases) {
        const std::string out = file("refused");
        const CliResult r = bench(c.arguments + " -o " + out);
        EXPECT_EQ(r.status, 2) << c.arguments << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, c.message)) << c.arguments << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.arguments;
    }
    // An output that cannot be a folder.
    CliResult r = bench("--spp 1 -o " + file("blocker"));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "exists and is not a folder")) << r.output;
    r = bench("--spp 1 -o " + file("blocker") + "/results");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_TRUE(contains(r.output, "cannot create the folder")) << r.output;
    EXPECT_TRUE(fs::is_regular_file(file("blocker")));
}

}  // namespace
}  // namespace penumbra::test
