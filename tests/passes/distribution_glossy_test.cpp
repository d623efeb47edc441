// The distribution pipeline on the glossy scene (scenes/glossy: gold spheres of roughness 0.1,
// 0.25 and 0.5, a blue plastic with a smooth and with a rough coat, in the Cornell box) against
// its stored path-traced reference (4096 spp): the rough glossy lobes' indirect light, which
// the distribution tracer gets by sampling the lobe towards the radiosity solution
// (raytrace/distribution_tracer.h), while the Lambertian layer takes its share of the
// solution's indirect light. The spheres show mostly the walls' reflection, so a tracer that
// spread the glossy lobes' indirect light as Lambertian (as the ambient term alone does) is
// visibly off on them.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace penumbra::test {
namespace {

const std::string kFolder = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/glossy/";

double luminance(const Image& image, int x, int y) {
    return 0.2126 * image.at(x, y, 0) + 0.7152 * image.at(x, y, 1) + 0.0722 * image.at(x, y, 2);
}

// Whether the first hit's base colour (the albedo AOV) at (x, y) is `base`: the pixels that see
// one material, whole (an edge pixel mixes colours and is left out).
bool shows(const Image& image, int x, int y, const Color& base) {
    const int albedo = image.channelIndex("albedo.R");
    for (int c = 0; c < 3; ++c) {
        if (std::abs(image.at(x, y, albedo + c) - base[c]) > 0.02f)
            return false;
    }
    return true;
}

// The summed luminance of `image` over the pixels whose first hit is of base colour `base` (as
// `shows` says, in `image`'s albedo AOV), over that of `reference` there, and how many pixels.
struct RegionRatio {
    double ratio = 0.0;
    int pixels = 0;
};
RegionRatio regionRatio(const Image& image, const Image& reference, const Color& base) {
    double test = 0.0, ref = 0.0;
    int pixels = 0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            if (shows(image, x, y, base)) {
                test += luminance(image, x, y);
                ref += luminance(reference, x, y);
                ++pixels;
            }
        }
    }
    return {ref > 0.0 ? test / ref : 0.0, pixels};
}

// A scene's `distribution` preview (64 spp) against the path tracer (1024 spp), 48 x 48, over
// the pixels that show base colour `base`.
RegionRatio previewAgainstPathTracer(GltfBuilder& scene, const std::string& name,
                                     const Color& base) {
    TempDir dir(name);
    scene.write(dir.file("room.gltf"));
    const std::string options = " --width 48 --height 48 --seed 2 --aov albedo";
    const Image preview = renderImage(dir.file("room.gltf"), dir.file("distribution.exr"),
                                      "--pipeline distribution --spp 64" + options);
    const Image reference = renderImage(dir.file("room.gltf"), dir.file("reference.exr"),
                                        "--pipeline reference --spp 1024" + options);
    return regionRatio(preview, reference, base);
}

TEST(DistributionGlossy, GlossySpheresAgreeWithTheReference) {
    TempDir dir("distribution-glossy");
    const std::string out = dir.file("distribution.exr");
    const CliResult result =
        runPenumbra("render " + kFolder + "glossy.gltf -o " + out +
                    " --quiet --pipeline distribution --width 128 --height 128 --spp 64 "
                    "--seed 3 --aov albedo");
    ASSERT_EQ(result.status, 0) << result.output;
    const Image image = readImage(out);
    const Image reference = readImage(kFolder + "reference.exr");
    ASSERT_EQ(reference.width(), image.width());

    const struct {
        const char* name;
        Color base;  // scenes/glossy/README.md
    } regions[] = {{"gold", Color(1.0f, 0.766f, 0.336f)},
                   {"blue plastic", Color(0.05f, 0.15f, 0.5f)}};
    // Measured: gold 0.986, plastic 0.997 of the reference (seed 3) since the plastic's Lambertian
    // layer takes its directional albedo's share of the solution (0.995 with its average), and
    // since the sharp glossy lobes (the gold of roughness 0.1) are carried by the specular
    // transfer; before, 0.978 and 0.989
    // (seed 3; seeds 0 and 1: 0.989 and
    // 0.995, 1.002 and 0.986); with the ambient term alone (the glossy lobes' indirect light
    // spread as Lambertian) 0.928 and 0.945 (seed 3). The bound is the issue's 3 % for
    // distribution's region means; the reference's own noise over these regions (450 and 1200
    // pixels at 4096 spp) is far below it.
    for (const auto& r : regions) {
        const RegionRatio region = regionRatio(image, reference, r.base);
        ASSERT_GT(region.pixels, 300) << r.name;
        std::printf("%-13s pixels %5d  distribution / reference %.4f\n", r.name, region.pixels,
                    region.ratio);
        EXPECT_NEAR(region.ratio, 1.0, 0.03) << r.name;
    }
}

