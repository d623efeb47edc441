// Indirect caustics in the hybrid pipeline: a closed room lit mostly through a mirror. A small area
// light under the ceiling faces up at a mirror just above it, which catches 86 % of its light and
// sends it down (L S D: the floor lit by the light's mirror image), so most of the room's light
// is that caustic and its diffuse bounces (L S D D+). The hybrid's radiosity solution takes the
// caustic photons (radiosity/deposited_flux.h) and must then agree with the path tracer; with the
// photons left out of the solution (the radiosity pass's caustics = "exclude"), the preview
// (which takes the solution as it is) misses the light of L S D D D E and longer paths, which the
// planner names and this test measures, and the hybrid's correction brings it back: a solution
// without most of the room's light costs noise, not correctness.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace penumbra::test {
namespace {

class IndirectCaustics : public testing::Test {
  protected:
    void SetUp() override {
        GltfBuilder scene;
        addMirrorRoom(scene);
        scene.write(dir_.file("room.gltf"));
    }

    Image render(const std::string& input, const std::string& options, CliResult* out) {
        return renderImage(input, dir_.file("out.exr"),
                           "--width 64 --height 64 --seed 3 " + options, out);
    }

    // The hybrid's passes as a script, the radiosity pass's caustics key set to `caustics` and
    // the path pass's correction to `correction` (0: the preview).
    std::string hybridScript(const std::string& caustics, const std::string& correction) {
        const std::string path = dir_.file("hybrid-" + caustics + "-" + correction + ".toml");
        std::ofstream(path) << "scene = \"room.gltf\"\n"
                            << "[[pass]]\ntype = \"caustics\"\n"
                            << "[[pass]]\ntype = \"radiosity\"\ncaustics = \"" << caustics << "\"\n"
                            << "[[pass]]\ntype = \"path\"\nradiosity = true\ncorrection = "
                            << correction << "\n";
        return path;
    }

    TempDir dir_{"indirect-caustics"};
};

TEST_F(IndirectCaustics, TheSolutionCarriesThePhotonsOn) {
    const double reference =
        luminanceMean(render(dir_.file("room.gltf"), "--pipeline reference --spp 1024", nullptr));
    CliResult hybridRun;
    const double hybrid = luminanceMean(
        render(dir_.file("room.gltf"), "--pipeline hybrid-preview --spp 64", &hybridRun));
    CliResult excludedRun;
    const double excluded =
        luminanceMean(render(hybridScript("exclude", "0"), "--spp 64", &excludedRun));
    CliResult correctedRun;
    const double corrected =
        luminanceMean(render(hybridScript("exclude", "0.5"), "--spp 256", &correctedRun));
    std::printf("preview / reference %.4f, without photons in the solution %.4f, corrected %.4f\n",
                hybrid / reference, excluded / reference, corrected / reference);
    EXPECT_EQ(hybridRun.output.find("L S D D D E"), std::string::npos) << hybridRun.output;
    EXPECT_NE(excludedRun.output.find("L S D D D E"), std::string::npos) << excludedRun.output;
    EXPECT_EQ(correctedRun.output.find("warning"), std::string::npos) << correctedRun.output;
    // Measured: hybrid 0.981 (seeds 1 and 7 with this reference: 0.980, 0.977), without the
    // photons 0.59; two references of other seeds agree within 0.2 %. What the hybrid still
    // lacks is the solution's own error (the Cornell box's faces within 2.6 %) and the light
    // that the mirror carries between diffuse surfaces before the second diffuse vertex (L D S
    // D D D E, named by the planner; with a mirror over the whole ceiling it was 13 %). The
    // bound is the 3 % for the hybrid's region means.
    EXPECT_NEAR(hybrid / reference, 1.0, 0.03);
    EXPECT_LT(excluded / reference, 0.8);
    EXPECT_NEAR(corrected / reference, 1.0, 0.03);
}

}  // namespace
}  // namespace penumbra::test
