// Image regressions: each regression scene is rendered through the command line at a low spp
// with a fixed seed and compared with its stored converged reference and per-pixel variance
// image (made on purpose by scripts/update-references) by the noise-aware comparison of
// tests/image_compare.h. How the thresholds were chosen: docs/testing.md.
//
// A failing comparison writes the test render and a false-colour map of |test - ref| / ref to
// <build>/regression-failures/ and prints their paths. The other tests prove that the
// comparison fails for real regressions of 3 %.
#include "core/image_io.h"
#include "tests/cli_runner.h"
#include "tests/image_compare.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <variant>

namespace penumbra::test {
namespace {

// The test render's settings must match scripts/update-references, which records the spp in the
// variance image; the test checks it. The seed differs from the reference's (1000) and from
// those of the variance renders (2000 and up), so the three are independent.
struct RegressionScene {
    std::string name;  // folder under scenes/, holding NAME.gltf, reference.exr, variance.exr
    int width = 128, height = 128, spp = 64;
};
constexpr int kTestSeed = 1;
const RegressionScene kCornellBox{"cornell-box"};

// The relative MSE may reach this multiple of its expected value before the render counts as
// too noisy (docs/testing.md: over 80 seeds its mean was 1.00 times the expectation, its standard
// deviation 0.028 times, its largest value 1.07 times).
constexpr double kRelativeMseFactor = 1.3;

std::string sceneFolder(const RegressionScene& scene) {
    return std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + scene.name;
}

std::string sceneGltf(const RegressionScene& scene) {
    return sceneFolder(scene) + "/" + scene.name + ".gltf";
}

int intAttribute(const ImageMetadata& metadata, const std::string& key) {
    const ImageMetadata::Value* value = metadata.find(key);
    return value && std::holds_alternative<int>(*value) ? std::get<int>(*value) : 0;
}

// Expected relative MSE of a correct test render: the mean over pixels and channels of its
// variance (its noise, plus the reference's) over r^2 + eps, with eps as in compareImages().
double expectedRelativeMse(const Image& reference, const Image& variance,
                           const ImageCompareOptions& options) {
    double referenceSum = 0.0;
    for (const float r : reference.pixels())
        referenceSum += r;
    const size_t count = reference.pixels().size();
    const double floor = options.relMseFloor * referenceSum / double(count);
    double sum = 0.0;
    for (size_t i = 0; i < count; ++i) {
        const double r = reference.pixels()[i];
        sum += std::max(0.0f, variance.pixels()[i]) / (r * r + floor * floor);
    }
    return sum / double(count) * (1.0 + options.referenceVarianceRatio);
}

// The stored reference and variance image of a scene, and the comparison options they imply.
struct StoredReference {
    Image reference, variance;
    ImageCompareOptions options;
};

StoredReference loadReference(const RegressionScene& scene) {
    StoredReference stored;
    ImageMetadata referenceMetadata, varianceMetadata;
    stored.reference = readImage(sceneFolder(scene) + "/reference.exr", &referenceMetadata);
    stored.variance = readImage(sceneFolder(scene) + "/variance.exr", &varianceMetadata);
    // A variance image measured at another spp or size describes another test: regenerate.
    EXPECT_EQ(intAttribute(varianceMetadata, "penumbra:spp"), scene.spp)
        << scene.name << "/variance.exr was made for another spp: run scripts/update-references";
    EXPECT_EQ(stored.variance.width(), scene.width) << "run scripts/update-references";
    EXPECT_EQ(stored.variance.height(), scene.height) << "run scripts/update-references";
    const int referenceSpp = intAttribute(referenceMetadata, "penumbra:spp");
    EXPECT_GT(referenceSpp, 0) << scene.name << "/reference.exr has no penumbra:spp";
    stored.options.referenceVarianceRatio = double(scene.spp) / std::max(referenceSpp, 1);
    stored.options.maxRelativeMse =
        kRelativeMseFactor * expectedRelativeMse(stored.reference, stored.variance, stored.options);
    return stored;
}

// Renders `gltf` as the regression test of `scene` does.
Image renderTestImage(const RegressionScene& scene, const std::string& gltf, const TempDir& dir) {
    const std::string output = dir.file("test.exr");
    const CliResult result =
        runPenumbra("render " + gltf + " -o " + output + " --quiet --width " +
                    std::to_string(scene.width) + " --height " + std::to_string(scene.height) +
                    " --spp " + std::to_string(scene.spp) + " --seed " + std::to_string(kTestSeed));
    EXPECT_EQ(result.status, 0) << result.output;
    return readImage(output);
}

ImageCompareResult compare(const Image& test, const StoredReference& stored) {
    return compareImages(test, stored.reference, stored.variance, stored.options);
}

// Writes the test render and the difference heat map for a failed comparison; prints the paths.
void writeFailureImages(const RegressionScene& scene, const Image& test, const Image& reference) {
    const std::string folder = std::string(PENUMBRA_BINARY_DIR) + "/regression-failures";
    std::filesystem::create_directories(folder);
    const std::string testPath = folder + "/" + scene.name + "-test.exr";
    const std::string mapPath = folder + "/" + scene.name + "-difference.png";
    writeImage(testPath, test, {}, {}, {});
    // Full scale (red) at a relative difference of 1; a correct 64-spp render is mostly blue.
    writeImage(mapPath, relativeDifferenceHeatMap(test, reference, 1.0), {}, {}, {});
    std::cout << "regression failure images:\n  " << testPath << "\n  " << mapPath << "\n";
}

void expectMatchesReference(const RegressionScene& scene) {
    const StoredReference stored = loadReference(scene);
    TempDir dir("regression-" + scene.name);
    const Image test = renderTestImage(scene, sceneGltf(scene), dir);
    const ImageCompareResult result = compare(test, stored);
    std::cout << scene.name << ": " << result.summary() << "\n";
    if (!result.passed)
        writeFailureImages(scene, test, stored.reference);
    EXPECT_TRUE(result.passed) << result.reason;
}

TEST(Regression, CornellBoxMatchesReference) {
    expectMatchesReference(kCornellBox);
}

// The same comparison must fail for a render 3 % too bright or too dark everywhere, e.g. a light
// unit or a BSDF normalisation slightly off.
TEST(Regression, ComparisonCatchesThreePercentScale) {
    const StoredReference stored = loadReference(kCornellBox);
    TempDir dir("regression-scale");
    const Image test = renderTestImage(kCornellBox, sceneGltf(kCornellBox), dir);
    for (const float scale : {1.03f, 0.97f}) {
        Image perturbed = test;
        for (float& value : perturbed.pixels())
            value *= scale;
        const ImageCompareResult result = compare(perturbed, stored);
        EXPECT_FALSE(result.passed) << "scale " << scale << ": " << result.summary();
        std::cout << "scaled by " << scale << ": " << result.summary() << "\n";
    }
}

// ... and for a local change: the red wall's albedo 3 % lower, in a modified copy of the scene.
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
    const Image test = renderTestImage(kCornellBox, dir.file("scene.gltf"), dir);
    const ImageCompareResult result = compare(test, stored);
    EXPECT_FALSE(result.passed) << result.summary();
    std::cout << "red wall albedo x 0.97: " << result.summary() << "\n" << result.reason << "\n";
}

// ... and for a render as unbiased as before but noisier: every pixel's deviation from the
// reference 1.5 times larger (2.25 times the variance), e.g. a sampling strategy lost.
TEST(Regression, ComparisonCatchesExtraNoise) {
    const StoredReference stored = loadReference(kCornellBox);
    TempDir dir("regression-noise");
    const Image test = renderTestImage(kCornellBox, sceneGltf(kCornellBox), dir);
    Image noisier = test;
    for (size_t i = 0; i < noisier.pixels().size(); ++i) {
        const float r = stored.reference.pixels()[i];
        noisier.pixels()[i] = r + 1.5f * (test.pixels()[i] - r);
    }
    const ImageCompareResult result = compare(noisier, stored);
    EXPECT_GT(result.relativeMse, result.maxRelativeMse) << result.summary();
    std::cout << "noise x 1.5: " << result.summary() << "\n";
}

}  // namespace
}  // namespace penumbra::test