// A rough metal floor (roughness 0.3: a glossy lobe the solution spreads, which the tracer
// samples) in front of a mirror covering one wall of a white room lit by a lamp under its
// ceiling, seen from the opposite wall looking down: the floor reflects the mirror, which
// reflects the room behind the camera. The floor's sample must go on through the mirror to the
// wall it shows, as the eye's ray goes on through specular vertices; read at the mirror, which
// the solution holds black, the floor showed little but the lamp's highlight (as a polished floor
// showed a glass balustrade's stairs black on the modern hall). The path tracer is the oracle.
TEST(DistributionGlossy, ARoughFloorReflectsWhatTheMirrorShows) {
    GltfBuilder scene;
    const int white = scene.addMaterial({.baseColor = Color(0.8f)});
    addClosedBox(scene, white, white);
    const int mirror = scene.addMaterial(
        {.baseColor = Color(0.95f), .lambertian = false, .metallic = 1.0f, .roughness = 0.0f});
    const int rough = scene.addMaterial(
        {.baseColor = Color(0.9f), .lambertian = false, .metallic = 1.0f, .roughness = 0.3f});
    const int lamp = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 20.0f});
    constexpr float m = 0.99f, s = 0.2f, h = 0.9f;
    scene.addQuad({-m, -m, -m}, {m, -m, -m}, {m, m, -m}, {-m, m, -m}, mirror);  // z = -1, +z
    scene.addQuad({-m, -m, m}, {m, -m, m}, {m, -m, -m}, {-m, -m, -m}, rough);   // floor, up
    scene.addQuad({-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}, lamp);        // faces down
    // From z = 0.9 looking along -z, pitched 30 degrees down (about x).
    scene.setPerspectiveCamera({0.0f, 0.2f, 0.9f}, {-0.258819f, 0.0f, 0.0f, 0.965926f}, 0.8f);
    const RegionRatio floor = previewAgainstPathTracer(scene, "distribution-mirror", Color(0.9f));
    ASSERT_GT(floor.pixels, 500);
    std::printf("rough floor: pixels %d  distribution / reference %.4f\n", floor.pixels,
                floor.ratio);
    // Measured 0.991 (0.488 with the sample read at the mirror). The bound is the issue's 3 % for
    // the preview's region means; the path tracer's noise over 1000 pixels is far below it.
    EXPECT_NEAR(floor.ratio, 1.0, 0.03);
}

TEST(DistributionGlossy, APolishedFloorSeenAtGrazingAnglesIsNotTooBright) {
    // A coated floor (roughness 0.1, as the modern hall's tiles) seen from just above it: at
    // grazing angles its coat reflects much of the light and the Lambertian layer under it
    // little, so the layer's share of the solution must be its directional albedo there
    // (Bsdf::matteAlbedo), not its hemispherical average. The path tracer is the oracle.
    GltfBuilder scene;
    const int white = scene.addMaterial({.baseColor = Color(0.8f)});
    addClosedBox(scene, white, white);
    const int polished =
        scene.addMaterial({.baseColor = Color(0.5f), .lambertian = false, .roughness = 0.1f});
    const int lamp = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 20.0f});
    constexpr float m = 0.99f, s = 0.2f, h = 0.9f;
    scene.addQuad({-m, -m, m}, {m, -m, m}, {m, -m, -m}, {-m, -m, -m}, polished);  // floor, up
    scene.addQuad({-s, h, -s}, {s, h, -s}, {s, h, s}, {-s, h, s}, lamp);          // faces down
    // 9 cm above the floor at z = 0.9, looking along -z, pitched 5 degrees down (about x): the
    // floor is seen at 62 to 87 degrees from its normal.
    scene.setPerspectiveCamera({0.0f, -0.9f, 0.9f}, {-0.0436194f, 0.0f, 0.0f, 0.9990482f}, 0.8f);
    const RegionRatio floor = previewAgainstPathTracer(scene, "distribution-grazing", Color(0.5f));
    ASSERT_GT(floor.pixels, 300);
    std::printf("polished floor: pixels %d  distribution / reference %.4f\n", floor.pixels,
                floor.ratio);
    // Measured 0.995 (1.120 with the Lambertian layer's hemispherical albedo). The bound is the
    // issue's 3 % for the preview's region means.
    EXPECT_NEAR(floor.ratio, 1.0, 0.03);
}

}  // namespace
}  // namespace penumbra::test
