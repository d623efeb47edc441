// The hybrid pipeline on the glossy scene (scenes/glossy: gold spheres of roughness 0.1, 0.25 and
// 0.5, a blue plastic with a smooth and with a rough coat, in the Cornell box) against its stored
// path-traced reference (4096 spp), surface by surface. The spheres' rough glossy lobes are what
// the radiosity solution spreads as Lambertian: a path tracer that took the whole solution at its
// second diffuse vertex sent the gold's light up to the ceiling and off the floor, which the
// metal reflects down (raytrace/path_tracer.h: the reuse vertex takes only the Lambertian layer's
// share and follows the glossy lobes).
#include "core/gltf_loader.h"
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/region_means.h"

#include <gtest/gtest.h>

#include <string>

namespace penumbra::test {
namespace {

const std::string kFolder = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/glossy/";
constexpr int kSize = 128;  // the stored reference's size
// Surfaces seen through at least this many whole pixels: the box's five sides and its light, the
// five spheres.
constexpr int kMinPixels = 100;
// The box's sides see the spheres at the path's second diffuse vertex, where the bias was: with
// the whole solution taken there (this test's settings), the ceiling +3.6 % in red and +3.5 % in
// green (at 64 spp +3.6, +3.4, +1.9 %), the floor -1.4 %; following the glossy lobes, every side
// within [-1.5 %, +0.4 %] (seeds 1, 5 and 9; the ceiling's -1.0 to -1.5 % is what the solution
// still spreads as Lambertian from the third vertex on). The reference pipeline itself is within
// 0.3 % of the stored reference on them at 128 spp.
constexpr double kBoxTolerance = 0.02;
// The spheres show the light's highlights, the noisiest pixels: the reference pipeline is 2.1 %
// off on them at 128 spp (seed 5), the uncorrected hybrid was up to 2.5 %; this bound only
// catches a gross error. The corrected hybrid is noisier per sample (its correction traces on
// with weight 2): at 128 spp the smooth plastic's red (its dimmest channel) was +3.9 and +4.0 %
// in two builds, at 256 spp +2.6 %, its other channels and every other sphere within 1.8 %; so
// the test takes 256 spp.
constexpr double kSphereTolerance = 0.04;
constexpr int kSpp = 256;

// The spheres' nodes (scenes/glossy/README.md).
bool isSphere(const std::string& mesh) {
    return mesh.starts_with("gold_") || mesh.starts_with("plastic_");
}

TEST(HybridGlossy, EverySurfaceAgreesWithTheReference) {
    const Scene scene(loadGltf(kFolder + "glossy.gltf"));
    const std::vector<int> mask = regionMask(scene, kSize, kSize);
    TempDir dir("hybrid-glossy");
    const std::string out = dir.file("hybrid.exr");
    const CliResult result =
        runPenumbra("render " + kFolder + "glossy.gltf -o " + out +
                    " --quiet --pipeline hybrid --width 128 --height 128 --seed 5 --spp " +
                    std::to_string(kSpp));
    ASSERT_EQ(result.status, 0) << result.output;
    const RegionMeans test = regionMeans(readImage(out), mask);
    const RegionMeans reference = regionMeans(readImage(kFolder + "reference.exr"), mask);
    const int regions = expectRegionMeansNear(
        scene, test, reference, kMinPixels, "hybrid",
        [](const std::string& mesh) { return isSphere(mesh) ? kSphereTolerance : kBoxTolerance; });
    EXPECT_EQ(regions, 11);
}

}  // namespace
}  // namespace penumbra::test
