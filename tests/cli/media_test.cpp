// A participating medium through the command line (docs/media.md): a pass script's [[medium]]
// reaches the render with its box in the glTF file's world frame, its density from an OpenVDB
// file placed by its box or by the file's own voxel transform, and the pipelines that do not
// render media refuse such a scene with exit status 2 and no image, as bad tables are refused.
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/medium_scenes.h"

#include <gtest/gtest.h>
#include <openvdb/openvdb.h>

#include <algorithm>
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

// A density of 0.5 in 4 x 4 x 4 voxels, written as a.vdb whose voxel transform puts the voxel
// centres, with the border of zero around them, from (990, 40, -23.5) to (1010, 60, -22) in the
// file's frame: kSlab's box. Along z the density is then 0 at the box's faces, 0.5 from one
// voxel (0.3 m) inside them, linear between: its integral through the slab is 0.5 (1.5 - 0.3).
void writeDensity(const TempDir& dir) {
    openvdb::initialize();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(0.0f);
    grid->setName("density");
    grid->fill(openvdb::CoordBBox(openvdb::Coord(0), openvdb::Coord(3)), 0.5f);
    openvdb::math::Mat4d voxelToWorld(openvdb::math::Mat4d::identity());
    voxelToWorld.setToScale(openvdb::Vec3d(4.0, 4.0, 0.3));
    voxelToWorld.setTranslation(openvdb::Vec3d(994.0, 44.0, -23.2));
    grid->setTransform(openvdb::math::Transform::createLinearTransform(voxelToWorld));
    openvdb::io::File(dir.file("density.vdb")).write({grid});
}

TEST(Media, AVdbDensityAttenuatesByItsOpticalDepth) {
    TempDir dir("media-density");
    writeScene(dir);
    writeDensity(dir);
    const float sigmaA[3] = {0.1f, 0.4f, 1.0f};
    // Placed by the file's transform, and stretched over the same box by the script.
    for (const std::string placement : {"", "box = [990, 40, -23.5, 1010, 60, -22]\n"}) {
        SCOPED_TRACE(placement.empty() ? "the file's placement" : "the script's box");
        writeScript(
            dir, "[[pass]]\ntype = \"path\"\n",
            "[[medium]]\nsigma_a = [0.1, 0.4, 1.0]\ndensity = \"density.vdb\"\n" + placement);
        const Image image = renderImage(dir.file("scene.toml"), dir.file("density.exr"),
                                        "--width 8 --height 8 --spp 4");
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(regionMean(image, c, 0, 0, 8, 8), 3.0 * std::exp(-sigmaA[c] * 0.6),
                        1e-4 * 3.0)
                << "channel " << c;
        }
    }
    const CliResult info = runPenumbra("info " + dir.file("scene.toml"));
    EXPECT_EQ(info.status, 0) << info.output;
    EXPECT_NE(info.output.find("scaled by a density grid of 6 x 6 x 6 nodes, at most 0.5"),
              std::string::npos)
        << info.output;
}

TEST(Media, ABadDensityIsRefused) {
    TempDir dir("media-bad-density");
    writeScene(dir);
    writeDensity(dir);
    const std::string path = "[[pass]]\ntype = \"path\"\n";
    writeScript(dir, path, "[[medium]]\nsigma_a = 0.1\ndensity = \"missing.vdb\"\n");
    expectRefused(dir, "scene.toml:6:11: medium[0].density: file not found");
    writeScript(dir, path, "[[medium]]\nsigma_a = 0.1\ndensity = \"panel.gltf\"\n");
    expectRefused(dir, "medium[0].density: expected an OpenVDB file (.vdb)");
    writeScript(dir, path, "[[medium]]\nsigma_a = 0.1\ndensity_grid = \"smoke\"\n");
    expectRefused(dir, "medium[0].density_grid: names a grid of the density file");
    writeScript(dir, path,
                "[[medium]]\nsigma_a = 0.1\ndensity = \"density.vdb\"\ndensity_grid = \"smoke\"\n");
    expectRefused(dir, "density.vdb: no grid \"smoke\" (the file holds \"density\")");
}

// The slab glowing: what it emits along the 1.5 m, Le (1 - exp(-sigma_a 1.5)), adds to what it
// lets through of the panel.
TEST(Media, AGlowingSlabAddsItsEmission) {
    TempDir dir("media-glow");
    writeScene(dir);
    writeScript(dir, "[[pass]]\ntype = \"path\"\n", kSlab + "emission = [1.0, 2.0, 0.5]\n");
    const Image image =
        renderImage(dir.file("scene.toml"), dir.file("glow.exr"), "--width 8 --height 8 --spp 4");
    const float sigmaA[3] = {0.1f, 0.4f, 1.0f}, Le[3] = {1.0f, 2.0f, 0.5f};
    for (int c = 0; c < 3; ++c) {
        const double T = std::exp(-sigmaA[c] * 1.5);
        EXPECT_NEAR(regionMean(image, c, 0, 0, 8, 8), 3.0 * T + Le[c] * (1.0 - T), 1e-4 * 3.0)
            << "channel " << c;
    }
    const CliResult info = runPenumbra("info " + dir.file("scene.toml"));
    EXPECT_NE(info.output.find("emitting (1, 2, 0.5) cd/m²"), std::string::npos) << info.output;
    // Emission without absorption in a channel is refused.
    writeScript(dir, "[[pass]]\ntype = \"path\"\n",
                "[[medium]]\nsigma_a = [0.1, 0.0, 0.1]\nemission = 1.0\n");
    expectRefused(dir, "scene.toml:6:12: medium[0].emission: a medium emits sigma_a x emission");
}

