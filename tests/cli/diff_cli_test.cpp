// `penumbra diff` through the real binary: exit status 0 when every check holds, 1 when one
// fails (named in the message), 2 on bad input with nothing written; --json, --downsample,
// --mask; the heat map and its legend.
#include "core/heatmap.h"
#include "core/image_io.h"
#include "tests/support/cli_runner.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>

namespace penumbra::test {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

Image makeRgb(int width, int height, const std::function<float(int, int, int)>& value) {
    Image image(width, height, {"R", "G", "B"});
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < 3; ++c)
                image.at(x, y, c) = value(x, y, c);
        }
    }
    return image;
}

// A smooth HDR pattern, values in [0.2, 1.8].
float pattern(int x, int y, int c) {
    return float(1.0 + 0.8 * std::sin(0.3 * x + c) * std::cos(0.2 * y));
}

void writeExr(const std::string& path, const Image& image) {
    writeImage(path, image, {}, {}, ToneMapping{});
}

// A Portable Float Map (little-endian, rows bottom to top): the one float format simple enough
// to write here with a NaN in it (writeImage replaces non-finite values by 0).
void writePfm(const std::string& path, const Image& image) {
    std::ofstream out(path, std::ios::binary);
    out << "PF\n" << image.width() << " " << image.height() << "\n-1.0\n";
    for (int y = image.height() - 1; y >= 0; --y) {
        for (int x = 0; x < image.width(); ++x) {
            for (int c = 0; c < 3; ++c) {
                const float v = image.at(x, y, c);
                out.write(reinterpret_cast<const char*>(&v), sizeof v);
            }
        }
    }
}

class DiffCli : public ::testing::Test {
  protected:
    void SetUp() override {
        writeExr(file("reference.exr"), makeRgb(48, 32, pattern));
        // R off by +0.1 everywhere, G and B exact.
        writeExr(file("offset.exr"), makeRgb(48, 32, [](int x, int y, int c) {
                     return pattern(x, y, c) + (c == 0 ? 0.1f : 0.0f);
                 }));
    }

    std::string file(const std::string& name) const { return dir_.file(name); }
    CliResult diff(const std::string& test, const std::string& arguments = "") const {
        return runPenumbra("diff " + file(test) + " " + file("reference.exr") + " " + arguments);
    }

    TempDir dir_{"diff-cli"};
};

TEST_F(DiffCli, IdenticalImagesPassEveryCheck) {
    const CliResult result =
        diff("reference.exr", "--fail-above rmse=0 --fail-below ssim=1 --fail-below psnr=200");
    EXPECT_EQ(result.status, 0) << result.output;
    EXPECT_TRUE(contains(result.output, "inf")) << result.output;  // PSNR of identical images
}

TEST_F(DiffCli, FailedThresholdExitsOneAndSaysWhich) {
    // RMSE over all channels: sqrt(0.1^2 / 3) = 0.0577.
    CliResult result = diff("offset.exr", "--fail-above rmse=0.05 --fail-above mae=1");
    EXPECT_EQ(result.status, 1) << result.output;
    EXPECT_TRUE(contains(result.output, "FAIL: rmse (all) = 0.05774 is above 0.05"))
        << result.output;
    EXPECT_FALSE(contains(result.output, "FAIL: mae")) << result.output;
    EXPECT_EQ(diff("offset.exr", "--fail-above rmse=0.06").status, 0);
    // Per row: G is exact, R is not.
    EXPECT_EQ(diff("offset.exr", "--fail-above rmse:G=1e-6").status, 0);
    result = diff("offset.exr", "--fail-above rmse:R=0.09 --fail-below psnr:R=10");
    EXPECT_EQ(result.status, 1) << result.output;
    EXPECT_TRUE(contains(result.output, "rmse (R) = 0.1 is above 0.09")) << result.output;
    // Higher is better for PSNR and SSIM: --fail-below.
    result = diff("offset.exr", "--fail-below ssim=0.99999");
    EXPECT_EQ(result.status, 1) << result.output;
    EXPECT_TRUE(contains(result.output, "FAIL: ssim (all)")) << result.output;
}

