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

    struct Region {
        const char* name;
        Color base;  // scenes/glossy/README.md
        double test = 0.0, ref = 0.0;
        int pixels = 0;
    };
    Region regions[] = {{"gold", Color(1.0f, 0.766f, 0.336f)},
                        {"blue plastic", Color(0.05f, 0.15f, 0.5f)}};
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            for (Region& r : regions) {
                if (shows(image, x, y, r.base)) {
                    r.test += luminance(image, x, y);
                    r.ref += luminance(reference, x, y);
                    ++r.pixels;
                }
            }
        }
    }
    // Measured: gold 0.986, plastic 0.995 of the reference (seed 3) since the sharp glossy lobes
    // (the gold of roughness 0.1) are carried by the specular transfer; before, 0.978 and 0.989
    // (seed 3; seeds 0 and 1: 0.989 and
    // 0.995, 1.002 and 0.986); with the ambient term alone (the glossy lobes' indirect light
    // spread as Lambertian) 0.928 and 0.945 (seed 3). The bound is the issue's 3 % for
    // distribution's region means; the reference's own noise over these regions (450 and 1200
    // pixels at 4096 spp) is far below it.
    for (const Region& r : regions) {
        ASSERT_GT(r.pixels, 300) << r.name;
        const double ratio = r.test / r.ref;
        std::printf("%-13s pixels %5d  distribution / reference %.4f\n", r.name, r.pixels, ratio);
        EXPECT_NEAR(ratio, 1.0, 0.03) << r.name;
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
    TempDir dir("distribution-mirror");
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
    scene.write(dir.file("room.gltf"));
    const std::string options = " --width 48 --height 48 --seed 2 --aov albedo";
    const Image preview = renderImage(dir.file("room.gltf"), dir.file("distribution.exr"),
                                      "--pipeline distribution --spp 64" + options);
    const Image reference = renderImage(dir.file("room.gltf"), dir.file("reference.exr"),
                                        "--pipeline reference --spp 1024" + options);
    double test = 0.0, ref = 0.0;
    int pixels = 0;
    for (int y = 0; y < preview.height(); ++y) {
        for (int x = 0; x < preview.width(); ++x) {
            if (shows(preview, x, y, Color(0.9f))) {
                test += luminance(preview, x, y);
                ref += luminance(reference, x, y);
                ++pixels;
            }
        }
    }
    ASSERT_GT(pixels, 500);
    std::printf("rough floor: pixels %d  distribution / reference %.4f\n", pixels, test / ref);
    // Measured 0.991 (0.488 with the sample read at the mirror). The bound is the issue's 3 % for
    // the preview's region means; the path tracer's noise over 1000 pixels is far below it.
    EXPECT_NEAR(test / ref, 1.0, 0.03);
}

}  // namespace
}  // namespace penumbra::test
