// Scenes built to break renderers: the Cornell box moved 100 km from the origin, shrunk to a
// 0.56 mm box, and moved and rotated. The loader rebases the world on the geometry's centre in
// double precision and radiance does not depend on scale, so each must render like the original.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <iostream>
#include <string>

namespace penumbra::test {
namespace {

using nlohmann::json;

const std::string kCornellBox =
    std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.gltf";

constexpr int kSize = 64, kBlock = 8, kSpp = 32;

json readJson(const std::string& path) {
    std::ifstream in(path);
    return json::parse(in);
}

// The Cornell box with the roots of its scene moved under one new root node that carries
// `transform` (glTF node properties: translation, rotation, scale). The buffer is a data URI, so
// the file stays self-contained wherever it is written.
json transformedCornellBox(const json& transform) {
    json gltf = readJson(kCornellBox);
    json& scene = gltf["scenes"][gltf.value("scene", 0)];
    json root = transform;
    root["name"] = "robustness_root";
    root["children"] = scene["nodes"];
    gltf["nodes"].push_back(root);
    scene["nodes"] = json::array({gltf["nodes"].size() - 1});
    return gltf;
}

// Renders `gltf` at 64 x 64, 32 spp, seed 7; checks that no sample was dropped as NaN or
// infinite and that every pixel is finite.
Image render(const json& gltf, const TempDir& dir, const std::string& name) {
    const std::string scene = dir.file(name + ".gltf"), image = dir.file(name + ".exr");
    std::ofstream(scene) << gltf.dump();
    const CliResult result = runPenumbra(
        "render " + scene + " -o " + image + " --width " + std::to_string(kSize) + " --height " +
        std::to_string(kSize) + " --spp " + std::to_string(kSpp) + " --seed 7 --quiet");
    EXPECT_EQ(result.status, 0) << result.output;
    ImageMetadata metadata;
    Image out = readImage(image, &metadata);
    // The tracer drops non-finite samples before the film and counts them.
    const ImageMetadata::Value* dropped = metadata.find("penumbra:path.dropped_samples");
    EXPECT_TRUE(dropped && std::holds_alternative<std::string>(*dropped) &&
                std::get<std::string>(*dropped) == "0")
        << name << ": samples dropped as NaN or infinite";
    size_t nonFinite = 0;
    for (const float v : out.pixels())
        nonFinite += std::isfinite(v) ? 0 : 1;
    EXPECT_EQ(nonFinite, 0u) << name;
    return out;
}

double luminance(const Image& image, int x, int y) {
    return 0.2126 * image.at(x, y, 0) + 0.7152 * image.at(x, y, 1) + 0.0722 * image.at(x, y, 2);
}

// Luminance differences image - original over the 8 x 8 block (bx, by): their mean and standard
// deviation.
struct BlockDifference {
    double mean = 0.0, sd = 0.0, originalMean = 0.0;
};

BlockDifference blockDifference(const Image& image, const Image& original, int bx, int by) {
    double sum = 0.0, sumSquares = 0.0, originalSum = 0.0;
    for (int y = by * kBlock; y < (by + 1) * kBlock; ++y) {
        for (int x = bx * kBlock; x < (bx + 1) * kBlock; ++x) {
            const double d = luminance(image, x, y) - luminance(original, x, y);
            sum += d;
            sumSquares += d * d;
            originalSum += luminance(original, x, y);
        }
    }
    constexpr int n = kBlock * kBlock;
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, (sumSquares - n * mean * mean) / (n - 1))),
            originalSum / n};
}

double imageMean(const Image& image) {
    double sum = 0.0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x)
            sum += luminance(image, x, y);
    }
    return sum / (kSize * kSize);
}

