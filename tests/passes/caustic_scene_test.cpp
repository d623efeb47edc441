// The caustic scene of issue 4 (scenes/caustic-spheres: a glass and a mirror sphere in a box lit
// by a small area light) against its stored path-traced reference (4096 spp), through the command
// line. The caustic region is scenes/caustic-spheres/caustic-mask.png (the floor where the glass
// sphere focuses the light).
//
// - caustics + path (caustics-path.toml): an exact partition of the light paths, so the whole
//   image must agree with the reference and the caustic region up to the photon map's blur;
//   double counting or a lost class would show at once; the same with progressive photon mapping.
// - hybrid: as above, with the radiosity solution (which took the caustic photons) at the second
//   diffuse vertex; it leaves out the light paths the planner names (light that passed a sphere
//   after a diffuse bounce and then went between diffuse surfaces, L D S D D D E, ...), a
//   measured bias, low, never high.
// - the per-pass layers of the EXR sum to the beauty exactly, and a scene without specular
//   surfaces (the Cornell box) has no caustic pass.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace penumbra::test {
namespace {

const std::string kScenes = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/";
const std::string kFolder = kScenes + "caustic-spheres/";
constexpr char kSize[] = " --width 128 --height 128 --seed 5";

struct Means {
    double channel[3] = {0, 0, 0};
    double caustic = 0;  // mean luminance over the mask
};

double luminance(const Image& image, int x, int y) {
    return 0.2126 * image.at(x, y, 0) + 0.7152 * image.at(x, y, 1) + 0.0722 * image.at(x, y, 2);
}

Means means(const Image& image, const Image& mask) {
    Means m;
    int inMask = 0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            for (int c = 0; c < 3; ++c)
                m.channel[c] += image.at(x, y, c);
            if (mask.at(x, y, 0) > 0.5f) {
                m.caustic += luminance(image, x, y);
                ++inMask;
            }
        }
    }
    for (double& c : m.channel)
        c /= image.width() * image.height();
    m.caustic /= inMask;
    return m;
}

// Each channel's and the caustic region's ratio of `test` over `ref`, printed under `label`, with
// every channel's checked to lie in [lo, hi] and the caustic region's within 5 %.
void expectRatios(const Means& test, const Means& ref, const char* label, double lo, double hi) {
    for (int c = 0; c < 3; ++c) {
        const double ratio = test.channel[c] / ref.channel[c];
        std::printf("%s / reference, channel %d: %.4f\n", label, c, ratio);
        EXPECT_GT(ratio, lo) << "channel " << c;
        EXPECT_LT(ratio, hi) << "channel " << c;
    }
    std::printf("%s / reference, caustic region: %.4f\n", label, test.caustic / ref.caustic);
    EXPECT_NEAR(test.caustic / ref.caustic, 1.0, 0.05);
}

class CausticScene : public testing::Test {
  protected:
    Image render(const std::string& input, const std::string& options, CliResult* out = nullptr) {
        return renderImage(input, dir_.file("image.exr"), std::string(kSize) + " " + options, out);
    }

    TempDir dir_{"caustic-scene"};
    const Image reference_ = readImage(kFolder + "reference.exr");
    const Image mask_ = readImage(kFolder + "caustic-mask.png");
};

TEST_F(CausticScene, CausticsAndPathPartitionEveryLightPath) {
    CliResult result;
    const Image image = render(kFolder + "caustics-path.toml", "--spp 64", &result);
    EXPECT_EQ(result.output.find("warning"), std::string::npos) << result.output;
    const Means test = means(image, mask_), ref = means(reference_, mask_);
    // Measured when this was written: whole image -0.3 % per channel, caustic region -2.4 %
    // (the cone filter's blur at the caustic's edges). The path tracer alone at 64 spp is off by
    // up to 4 % on the caustic region from noise; the caustic pass has none of that noise.
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(test.channel[c] / ref.channel[c], 1.0, 0.02) << "channel " << c;
    EXPECT_NEAR(test.caustic / ref.caustic, 1.0, 0.05);

    // The beauty is the sum of the two passes' layers, to float precision (it is computed so).
    const int caustics = image.channelIndex("caustics.R"), path = image.channelIndex("path.R");
    ASSERT_GE(caustics, 0);
    ASSERT_GE(path, 0);
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(image.at(x, y, c),
                          image.at(x, y, caustics + c) + image.at(x, y, path + c));
        }
    }
}

