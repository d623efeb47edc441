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
    // Measured: gold 0.978, plastic 0.989 of the reference (seed 3; seeds 0 and 1: 0.989 and
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

}  // namespace
}  // namespace penumbra::test