// Compares `image` with the original render. The luminance means agree within 1 %. Each 8 x 8
// block mean agrees with the original's within what the pixel noise explains: a paired test on
// the 64 pixel differences of the block, |mean| <= t sd / 8, plus 1e-4 of the block's level for
// float rounding. t = 4.7 is the Student quantile (63 degrees of freedom, Cornish-Fisher
// expansion) for a two-sided Sidak-corrected false-alarm rate of 1e-3 over the 64 blocks. When
// the paths are the same as the original's (a pure translation or scale: same shading frames,
// same samples) the differences are only rounding, sd ~ 0 and the bound is 1e-4 of the block;
// when they decorrelate (a rotation turns the shading frames, so the BSDF samples go elsewhere)
// it is the block's own noise. A light leak into a dark corner or a lost shadow shifts the whole
// block one way and fails once it exceeds 4.7 standard errors. Prints the measured differences.
void expectSameImage(const Image& image, const Image& original, const std::string& name) {
    ASSERT_EQ(image.width(), original.width());
    ASSERT_EQ(image.height(), original.height());
    const double mean = imageMean(image), reference = imageMean(original);
    EXPECT_NEAR(mean, reference, 0.01 * reference) << name;
    constexpr double kT = 4.7, kRounding = 1e-4;
    double largestRelative = 0.0, largestZ = 0.0;
    for (int by = 0; by < kSize / kBlock; ++by) {
        for (int bx = 0; bx < kSize / kBlock; ++bx) {
            const BlockDifference d = blockDifference(image, original, bx, by);
            const double level = std::max(d.originalMean, 1e-3 * reference);
            const double standardError = d.sd / kBlock;
            EXPECT_LE(std::abs(d.mean), kT * standardError + kRounding * level)
                << name << ": block " << bx << "," << by << ": mean " << d.originalMean + d.mean
                << " vs " << d.originalMean << ", standard error of the difference "
                << standardError;
            largestRelative = std::max(largestRelative, std::abs(d.mean) / reference);
            if (standardError > 0.0)
                largestZ = std::max(largestZ, std::abs(d.mean) / standardError);
        }
    }
    std::cout << name << ": image mean " << mean << " vs " << reference << " ("
              << 100.0 * (mean - reference) / reference << " %); largest block difference "
              << 100.0 * largestRelative << " % of the image mean, largest z " << largestZ << "\n";
}

class Robustness : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        dir_ = new TempDir("robustness");
        original_ = new Image(render(readJson(kCornellBox), *dir_, "original"));
    }
    static void TearDownTestSuite() {
        delete original_;
        delete dir_;
    }

    static TempDir* dir_;
    static Image* original_;
};

TempDir* Robustness::dir_ = nullptr;
Image* Robustness::original_ = nullptr;

TEST_F(Robustness, FarFromTheOrigin) {
    const json gltf = transformedCornellBox({{"translation", {1e5, 1e5, 1e5}}});
    expectSameImage(render(gltf, *dir_, "far"), *original_, "translated by 1e5 m");
}

TEST_F(Robustness, MillimetreScale) {
    json gltf = transformedCornellBox({{"scale", {1e-3, 1e-3, 1e-3}}});
    // "The view matrix is derived from the global transform of the node containing the camera
    // with the scaling ignored" (glTF 2.0, 3.10.2): znear is not scaled with the node, so a
    // millimetre-scale asset must say znear in millimetres too, or the whole box (1.4 mm from
    // the camera) lies before the 10 mm near plane.
    for (json& camera : gltf["cameras"])
        camera["perspective"]["znear"] = camera["perspective"]["znear"].get<double>() * 1e-3;
    expectSameImage(render(gltf, *dir_, "small"), *original_, "scaled by 1e-3");
}

TEST_F(Robustness, FarFromTheOriginAndRotated) {
    // 40 degrees about the normalised axis (1, 2, 3): no face stays axis-aligned.
    const double half = 0.5 * 40.0 * M_PI / 180.0, norm = std::sqrt(14.0);
    const json rotation = {std::sin(half) * 1 / norm, std::sin(half) * 2 / norm,
                           std::sin(half) * 3 / norm, std::cos(half)};
    const json gltf =
        transformedCornellBox({{"translation", {1e5, 1e5, 1e5}}, {"rotation", rotation}});
    expectSameImage(render(gltf, *dir_, "far-rotated"), *original_, "translated and rotated");
}

}  // namespace
}  // namespace penumbra::test
