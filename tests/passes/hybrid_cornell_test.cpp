// The pipelines that reuse the radiosity solution (hybrid, hybrid-preview, distribution) on the
// Cornell box
// against the stored converged path-traced reference (scenes/cornell-box/reference.exr, 16384
// spp), wall by wall and block face by block face: the 3 % at default settings. Every
// surface of the box is Lambertian, so both pipelines count every light path the box holds
// (L D* E; `penumbra plan` warns of none) and must agree with the reference up to the radiosity
// solution's error, which they see only after the first diffuse bounce, and their own noise.
#include "core/gltf_loader.h"
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/region_means.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace penumbra::test {
namespace {

const std::string kSceneFolder = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box";
constexpr int kSize = 128;  // the stored reference's size

// Faces seen through at least this many whole pixels (as tests/passes/radiosity_cornell_test.cpp).
constexpr int kMinPixels = 30;
// The issue asks for 3 % on every region mean. Measured (seeds 1, 2, 7): since the closed
// solids' inner sides are sealed and the oracle also weighs each receiver's own radiance
// (radiosity/link_refiner.cpp, exceedsThreshold) the hybrid (today's hybrid-preview, which takes
// the solution as it is) is within [-1.6 %, +2.5 %] (the tall
// block's narrow face towards the red wall in green, +2.0 to +2.5 %, the short block's front
// -1.6 %), the distribution pipeline within [-2.9 %, +1.7 %] on every seed (its ambient term is
// the radiosity view's indirect part, whose short block front converges from below as epsilon
// shrinks: -2.9 % at the default 0.01, -1.8 % at 0.005; tests/passes/radiosity_cornell_test.cpp).
// Both are held to the 3 %. Before, since the radiosity solution is that of each
// element's exposed part (isCovered, element_sampling.h): distribution [-0.9 %, +2.8 %], hybrid
// [-1.1 %, +4.0 %] (that narrow face: the oracle's threshold, relative to the scene's mean
// radiance only, was about 10 % of its green); before that, distribution [-2.6 %, +1.6 %],
// hybrid [-4.3 %, +1.7 %] (the short block's dim front in red); before the solver's visibility
// fix [-4.0 %, +3.2 %] and [-3.4 %, +3.1 %].
// The hybrid corrects the solution (raytrace/path_tracer.h): its means are the path tracer's,
// its noise more than the preview's, which takes the solution as it is. At 64 spp its darkest
// faces' means were 3 % off on seed 7 (the short block's side -2.9 %, with the correction
// filtered or not: noise, not the filter), at 256 spp within [-0.6 %, +2.0 %] over seeds 1, 2
// and 7; the preview keeps the bound of the solution's error above at 64 spp.
struct Case {
    std::string pipeline;
    double tolerance;
    int spp;
};

class ReusingPipelines : public testing::TestWithParam<Case> {};

TEST_P(ReusingPipelines, EveryWallAndBlockFaceAgreesWithTheReference) {
    const Scene scene(loadGltf(kSceneFolder + "/cornell-box.gltf"));
    const std::vector<int> mask = regionMask(scene, kSize, kSize);

    const Case& param = GetParam();
    TempDir dir("reusing-" + param.pipeline);
    const std::string out = dir.file("image.exr");
    const CliResult result = runPenumbra(
        "render " + kSceneFolder + "/cornell-box.gltf -o " + out + " --quiet" + " --pipeline " +
        param.pipeline + " --width 128 --height 128 --seed 7 --spp " + std::to_string(param.spp));
    ASSERT_EQ(result.status, 0) << result.output;
    const RegionMeans test = regionMeans(readImage(out), mask);
    const RegionMeans reference = regionMeans(readImage(kSceneFolder + "/reference.exr"), mask);

    const int regions = expectRegionMeansNear(scene, test, reference, kMinPixels, param.pipeline,
                                              [&](const std::string&) { return param.tolerance; });
    EXPECT_GE(regions, 10);  // the five walls, the light, the visible faces of the blocks
}

INSTANTIATE_TEST_SUITE_P(CornellBox, ReusingPipelines,
                         testing::Values(Case{"hybrid", 0.03, 256},
                                         Case{"hybrid-preview", 0.03, 64},
                                         Case{"distribution", 0.03, 64}),
                         [](const testing::TestParamInfo<Case>& info) {
                             std::string name = info.param.pipeline;
                             std::replace(name.begin(), name.end(), '-', '_');
                             return name;
                         });

}  // namespace
}  // namespace penumbra::test