TEST_F(DiffCli, JsonIsOneObject) {
    const CliResult result = diff("offset.exr", "--json --fail-above relmse=1 --metric rmse,psnr");
    ASSERT_EQ(result.status, 0) << result.output;
    const nlohmann::json json = nlohmann::json::parse(result.output);
    EXPECT_EQ(json["width"], 48);
    EXPECT_EQ(json["compared_pixels"], 48 * 32);
    EXPECT_NEAR(json["metrics"]["R"]["rmse"].get<double>(), 0.1, 1e-6);
    EXPECT_EQ(json["metrics"]["G"]["rmse"].get<double>(), 0.0);
    EXPECT_TRUE(json["metrics"]["G"]["psnr"].is_null());  // +infinity
    EXPECT_NEAR(json["metrics"]["luminance"]["rmse"].get<double>(), 0.2126 * 0.1, 1e-6);
    EXPECT_FALSE(json["metrics"]["all"].contains("ssim"));  // not selected
    EXPECT_EQ(json["ssim_input"], "reinhard");
    ASSERT_EQ(json["thresholds"].size(), 1u);
    EXPECT_EQ(json["thresholds"][0]["metric"], "relmse");
    EXPECT_EQ(json["thresholds"][0]["passed"], true);
    EXPECT_EQ(json["passed"], true);
}

TEST_F(DiffCli, BadInputExitsTwo) {
    writeExr(file("small.exr"), makeRgb(24, 16, pattern));
    const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
        {"diff " + file("small.exr") + " " + file("reference.exr"),
         {"small.exr (24 x 16)", "reference.exr (48 x 32)", "differ in size"}},
        {"diff " + file("missing.exr") + " " + file("reference.exr"), {"missing.exr"}},
        {"diff " + file("offset.exr") + " " + file("reference.exr") + " --channel R,A",
         {"no channel \"A\"", "R, G, B"}},
        {"diff " + file("offset.exr") + " " + file("reference.exr") + " --fail-above rsme=1",
         {"unknown metric \"rsme\"", "rmse, relmse, mae, mre, psnr, ssim"}},
        {"diff " + file("offset.exr") + " " + file("reference.exr") + " --fail-above rmse:Z=1",
         {"no row \"Z\"", "R, G, B, luminance, all"}},
        {"diff " + file("offset.exr") + " " + file("reference.exr") + " --fail-above rmse=x",
         {"\"x\" is not a number"}},
        {"diff " + file("offset.exr") + " " + file("reference.exr") + " --metric rmse,foo",
         {"unknown metric \"foo\""}},
        {"diff " + file("offset.exr") + " " + file("reference.exr") + " --mask " +
             file("small.exr"),
         {"small.exr (24 x 16)", "differ in size"}},
        {"diff " + file("offset.exr") + " " + file("reference.exr") + " --heatmap " +
             file("no/such/dir/map.png"),
         {"does not exist"}},
    };
    for (const auto& [arguments, mentions] : cases) {
        // Each asks for a heat map, which must not be written.
        const CliResult result = runPenumbra(contains(arguments, "--heatmap")
                                                 ? arguments
                                                 : arguments + " --heatmap " + file("map.png"));
        EXPECT_EQ(result.status, 2) << arguments << "\n" << result.output;
        for (const std::string& mention : mentions)
            EXPECT_TRUE(contains(result.output, mention)) << arguments << "\n" << result.output;
        EXPECT_FALSE(fs::exists(file("map.png"))) << arguments;
    }
}

