// Image regressions: each regression scene is rendered through the command line at a low spp
// with a fixed seed and gated by `penumbra diff --fail-above relmse=T` against its stored
// converged reference (made on purpose by scripts/update-references), with T chosen from the
// stored per-pixel variance image by the rule of docs/testing.md. Two diff gates per scene:
// the pixels (too much noise: fireflies, a lost strategy) and K x K block means (a bias: the
// noise falls by K^2, a bias does not). The multi-scale block z-tests of
// tests/support/image_compare.h run as well: they locate a local bias that the whole-image relMSE
// dilutes.
//
// A failing scene leaves its test render and the diff heat maps in
// <build>/regression-failures/ and prints their paths. Other tests prove that the gates fail
// for a render 3 % too bright or too dark, a 3 % change of one wall's albedo and extra noise.
// Each entry is a scene through a pipeline preset: the path tracer, or whitted, distribution
// and hybrid, each against a reference of its own pipeline (they are biased by design).
// The radiosity pipeline is deterministic: its regression is a near-exact comparison.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/image_compare.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <tuple>
#include <variant>
#include <vector>

namespace penumbra::test {
namespace {

// The test render's settings must match scripts/update-references, which records the spp in the
// variance image; the test checks it. The seed differs from the reference's (1000) and from
// those of the variance renders (2000 and up), so the three are independent.
struct RegressionScene {
    std::string name;  // folder under scenes/, holding NAME.gltf, reference.exr, variance.exr
    // The pipeline preset (render --pipeline) whose output is gated; "reference" (the path
    // tracer) uses reference.exr and variance.exr, another PIPELINE-reference.exr and
    // PIPELINE-variance.exr, references of that pipeline (it is biased by design: the test
    // checks that its output does not change).
    std::string pipeline = "reference";
    int width = 128, height = 128, spp = 64;
    // K of the bias gate: 16 x 16 blocks, 8 x 8 of them at 128 x 128. Their noise is 256 times
    // smaller than a pixel's while a 3 % bias stays (docs/testing.md).
    int blockSize = 16;
    // Widening of the z-tests' noise standard error (ImageCompareOptions::tailAllowance): 1.5
    // was measured on the Cornell box; scenes whose channels are carried by rarer paths
    // (glossy and specular caustics) have heavier tails and need more (docs/testing.md).
    double tailAllowance = 1.5;
    // Smallest threshold of the pixel and block gates, as multiples of the expected relMSE m:
    // T = max(m + 6 sd, factor x m). The sd computed for normal noise describes the Cornell box
    // (measured over 12 seeds: 2 % of m for the pixels, 15 % for the blocks); where fireflies
    // make the tail heavier, the factor is 1 + 6 x the standard deviation measured over seeds,
    // relative to m (docs/testing.md).
    double pixelsFactor = 1.3, blocksFactor = 1.3;
};
// Fields in order: name, pipeline, width, height, spp, blockSize, tailAllowance, pixelsFactor,
// blocksFactor.
const RegressionScene kCornellBox{"cornell-box"};
// Measured over 10 seeds: sd 9 % of m for the pixels, 30 % for the blocks.
const RegressionScene kGlossy{"glossy", "reference", 128, 128, 64, 16, 2.0, 1.6, 2.8};
// Caustics seen through diffuse surfaces are rare paths for a path tracer: their noise has a
// heavy tail, so this scene renders 128 spp and its bias gate compares 64 x 64 block means (the
// four quadrants): at 16 x 16 the noise of the blocks in the caustic alone is as large as a 3 %
// bias (docs/testing.md).
// Measured over 8 seeds: sd 8 % of m for the pixels, 24 % for the blocks.
const RegressionScene kCausticSpheres{
    "caustic-spheres", "reference", 128, 128, 128, 64, 2.0, 1.6, 2.5};
// The pipeline presets other than the path tracer, each on a scene where what it counts
// matters (docs/light-paths.md), at 64 x 64 to keep the test and the references small; their
// references are the mean of the variance renders (scripts/update-references).
// Whitted: mirror and glass recursion, direct light at the diffuse vertex. The light seen
// through the glass sphere is a rare, very bright hit: at 64 spp one seed in five had a block
// 9 times its expected relMSE (as much as a 3 % bias), so the test renders 256 spp (0.5 s).
// The tail stays heavy (seeds 1-7: pixels 0.46 to 6.8 x m, sd 226 % of m; blocks 0.35 to
// 3.6 x m, sd 112 %), hence the factors 1 + 6 sd / m; a 3 % bias still gives the blocks 35 to
// 48 x m.
const RegressionScene kWhitted{"caustic-spheres", "whitted", 64, 64, 256, 16, 3.0, 15.0, 8.0};
// Distribution: direct light plus the radiosity solution's indirect light as the ambient term.
// Measured over seeds 2-7: sd 9 % of m for the pixels, 50 % for the blocks.
const RegressionScene kDistribution{"cornell-box", "distribution", 64, 64, 64, 16, 2.0, 1.6, 4.0};
// Hybrid preview: radiosity reuse as it is, the caustic photon map (its photons change with the
// seed) and path tracing. Its bias gate compares 32 x 32 blocks (the quadrants): with 16 x 16
// ones a 3 % bias raised the block relMSE to 2.8-4.1 x m over seeds 1-7, around the threshold
// m + 6 sd = 3.7 m. Measured over seeds 1-7: sd 9 % of m for the pixels, 39 % for the 32 x 32
// blocks. The hybrid itself is not an entry: its correction is reconstructed by a filter
// (raytrace/correction_filter.h), so its pixels' noise is correlated over a few pixels and a
// block's variance is not the sum of its pixels' that the gates assume (its block relMSE was
// 2.0 to 4.1 x that m over seeds 1-5). It converges to the path tracer, and is checked against
// the path tracer's references instead (tests/passes/hybrid_cornell_test.cpp,
// caustic_scene_test.cpp, hybrid_glossy_test.cpp).
const RegressionScene kHybridPreview{
    "caustic-spheres", "hybrid-preview", 64, 64, 32, 32, 2.0, 1.6, 2.5};

// The test's seed: 1, or PENUMBRA_REGRESSION_SEED to check the thresholds with other seeds
// (docs/testing.md, "Adding a regression scene").
int testSeed() {
    const char* seed = std::getenv("PENUMBRA_REGRESSION_SEED");
    return seed ? std::atoi(seed) : 1;
}

// The gates' thresholds from the expected relMSE m and its standard deviation sd under normal
// noise (expectedRelativeMse()): T = max(m + kSigmas sd, factor m), the factor per scene.
// docs/testing.md gives the measurements: over many seeds no correct render came near T.
constexpr double kSigmas = 6.0;

std::string sceneFolder(const std::string& name) {
    return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name;
}

std::string sceneGltf(const RegressionScene& scene) {
    return sceneFolder(scene.name) + "/" + scene.name + ".gltf";
}

// The stored file `kind` ("reference.exr", "variance.exr") of the scene's pipeline.
std::string storedFile(const RegressionScene& scene, const std::string& kind) {
    const std::string prefix = scene.pipeline == "reference" ? "" : scene.pipeline + "-";
    return sceneFolder(scene.name) + "/" + prefix + kind;
}

// The entry's name in messages and failure files: the scene, then a pipeline other than the
// path tracer.
std::string entryName(const RegressionScene& scene) {
    return scene.pipeline == "reference" ? scene.name : scene.name + "-" + scene.pipeline;
}

std::string failureFolder() {
    return std::string(PENUMBRA_BINARY_DIR) + "/regression-failures";
}

int intAttribute(const ImageMetadata& metadata, const std::string& key) {
    const ImageMetadata::Value* value = metadata.find(key);
    return value && std::holds_alternative<int>(*value) ? std::get<int>(*value) : 0;
}

// The beauty (R, G, B) of an image whose other channels are a pipeline's pass layers (hybrid:
// caustics.*, path.*): the gates compare the beauty, as `penumbra diff` does by default. A
// layer's own noise is not what the regression is about, and the caustic layer's variance, from
// few renders, is zero in pixels that a rare photon reaches (a z of 29 for one such photon).
Image beauty(const Image& image) {
    if (image.channels() == 3)
        return image;
    Image rgb(image.width(), image.height(), {"R", "G", "B"});
    for (int c = 0; c < 3; ++c) {
        const int from = image.channelIndex(rgb.channelNames()[c]);
        EXPECT_GE(from, 0) << "no channel " << rgb.channelNames()[c];
        for (int y = 0; y < image.height() && from >= 0; ++y)
            for (int x = 0; x < image.width(); ++x)
                rgb.at(x, y, c) = image.at(x, y, from);
    }
    return rgb;
}

// One `penumbra diff` gate: relMSE with eps `epsilon`, of pixels (downsample 1) or block means.
struct DiffGate {
    std::string name;  // "pixels" or "blocks": in file names and messages
    int downsample = 1;
    double epsilon = 0.01;
    double expected = 0.0;   // relMSE expected of a correct render (0: not known)
    double threshold = 0.0;  // --fail-above relmse=threshold
};

struct GateResult {
    int status = -1;  // penumbra diff's exit status: 0 pass, 1 fail, 2 bad input
    double relativeMse = 0.0;
    std::string command;  // the diff command, to repeat it by hand
    std::string output;
};

// Runs `penumbra diff TEST REFERENCE` with the gate's options; a heat map path may be empty.
GateResult runGate(const DiffGate& gate, const std::string& test, const std::string& reference,
                   const std::string& heatmap) {
    char options[200];
    std::snprintf(options, sizeof options,
                  " --metric relmse --downsample %d --epsilon %.9g --fail-above relmse=%.9g",
                  gate.downsample, gate.epsilon, gate.threshold);
    GateResult result;
    result.command = "penumbra diff " + test + " " + reference + options;
    const CliResult run = runPenumbra("diff " + test + " " + reference + options + " --json" +
                                      (heatmap.empty() ? "" : " --heatmap " + heatmap));
    result.status = run.status;
    result.output = run.output;
    // Standard error (the FAIL lines, unbuffered) comes first, then the JSON object.
    const size_t begin = run.output.find('{'), end = run.output.rfind('}');
    if (begin != std::string::npos && end != std::string::npos && end > begin) {
        const nlohmann::json json =
            nlohmann::json::parse(run.output.substr(begin, end - begin + 1), nullptr, false);
        const nlohmann::json::json_pointer relmse("/metrics/all/relmse");
        if (!json.is_discarded() && json.contains(relmse) && json[relmse].is_number())
            result.relativeMse = json[relmse].get<double>();
    }
    return result;
}

std::string describe(const DiffGate& gate, const GateResult& result) {
    char buffer[200];
    std::snprintf(buffer, sizeof buffer,
                  "diff gate %-6s (K = %2d): relMSE %.4g = %.3f x expected %.4g, threshold %.4g: "
                  "exit %d",
                  gate.name.c_str(), gate.downsample, result.relativeMse,
                  gate.expected > 0.0 ? result.relativeMse / gate.expected : 0.0, gate.expected,
                  gate.threshold, result.status);
    return buffer + ("\n    " + result.command);
}

// The stored reference and variance image of a scene, and the gates and options they imply.
struct StoredReference {
    std::string referencePath;
    Image reference, variance;
    ImageCompareOptions options;
    std::vector<DiffGate> gates;
};

StoredReference loadReference(const RegressionScene& scene) {
    StoredReference stored;
    ImageMetadata referenceMetadata, varianceMetadata;
    stored.referencePath = storedFile(scene, "reference.exr");
    stored.reference = beauty(readImage(stored.referencePath, &referenceMetadata));
    const std::string variancePath = storedFile(scene, "variance.exr");
    stored.variance = beauty(readImage(variancePath, &varianceMetadata));
    // A variance image measured at another spp or size describes another test: regenerate.
    EXPECT_EQ(intAttribute(varianceMetadata, "penumbra:spp"), scene.spp)
        << variancePath << " was made for another spp: run scripts/update-references";
    EXPECT_EQ(stored.variance.width(), scene.width) << "run scripts/update-references";
    EXPECT_EQ(stored.variance.height(), scene.height) << "run scripts/update-references";
    const int referenceSpp = intAttribute(referenceMetadata, "penumbra:spp");
    EXPECT_GT(referenceSpp, 0) << stored.referencePath << " has no penumbra:spp";
    // A reference that is the mean of M renders at the test's spp has 1/M of a test render's
    // variance; a long render has test spp / its spp of it.
    const int meanOfRenders =
        std::max(intAttribute(referenceMetadata, "penumbra:mean_of_renders"), 1);
    stored.options.referenceVarianceRatio =
        double(scene.spp) / (double(std::max(referenceSpp, 1)) * meanOfRenders);
    stored.options.tailAllowance = scene.tailAllowance;

    const double epsilon = relativeMseEpsilon(stored.reference);
    for (const auto& [name, k, factor] :
         {std::tuple<std::string, int, double>{"pixels", 1, scene.pixelsFactor},
          {"blocks", scene.blockSize, scene.blocksFactor}}) {
        const ExpectedRelativeMse expected = expectedRelativeMse(
            stored.reference, stored.variance, stored.options.referenceVarianceRatio, k, epsilon);
        const double threshold =
            std::max(expected.mean + kSigmas * expected.standardDeviation, factor * expected.mean);
        stored.gates.push_back({name, k, epsilon, expected.mean, threshold});
    }
    return stored;
}

// Renders `gltf` as the regression test of `scene` does, to `output`.
Image renderTestImage(const RegressionScene& scene, const std::string& gltf,
                      const std::string& output) {
    const CliResult result = runPenumbra(
        "render " + gltf + " -o " + output + " --pipeline " + scene.pipeline + " --quiet --width " +
        std::to_string(scene.width) + " --height " + std::to_string(scene.height) + " --spp " +
        std::to_string(scene.spp) + " --seed " + std::to_string(testSeed()));
    EXPECT_EQ(result.status, 0) << result.output;
    return beauty(readImage(output));
}

// Runs every gate on the image file `test` and prints the results; with a non-empty
// `heatmapStem`, each gate writes its heat map to heatmapStem-GATE.png.
std::vector<GateResult> runGates(const StoredReference& stored, const std::string& test,
                                 const std::string& heatmapStem = "") {
    std::vector<GateResult> results;
    for (const DiffGate& gate : stored.gates) {
        const std::string heatmap =
            heatmapStem.empty() ? "" : heatmapStem + "-" + gate.name + ".png";
        results.push_back(runGate(gate, test, stored.referencePath, heatmap));
        std::cout << "  " << describe(gate, results.back()) << "\n";
        EXPECT_NE(results.back().status, 2) << results.back().output;
    }
    return results;
}

bool allPassed(const std::vector<GateResult>& results) {
    return std::all_of(results.begin(), results.end(),
                       [](const GateResult& result) { return result.status == 0; });
}

// Writes `image` x scale to `path`.
void writeScaled(const Image& image, float scale, const std::string& path) {
    Image scaled = image;
    for (float& value : scaled.pixels())
        value *= scale;
    writeImage(path, scaled, {}, {}, {});
}

// The regression test of one scene: the diff gates decide; the block z-tests must agree. Then
// the scene's block gate must fail for the same render 3 % brighter: the thresholds leave the
// test the power to see a small bias in this scene's noise.
void expectMatchesReference(const RegressionScene& scene) {
    const StoredReference stored = loadReference(scene);
    std::filesystem::create_directories(failureFolder());
    const std::string stem = failureFolder() + "/" + entryName(scene);
    const std::string testPath = stem + "-test.exr";
    const Image test = renderTestImage(scene, sceneGltf(scene), testPath);
    std::cout << entryName(scene) << " at " << scene.spp << " spp, seed " << testSeed() << ":\n";
    const bool gatesPassed = allPassed(runGates(stored, testPath, stem + "-heatmap"));
    const ImageCompareResult blocks =
        compareImages(test, stored.reference, stored.variance, stored.options);
    std::cout << "  " << blocks.summary() << "\n";
    EXPECT_TRUE(gatesPassed) << "penumbra diff failed the render of " << entryName(scene);
    EXPECT_TRUE(blocks.passed) << blocks.reason;
    const std::vector<std::string> failureFiles = {testPath, stem + "-heatmap-pixels.png",
                                                   stem + "-heatmap-blocks.png"};
    if (gatesPassed && blocks.passed) {
        for (const std::string& file : failureFiles)
            std::filesystem::remove(file);
    } else {
        std::cout << "regression failure images:\n";
        for (const std::string& file : failureFiles)
            std::cout << "  " << file << "\n";
    }

    TempDir dir("regression-" + entryName(scene));
    writeScaled(test, 1.03f, dir.file("scaled.exr"));
    std::cout << "the same x 1.03:\n";
    EXPECT_EQ(runGates(stored, dir.file("scaled.exr")).back().status, 1)
        << "the block gate of " << entryName(scene) << " misses a 3 % bias";
}

TEST(Regression, CornellBoxMatchesReference) {
    expectMatchesReference(kCornellBox);
}

TEST(Regression, GlossyMatchesReference) {
    expectMatchesReference(kGlossy);
}

TEST(Regression, CausticSpheresMatchesReference) {
    expectMatchesReference(kCausticSpheres);
}

TEST(Regression, WhittedPipelineMatchesReference) {
    expectMatchesReference(kWhitted);
}

TEST(Regression, DistributionPipelineMatchesReference) {
    expectMatchesReference(kDistribution);
}

TEST(Regression, HybridPreviewPipelineMatchesReference) {
    expectMatchesReference(kHybridPreview);
}

// The gates must fail for a render 3 % too bright or too dark everywhere, e.g. a light unit or
// a BSDF normalisation slightly off: penumbra diff exits 1 (the block gate catches it), and the
// z-tests agree.
TEST(Regression, DiffGateCatchesThreePercentScale) {
    const StoredReference stored = loadReference(kCornellBox);
    TempDir dir("regression-scale");
    const Image test = renderTestImage(kCornellBox, sceneGltf(kCornellBox), dir.file("test.exr"));
    std::cout << "unscaled:\n";
    ASSERT_TRUE(allPassed(runGates(stored, dir.file("test.exr"))));
    for (const float scale : {1.03f, 0.97f}) {
        writeScaled(test, scale, dir.file("scaled.exr"));
        std::cout << "scaled by " << scale << ":\n";
        EXPECT_EQ(runGates(stored, dir.file("scaled.exr")).back().status, 1);
        const ImageCompareResult z = compareImages(
            readImage(dir.file("scaled.exr")), stored.reference, stored.variance, stored.options);
        EXPECT_FALSE(z.passed) << z.summary();
        std::cout << "  " << z.summary() << "\n";
    }
}

// ... and for a local change: the red wall's albedo 3 % lower, in a modified copy of the scene.
// It moves the whole image's relMSE little (the block gate fails narrowly, at about 2.3 times
// its expectation against a threshold of 2); the block z-tests fail clearly, on the red wall.
TEST(Regression, ComparisonCatchesRedWallAlbedoChange) {
    const StoredReference stored = loadReference(kCornellBox);
    std::ifstream input(sceneGltf(kCornellBox));
    std::stringstream text;
    text << input.rdbuf();
    std::string gltf = text.str();
    // The red paint's baseColorFactor R (scenes/cornell-box/README.md), once in the file.
    const std::string red = "0.523577,";
    const size_t at = gltf.find(red);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(gltf.find(red, at + 1), std::string::npos);
    char darker[32];
    std::snprintf(darker, sizeof darker, "%.6f,", 0.523577 * 0.97);
    gltf.replace(at, red.size(), darker);
    TempDir dir("regression-red-wall");
    std::ofstream(dir.file("scene.gltf")) << gltf;
    const Image test = renderTestImage(kCornellBox, dir.file("scene.gltf"), dir.file("test.exr"));
    std::cout << "red wall albedo x 0.97:\n";
    runGates(stored, dir.file("test.exr"));
    const ImageCompareResult result =
        compareImages(test, stored.reference, stored.variance, stored.options);
    EXPECT_FALSE(result.passed) << result.summary();
    std::cout << "  " << result.summary() << "\n" << result.reason << "\n";
}

// ... and for a render as unbiased as before but noisier: every pixel's deviation from the
// reference 1.5 times larger (2.25 times the variance), e.g. a sampling strategy lost. The pixel
// gate catches it.
TEST(Regression, DiffGateCatchesExtraNoise) {
    const StoredReference stored = loadReference(kCornellBox);
    TempDir dir("regression-noise");
    const Image test = renderTestImage(kCornellBox, sceneGltf(kCornellBox), dir.file("test.exr"));
    Image noisier = test;
    for (size_t i = 0; i < noisier.pixels().size(); ++i) {
        const float r = stored.reference.pixels()[i];
        noisier.pixels()[i] = r + 1.5f * (test.pixels()[i] - r);
    }
    writeImage(dir.file("noisier.exr"), noisier, {}, {}, {});
    const DiffGate& pixels = stored.gates.front();
    const GateResult result = runGate(pixels, dir.file("noisier.exr"), stored.referencePath, "");
    std::cout << "noise x 1.5:\n  " << describe(pixels, result) << "\n";
    EXPECT_EQ(result.status, 1) << result.output;
}

// The radiosity pipeline has no Monte Carlo noise in its solution, and its view's pixel samples
// come from the seed: the same command gives the same image on any thread count. Its regression
// is therefore a near-exact comparison with a stored render (scripts/update-references) whose
// bound covers only the float16 storage and floating-point differences between builds.
struct RadiosityRegression {
    std::string reference = sceneFolder("cornell-box") + "/radiosity-reference.exr";
    std::string arguments = sceneFolder("cornell-box") +
                            "/cornell-box.gltf --pipeline radiosity --quiet --width 128 "
                            "--height 128 --spp 16 --seed 1";
    // relMSE bound: float16 rounds by at most 2^-11 relative (relMSE <= 2.4e-7); 1e-5 (0.3 %
    // RMS) leaves room for a refinement decision that a rounding difference flips, while a
    // 3 % change gives about 9e-4.
    DiffGate gate{"pixels", 1, 0.0, 0.0, 1e-5};
};

TEST(Regression, RadiosityPipelineMatchesReference) {
    RadiosityRegression radiosity;
    radiosity.gate.epsilon = relativeMseEpsilon(readImage(radiosity.reference));
    std::filesystem::create_directories(failureFolder());
    const std::string stem = failureFolder() + "/cornell-box-radiosity";
    const CliResult render =
        runPenumbra("render " + radiosity.arguments + " -o " + stem + "-test.exr");
    ASSERT_EQ(render.status, 0) << render.output;
    const GateResult result =
        runGate(radiosity.gate, stem + "-test.exr", radiosity.reference, stem + "-heatmap.png");
    std::cout << "radiosity: " << describe(radiosity.gate, result) << "\n";
    EXPECT_EQ(result.status, 0) << result.output;
    if (result.status == 0) {
        std::filesystem::remove(stem + "-test.exr");
        std::filesystem::remove(stem + "-heatmap.png");
    } else {
        std::cout << "regression failure images:\n  " << stem << "-test.exr\n  " << stem
                  << "-heatmap.png\n";
    }

    // The gate fails for the same render 3 % brighter.
    TempDir dir("regression-radiosity");
    writeScaled(readImage(radiosity.reference), 1.03f, dir.file("scaled.exr"));
    const GateResult failed =
        runGate(radiosity.gate, dir.file("scaled.exr"), radiosity.reference, "");
    std::cout << "radiosity x 1.03: " << describe(radiosity.gate, failed) << "\n";
    EXPECT_EQ(failed.status, 1) << failed.output;
}

}  // namespace
}  // namespace penumbra::test