// Stochastic progressive photon mapping in place of the photon map: the radius shrinks with the
// iterations, so the blur bias at the caustic's edges shrinks too (Hachisuka and Jensen 2009).
TEST_F(CausticScene, ProgressiveCausticsConvergeToTheReference) {
    const std::string script = dir_.file("sppm.toml");
    std::ofstream(script) << "scene = \"" << kFolder << "caustic-spheres.gltf\"\n"
                          << "[[pass]]\ntype = \"caustics\"\nmethod = \"progressive\"\n"
                          << "iterations = 64\nphotons_per_iteration = 20000\n"
                          << "[[pass]]\ntype = \"path\"\n";
    const Image image = render(script, "--spp 64");
    const Means test = means(image, mask_), ref = means(reference_, mask_);
    // Measured when this was written (seed 5): caustic region -1.0 % (the photon map's -2.4 %),
    // whole image -0.3 %.
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(test.channel[c] / ref.channel[c], 1.0, 0.02) << "channel " << c;
    EXPECT_NEAR(test.caustic / ref.caustic, 1.0, 0.03);
}

// The hybrid corrects its solution (docs/light-paths.md, "The hybrid's correction"): what the
// preview misses (below) is traced, and what is left is the caustic map's own bias. Measured at
// 64 spp, seeds 5, 1 and 2: every channel within [-0.4 %, -0.1 %] (the caustics pass with the
// path tracer alone: within 0.3 %). The bound, 0.8 % either way, failed the preview before its
// solution's specular transfer (-1.1 / -0.9 / -0.6 %) and fails a double count of the light the
// correction traces.
TEST_F(CausticScene, HybridConvergesToTheReference) {
    CliResult result;
    const Image image =
        render(kFolder + "caustic-spheres.gltf", "--pipeline hybrid --spp 64", &result);
    EXPECT_EQ(result.output.find("warning"), std::string::npos) << result.output;
    expectRatios(means(image, mask_), means(reference_, mask_), "hybrid", 0.992, 1.008);
}

// The preview takes the solution as it is (hybrid-preview; the hybrid corrects it). The solution
// holds the caustics (the map's photons) and the light its surfaces send through the spheres (its
// specular transfer), so no light path is missing and the planner warns of none; what is left is
// the solution's own error.
TEST_F(CausticScene, HybridPreviewIsWithinTheSolutionsError) {
    CliResult result;
    const Image image =
        render(kFolder + "caustic-spheres.gltf", "--pipeline hybrid-preview --spp 32", &result);
    EXPECT_EQ(result.output.find("warning"), std::string::npos) << result.output;
    const Means test = means(image, mask_), ref = means(reference_, mask_);
    // The radiosity solution's own error: its Cornell faces within [-2.6 %, +1.7 %], mostly low.
    // Measured: at first whole image -2.9 / -2.7 / -1.8 % (R, G, B), caustic region -3.3 %;
    // without the caustic map at the second diffuse vertex -4.2 / -4.0 / -3.1 %; since the path
    // tracer also brings the light each reuse vertex sees through the spheres (L D S D D E, ...),
    // -1.5 / -1.3 / -0.8 % and caustic -1.0 % (seed 5); since the solution takes the caustic
    // photons (L S D D D E counted), -1.1 / -0.9 / -0.6 %, caustic -0.4 % (seed 5), over seeds
    // 1, 2, 5 and 9 within [-1.1 %, -0.2 %], caustic [-2.1 %, -0.2 %]; since the solution's
    // specular transfer (L D S D D D E counted), -0.25 / -0.29 / -0.30 %, caustic +0.2 % (seed 5),
    // seeds 1, 2 and 9 within [-0.3 %, +0.1 %], caustic [-1.2 %, +0.4 %]. The lower bound is the
    // issue's 2 % for the whole image, the caustic region's its 5 %. Double counting would make
    // the image brighter than the reference: the upper bound is the reference's noise.
    expectRatios(test, ref, "hybrid-preview", 0.98, 1.005);
}

TEST_F(CausticScene, NoCausticPassWithoutSpecularSurfaces) {
    CliResult result;
    const Image image =
        render(kScenes + "cornell-box/cornell-box.gltf", "--pipeline hybrid --spp 1", &result);
    EXPECT_NE(result.output.find("(caustics): skipped: no surface has a specular lobe"),
              std::string::npos)
        << result.output;
    EXPECT_EQ(image.channelIndex("caustics.R"), -1);
}

}  // namespace
}  // namespace penumbra::test