TEST_F(DiffCli, NonFinitePixelsFail) {
    Image poisoned = makeRgb(48, 32, pattern);
    poisoned.at(3, 4, 1) = std::numeric_limits<float>::quiet_NaN();
    poisoned.at(5, 6, 0) = std::numeric_limits<float>::infinity();
    writePfm(file("poisoned.pfm"), poisoned);
    const CliResult result = diff("poisoned.pfm", "--json");
    EXPECT_EQ(result.status, 1) << result.output;
    EXPECT_TRUE(contains(result.output, "poisoned.pfm: 2 pixels are NaN or infinite"))
        << result.output;
    // The other pixels are compared as usual: the PFM holds the reference's values exactly.
    const nlohmann::json json =
        nlohmann::json::parse(result.output.substr(0, result.output.rfind('}') + 1));
    EXPECT_EQ(json["nonfinite"]["test"], 2);
    EXPECT_EQ(json["compared_pixels"], 48 * 32 - 2);
    EXPECT_EQ(json["metrics"]["all"]["rmse"].get<double>(), 0.0);
}

TEST_F(DiffCli, DownsamplingAveragesNoiseAway) {
    // +-0.05 in a checkerboard: zero in every 2 x 2 block mean.
    writeExr(file("noisy.exr"), makeRgb(48, 32, [](int x, int y, int c) {
                 return pattern(x, y, c) + ((x + y) % 2 ? 0.05f : -0.05f);
             }));
    EXPECT_EQ(diff("noisy.exr", "--fail-above rmse=1e-3").status, 1);
    const CliResult result = diff("noisy.exr", "--downsample 2 --fail-above rmse=1e-6 --json");
    EXPECT_EQ(result.status, 0) << result.output;
    const nlohmann::json json = nlohmann::json::parse(result.output);
    EXPECT_EQ(json["width"], 24);
    EXPECT_EQ(json["height"], 16);
}

TEST_F(DiffCli, MaskGivesRegions) {
    // Left third 0, the rest 1 (an 8-bit PNG mask: values 0 and 1 exactly).
    writeImage(file("mask.png"),
               makeRgb(48, 32, [](int x, int, int) { return x < 16 ? 0.f : 1.f; }), {}, {},
               ToneMapping{});
    const CliResult result = diff("offset.exr", "--mask " + file("mask.png") + " --json");
    ASSERT_EQ(result.status, 0) << result.output;
    const nlohmann::json json = nlohmann::json::parse(result.output);
    ASSERT_EQ(json["regions"].size(), 2u);
    EXPECT_EQ(json["regions"][0]["mask_value"], 0.0);
    EXPECT_EQ(json["regions"][0]["pixels"], 16 * 32);
    EXPECT_EQ(json["regions"][1]["pixels"], 32 * 32);
    EXPECT_NEAR(json["regions"][1]["metrics"]["R"]["mae"].get<double>(), 0.1, 1e-6);
}

TEST_F(DiffCli, HeatmapHasTheMapAndALegend) {
    const CliResult result = diff("offset.exr", "--heatmap " + file("map.png"));
    ASSERT_EQ(result.status, 0) << result.output;
    const Image map = readImage(file("map.png"));
    // The map at the top left, the legend below; the picture is wider than the 48-px input.
    ASSERT_EQ(map.width(), kFalseColourMinWidth);
    ASSERT_EQ(map.height(), 32 + kFalseColourLegendHeight);
    // The bar's ends hold viridis's first and last colours, sRGB-encoded in the PNG (van der
    // Walt and Smith's table: (0.267, 0.005, 0.329) and (0.993, 0.906, 0.144)).
    const int barY = 32 + kFalseColourBarTop + kFalseColourBarHeight / 2;
    const float first[3] = {0.267f, 0.005f, 0.329f}, last[3] = {0.993f, 0.906f, 0.144f};
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(map.at(kFalseColourMargin, barY, c), first[c], 0.02) << c;
        EXPECT_NEAR(map.at(kFalseColourMinWidth - kFalseColourMargin - 1, barY, c), last[c], 0.02)
            << c;
    }
    EXPECT_TRUE(contains(result.output, "heat map")) << result.output;
}

}  // namespace
}  // namespace penumbra::test
