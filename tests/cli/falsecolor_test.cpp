// `penumbra falsecolor`: a render's illuminance layer and luminance in false colour, against the
// closed form of a floor under a point light (E = I / h², L = rho E / pi): the map's colour is the
// legend's at the value's place on the scale; bad input is refused.
#include "core/heatmap.h"
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

namespace penumbra::test {
namespace {

constexpr float kIntensity = 100.0f, kHeight = 2.0f, kRho = 0.5f;
constexpr double kLux = kIntensity / (kHeight * kHeight);  // 25 lux below the light
constexpr int kSize = 8;

// A centimetre of floor below a point light, seen from above (orthographic): uniform to 1e-4.
std::string renderFloor(const TempDir& dir) {
    GltfBuilder scene;
    const int grey = scene.addMaterial({.baseColor = Color(kRho)});
    scene.addQuad({-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, grey);
    scene.addLight({.type = "point", .intensity = kIntensity, .position = {0, kHeight, 0}});
    const Vec4 lookingDown(-std::sqrt(0.5f), 0.0f, 0.0f, std::sqrt(0.5f));
    scene.setOrthographicCamera({0, 5, 0}, lookingDown, 0.005f, 0.005f);
    scene.write(dir.file("scene.gltf"));
    renderImage(dir.file("scene.gltf"), dir.file("floor.exr"),
                "--quiet --width 8 --height 8 --spp 4 --aov illuminance");
    return dir.file("floor.exr");
}

// The picture's map pixel in the middle, and the legend bar's pixel at `fraction` of the scale
// (core/heatmap.h: the bar's columns run from kFalseColourMargin across the picture less the
// margins, its rows from kFalseColourBarTop below the map).
void expectMapAtFraction(const Image& picture, double fraction) {
    const int barWidth = picture.width() - 2 * kFalseColourMargin;
    const int column = kFalseColourMargin + int(std::lround(fraction * (barWidth - 1)));
    const int row = kSize + kFalseColourBarTop + kFalseColourBarHeight / 2;
    for (int c = 0; c < 3; ++c) {
        // 8-bit outputs: one code value for the bar's column rounding.
        EXPECT_NEAR(picture.at(kSize / 2, kSize / 2, c), picture.at(column, row, c), 1.5 / 255)
            << "channel " << c;
    }
}

float metadataFloat(const std::string& path, const std::string& key) {
    ImageMetadata metadata;
    readImage(path, &metadata);
    const ImageMetadata::Value* value = metadata.find(key);
    EXPECT_NE(value, nullptr) << key;
    if (!value)
        return -1.0f;
    // PNG keeps its attributes as text.
    if (const std::string* text = std::get_if<std::string>(value))
        return std::stof(*text);
    return std::get<float>(*value);
}

TEST(FalseColour, IlluminanceOnALinearScale) {
    TempDir dir("falsecolor-linear");
    const std::string image = renderFloor(dir);
    const std::string picture = dir.file("lux.png");
    const CliResult r = runPenumbra("falsecolor " + image + " -o " + picture +
                                    " --quantity illuminance --scale linear --max 50 -q");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(metadataFloat(picture, "penumbra:falsecolor_low"), 0.0f);
    EXPECT_EQ(metadataFloat(picture, "penumbra:falsecolor_high"), 50.0f);
    const Image shown = readImage(picture);
    EXPECT_EQ(shown.height(), kSize + kFalseColourLegendHeight);
    expectMapAtFraction(shown, kLux / 50.0);
}

TEST(FalseColour, LuminanceOnALogScale) {
    TempDir dir("falsecolor-log");
    const std::string image = renderFloor(dir);
    const std::string picture = dir.file("luminance.png");
    const double luminance = kRho * kLux / std::numbers::pi;
    // Two decades below 100 x the floor's luminance: it sits at the middle of the scale.
    const CliResult r = runPenumbra("falsecolor " + image + " -o " + picture + " --max " +
                                    std::to_string(100.0 * luminance) + " --decades 4 -q");
    ASSERT_EQ(r.status, 0) << r.output;
    expectMapAtFraction(readImage(picture), 0.5);
}

TEST(FalseColour, RefusesWhatItCannotShow) {
    TempDir dir("falsecolor-refusals");
    const std::string image = renderFloor(dir);
    renderImage(dir.file("scene.gltf"), dir.file("plain.exr"), "--quiet --width 4 --height 4");
    const struct {
        std::string arguments, message;
    } cases[] = {
        {dir.file("plain.exr") + " --quantity illuminance", "--aov illuminance"},
        {image + " --quantity radiance", "--quantity radiance"},
        {image + " --scale cubic", "--scale cubic"},
        {dir.file("missing.exr"), "missing.exr"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.arguments);
        const CliResult r = runPenumbra("falsecolor " + c.arguments + " -o " + dir.file("out.png"));
        EXPECT_EQ(r.status, 2) << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
        EXPECT_FALSE(std::filesystem::exists(dir.file("out.png")));
    }
}

}  // namespace
}  // namespace penumbra::test
