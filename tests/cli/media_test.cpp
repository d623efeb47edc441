// A participating medium through the command line (docs/media.md): a pass script's [[medium]]
// reaches the render with its box in the glTF file's world frame, and the pipelines that do not
// render media refuse such a scene with exit status 2 and no image.
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace penumbra::test {
namespace {

// Everything moved far from the file's origin (the loader rebases it): a panel of 3 cd/m² 5 m in
// front of an orthographic camera that looks along -Z at its middle.
const Vec3 kOffset(1000.0f, 50.0f, -20.0f);

void writeScene(const TempDir& dir) {
    GltfBuilder scene;
    const int panel = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 3.0f});
    scene.addQuad({-1, -1, -5}, {1, -1, -5}, {1, 1, -5}, {-1, 1, -5}, panel);
    scene.setOrthographicCamera({0, 0, 0}, {0, 0, 0, 1}, 0.2f, 0.2f);
    scene.setRootTransform(kOffset, 1.0f);
    scene.write(dir.file("panel.gltf"));
}

void writeScript(const TempDir& dir, const std::string& passes, const std::string& medium) {
    std::ofstream(dir.file("scene.toml")) << "scene = \"panel.gltf\"\n" << passes << medium;
}

// An absorbing slab 1.5 m thick between the camera and the panel, in the file's frame.
const std::string kSlab =
    "[[medium]]\n"
    "sigma_a = [0.1, 0.4, 1.0]\n"
    "box = [990, 40, -23.5, 1010, 60, -22]\n";

// Renders the script of `dir` and expects it refused: exit status 2, `message` said, no image.
void expectRefused(const TempDir& dir, const std::string& message) {
    const std::string output = dir.file("refused.exr");
    const CliResult r = runPenumbra("render " + dir.file("scene.toml") + " -o " + output +
                                    " --width 8 --height 8 --spp 4");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(output));
}

TEST(Media, AScriptsSlabAttenuatesByBeerLambert) {
    TempDir dir("media-slab");
    writeScene(dir);
    writeScript(dir, "[[pass]]\ntype = \"path\"\n", kSlab);
    const Image image =
        renderImage(dir.file("scene.toml"), dir.file("slab.exr"), "--width 8 --height 8 --spp 4");
    const float sigmaA[3] = {0.1f, 0.4f, 1.0f};
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(regionMean(image, c, 0, 0, 8, 8), 3.0 * std::exp(-sigmaA[c] * 1.5), 1e-4 * 3.0)
            << "channel " << c;
    }
}

TEST(Media, PipelinesWithoutMediaRefuseTheScene) {
    TempDir dir("media-refused");
    writeScene(dir);
    writeScript(dir, "[[pass]]\ntype = \"radiosity\"\n[[pass]]\ntype = \"distribution\"\n", kSlab);
    // The radiosity pass is skipped here (the panel reflects nothing): the distribution pass is
    // the first that runs.
    expectRefused(dir, "pass 2 (distribution) does not render participating media");
}

TEST(Media, ABadMediumIsRefusedAtItsPlace) {
    TempDir dir("media-bad");
    writeScene(dir);
    writeScript(dir, "[[pass]]\ntype = \"path\"\n", "[[medium]]\nsigma_s = 0.1\ng = 1.5\n");
    expectRefused(dir, "scene.toml:6:5: medium[0].g: expected a number in (-1, 1), got 1.5");
}

}  // namespace
}  // namespace penumbra::test
