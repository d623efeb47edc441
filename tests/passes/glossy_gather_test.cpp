// A radiosity solution's light through a polished floor. A corridor whose one end is a lamp (an
// emitting wall) and whose floor is polished dark tiles (a dielectric coat of roughness 0.1 over
// a base of 0.05): seen at grazing angles from the far end, the floor mirrors the lamp (Fresnel
// reflectance about a half at 83 degrees), where a solution that spreads the coat's reflection as
// Lambertian shows it as dark as its tiles. The side walls and the ceiling are black, so the far
// wall's indirect light is mostly that image. The coat is sharp (Bsdf::hasSharpGlossyLobe): by
// default the specular transfer carries its reflection by photons, from the lamp too
// (passes/specular_transfer.h); without the transfer the solution spreads it and its gathers
// follow the lobe (radiosity/gathered_radiance.h). The distribution preview's `indirect` layer
// over the far wall is compared with the path tracer's (an independent estimator).
#include "core/math.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace penumbra::test {
namespace {

constexpr float kHalfWidth = 1.0f;  // the corridor spans [-1, 1] in x, [0, 2] in y
constexpr float kHeight = 2.0f;
constexpr float kLength = 8.0f;  // and [0, 8] in z: the lamp at z = 0, the far wall at z = 8
constexpr int kSize = 48;        // pixels across the far wall
// R_y(180 degrees): the camera looks along +Z, at the far wall.
const Vec4 kLookingAlongZ(0.0f, 1.0f, 0.0f, 0.0f);

void writePolishedCorridor(const std::string& path) {
    GltfBuilder scene;
    const int white = scene.addMaterial({.baseColor = Color(0.8f)});
    const int black = scene.addMaterial({.baseColor = Color(0.0f)});
    const int tiles =
        scene.addMaterial({.baseColor = Color(0.05f), .lambertian = false, .roughness = 0.1f});
    const int lamp = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = 10.0f});
    const float w = kHalfWidth, h = kHeight, d = kLength;
    scene.addQuad({-w, 0, d}, {w, 0, d}, {w, 0, 0}, {-w, 0, 0}, tiles);    // floor, up
    scene.addQuad({-w, h, 0}, {w, h, 0}, {w, h, d}, {-w, h, d}, black);    // ceiling, down
    scene.addQuad({-w, 0, 0}, {-w, 0, d}, {-w, h, d}, {-w, h, 0}, black);  // sides, inwards
    scene.addQuad({w, 0, d}, {w, 0, 0}, {w, h, 0}, {w, h, d}, black);
    scene.addQuad({-w, 0, 0}, {w, 0, 0}, {w, h, 0}, {-w, h, 0}, lamp);   // lamp, +Z
    scene.addQuad({w, 0, d}, {-w, 0, d}, {-w, h, d}, {w, h, d}, white);  // far wall, -Z
    scene.setOrthographicCamera({0, h / 2, d - 1.0f}, kLookingAlongZ, w, h / 2);
    scene.write(path);
}

// The mean luminance of the `indirect` layer over the whole image (the far wall).
double indirectMean(const Image& image) {
    const int r = image.channelIndex("indirect.R");
    EXPECT_GE(r, 0);
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            sum +=
                luminance(Color(image.at(x, y, r), image.at(x, y, r + 1), image.at(x, y, r + 2)));
        }
    }
    return sum / (image.width() * image.height());
}

// The preview's `indirect` layer over the far wall over the path tracer's (1024 spp: its own noise
// over the wall is a few tenths of a percent), with the radiosity pass's `min_element_area` and
// `specular_transfer` as given ("auto" for the defaults).
double previewOverReference(const std::string& minElementArea, const std::string& transfer) {
    TempDir dir("glossy-gather");
    const std::string scene = dir.file("corridor.gltf");
    writePolishedCorridor(scene);
    const std::string script = dir.file("preview.toml");
    std::ofstream(script) << "scene = \"corridor.gltf\"\n"
                          << "[[pass]]\ntype = \"radiosity\"\nmin_element_area = " << minElementArea
                          << "\nspecular_transfer = " << transfer
                          << "\n[[pass]]\ntype = \"distribution\"\n";
    const std::string size = std::to_string(kSize);
    const std::string options =
        " --width " + size + " --height " + size + " --seed 5 --aov indirect";
    const Image preview = renderImage(script, dir.file("distribution.exr"), "--spp 16" + options);
    const Image reference =
        renderImage(scene, dir.file("reference.exr"), "--pipeline reference --spp 1024" + options);
    const double p = indirectMean(preview), r = indirectMean(reference);
    std::printf(
        "min_element_area %s, specular_transfer %s: far wall's indirect light %.4f, "
        "reference %.4f, ratio %.3f\n",
        minElementArea.c_str(), transfer.c_str(), p, r, p / r);
    return p / r;
}

// At the defaults the far wall shows 1.003 of the reference's indirect light: the photons land
// where the floor sends the lamp's image. Without the transfer, the gathers alone following the
// lobe, 1.14 (0.06 when they too spread the coat as Lambertian): the far wall's leaves are large
// (nothing in the links' transfer asks to refine them), and the corners' values, linear over each
// leaf, overshoot a profile that rises fast towards the floor, where the grazing floor mirrors
// nearly all it sees (the preview's rows: 1.2-1.5 in the lower half, 0.8-0.9 in the upper);
// finer elements take the interpolation's share away: 1.07 at 0.001 m², 0.995 at 0.0003 m².
// Bounds: the issue's 3 % for the preview at its defaults and for the gathers at the finest mesh
// (the estimators' own bias would show there; the path tracer's noise and the gathers' are under
// 1 %); 20 % for the gathers at the default mesh (its 14 % and the preview's seed-to-seed spread,
// under 1 %).
TEST(GlossyGather, TheFarWallSeesTheLampInThePolishedFloor) {
    EXPECT_NEAR(previewOverReference("\"auto\"", "\"auto\""), 1.0, 0.03);
    EXPECT_NEAR(previewOverReference("\"auto\"", "\"exclude\""), 1.0, 0.2);
    EXPECT_NEAR(previewOverReference("0.0003", "\"exclude\""), 1.0, 0.03);
}

}  // namespace
}  // namespace penumbra::test
