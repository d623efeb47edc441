// The radiosity pipeline on the Cornell box against the stored converged path-traced reference
// (scenes/cornell-box/reference.exr, 16384 spp): the units test, region by region. Every
// surface of the box is Lambertian, so the radiosity solution and the path tracer solve the same
// equation and must agree on the mean radiance of each wall and block face.
#include "core/gltf_loader.h"
#include "core/image_io.h"
#include "core/scene.h"
#include "tests/support/cli_runner.h"
#include "tests/support/region_means.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace penumbra::test {
namespace {

const std::string kSceneFolder = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box";
constexpr int kSize = 128;  // the stored reference's size

TEST(RadiosityCornellBox, EveryWallAndBlockFaceAgreesWithTheReference) {
    const Scene scene(loadGltf(kSceneFolder + "/cornell-box.gltf"));
    const std::vector<int> mask = regionMask(scene, kSize, kSize);

    TempDir dir("radiosity-cornell");
    // The scene's own pass script's epsilon (scenes/cornell-box/radiosity.toml), half the default.
    const std::string script = dir.file("radiosity.toml");
    {
        std::ofstream toml(script);
        toml << "scene = \"" << kSceneFolder << "/cornell-box.gltf\"\nwidth = 128\nheight = 128\n"
             << "spp = 4\n[[pass]]\ntype = \"radiosity\"\nepsilon = 0.005\n";
    }
    const std::string out = dir.file("radiosity.exr");
    const CliResult result = runPenumbra("render " + script + " -o " + out + " --quiet");
    ASSERT_EQ(result.status, 0) << result.output;
    const Image radiosity = readImage(out);
    const Image reference = readImage(kSceneFolder + "/reference.exr");
    ASSERT_EQ(reference.width(), kSize);

    const RegionMeans r = regionMeans(radiosity, mask);
    const RegionMeans p = regionMeans(reference, mask);
    // Faces seen through at least this many whole pixels; the reference's relative standard
    // error of such a mean is below 0.1 % (per-pixel relative deviation near 5 % at 16384 spp,
    // over 30 or more pixels), so the bound is on the radiosity's error alone.
    constexpr int kMinPixels = 30;
    // The issue asks for 2 %. History (default settings): first every face and channel within
    // [-3.4 %, +3.1 %], most of them 1-2 % low; since partly occluded links weigh the children at
    // either end by their own visible fractions (setSourceWeights, setReceiverWeights in
    // radiosity/link_hierarchy.cpp) within [-2.6 %, +1.7 %]; since the solution is that of the
    // exposed part of each element (isCovered, element_sampling.h: the ceiling leaves straddling
    // the lamp that hangs 0.1 mm under it and the floor leaves straddling the blocks' feet showed,
    // and sent, the mean of their lit and covered parts, 10-15 % low over a few pixels) within
    // [-1.0 %, +2.9 %], above 2 % only two faces lit only indirectly, in their weak channels (the
    // short block's front +2.3 % green, the tall block's narrow face towards the red wall +2.9 %
    // green). Wholly covered sides no longer linked (2026-12-02) took away the refinement their
    // links had caused by chance: that face came out +3.2 %. The oracle now also refines a link
    // whose error is more than epsilon of what the receiver itself reflects in any channel
    // (exceedsThreshold in radiosity/link_refiner.cpp), and the faces converge to the reference as
    // epsilon shrinks: [-2.9 %, +1.8 %] at the default 0.01 (the short block's front, -2.3 to
    // -2.9 %, converges from below), [-1.8 %, +0.2 %] at 0.005, [-0.9 %, +0.1 %] at 0.00125. The
    // test runs at the scene's own script's 0.005 and holds the 2 %. Since a link's rays
    // go only to pairs of points that face each other (visibility() in
    // radiosity/link_transfer.cpp), the links that straddle a block's foot are no longer dropped
    // when their draws missed the few facing pairs: [-1.0 %, +0.6 %] at 0.005. The bound is 1.5 %,
    // tighter than the 2 %, so that losing that again fails here (the short block's front
    // face was -1.7 % before).
    constexpr double kTolerance = 0.015;
    const int regions = expectRegionMeansNear(scene, r, p, kMinPixels, "radiosity",
                                              [](const std::string&) { return kTolerance; });
    // The five walls, the light, and the visible faces of the two blocks.
    EXPECT_GE(regions, 10);
}

}  // namespace
}  // namespace penumbra::test