// The corrected hybrid renders a medium, named as a built-in pipeline by the script: in thermal
// equilibrium (walls that reflect rho and emit (1 - rho) Le around a medium that absorbs, scatters
// and emits with Le) every pixel sees Le, though the radiosity solution that the path pass reuses
// holds neither the medium's emission nor its scattering (docs/media.md, "The corrected hybrid").
// --pipeline replaces the script's, and combined with [[pass]] tables is refused.
TEST(Media, TheHybridRendersAGlowingFurnaceInEquilibrium) {
    TempDir dir("media-hybrid");
    const Color Le(1.0f, 2.0f, 0.5f);
    GltfBuilder scene = equilibriumBox(0.4f, Le);
    scene.setPerspectiveCamera({0.0f, 0.0f, 0.5f}, {0.0f, 0.0f, 0.0f, 1.0f}, 1.2f);
    scene.write(dir.file("furnace.gltf"));
    std::ofstream(dir.file("scene.toml"))
        << "scene = \"furnace.gltf\"\npipeline = \"hybrid\"\n"
        << "[[medium]]\nsigma_a = [0.6, 0.3, 1.0]\nsigma_s = 0.8\ng = 0.5\n"
        << "emission = [1.0, 2.0, 0.5]\n";
    for (const std::string pipeline : {"", "--pipeline reference"}) {
        CliResult run;
        const Image image = renderImage(dir.file("scene.toml"), dir.file("furnace.exr"),
                                        "--width 16 --height 16 --spp 16 " + pipeline, &run);
        // The hybrid's radiosity pass ran: its solution was reused.
        EXPECT_EQ(run.output.find("radiosity links") != std::string::npos, pipeline.empty())
            << run.output;
        // 4096 paths: the pixels' spread gives the mean a standard error of 0.2-0.8 % (seed 0,
        // both pipelines); 3 % is four times the largest.
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(regionMean(image, c, 0, 0, 16, 16), Le[c], 0.03 * Le[c])
                << pipeline << ", channel " << c;
        }
    }
    // Refused, with no image: a pipeline with [[pass]] tables, an unknown pipeline, and
    // --pipeline with [[pass]] tables.
    const auto expectScriptRefused = [&](const std::string& text, const std::string& options,
                                         const std::string& message) {
        std::ofstream(dir.file("bad.toml")) << "scene = \"furnace.gltf\"\n" << text;
        const CliResult r = runPenumbra("render " + dir.file("bad.toml") + " -o " +
                                        dir.file("bad.exr") + " " + options);
        EXPECT_EQ(r.status, 2) << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
        EXPECT_FALSE(std::filesystem::exists(dir.file("bad.exr")));
    };
    expectScriptRefused("pipeline = \"hybrid\"\n[[pass]]\ntype = \"path\"\n", "",
                        "give either a built-in `pipeline` or [[pass]] tables");
    expectScriptRefused("pipeline = \"hybird\"\n", "",
                        "bad.toml:2:12: pipeline: unknown pipeline 'hybird'");
    expectScriptRefused("[[pass]]\ntype = \"path\"\n", "--pipeline hybrid",
                        "--pipeline cannot be combined with a pass script that lists [[pass]]");
}

// Whitted's pass with the seed's linear fog (raytrace/linear_fog.h): through the slab, now also
// scattering and glowing, the panel keeps max(0, 1 - tau / 2) of its radiance, tau the slab's
// optical thickness, and the fog adds the rest of L_a = (sigma_s A + sigma_a Le) / sigma_t, A the
// ambient radiance: exactly, per channel, one of them (tau = 2.25) wholly fogged.
TEST(Media, WhittedsLinearFogIsTheSeedsFormula) {
    TempDir dir("media-linear-fog");
    writeScene(dir);
    writeScript(dir, "[[pass]]\ntype = \"whitted\"\nambient = 0.5\nmedium = \"linear-fog\"\n",
                kSlab + "sigma_s = 0.5\nemission = [1.0, 2.0, 0.5]\n");
    const Image image =
        renderImage(dir.file("scene.toml"), dir.file("fog.exr"), "--width 8 --height 8 --spp 1");
    const double sigmaA[3] = {0.1, 0.4, 1.0}, Le[3] = {1.0, 2.0, 0.5};
    for (int c = 0; c < 3; ++c) {
        const double sigmaT = sigmaA[c] + 0.5;
        const double T = std::max(0.0, 1.0 - sigmaT * 1.5 / 2.0);
        const double La = (0.5 * 0.5 + sigmaA[c] * Le[c]) / sigmaT;
        EXPECT_NEAR(regionMean(image, c, 0, 0, 8, 8), 3.0 * T + (1.0 - T) * La, 1e-4 * 3.0)
            << "channel " << c;
    }
    writeScript(dir, "[[pass]]\ntype = \"whitted\"\nmedium = \"fog\"\n", kSlab);
    expectRefused(dir,
                  "scene.toml:4:10: pass[0].medium: unknown value 'fog'; valid: "
                  "single-scattering, linear-fog");
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
