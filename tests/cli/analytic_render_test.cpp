// Analytic scenes rendered end to end through the command line: the renderer, the loader, the
// units and the EXR output must together reproduce closed-form radiance values.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra::test {
namespace {

// Orthographic camera looking straight down (-Y): rotation of -90 degrees about +X.
const Vec4 kLookDown{-std::sqrt(0.5f), 0.0f, 0.0f, std::sqrt(0.5f)};

// A large Lambertian floor at y = 0 facing +Y.
void addFloor(GltfBuilder& scene, int material, float halfSize) {
    scene.addQuad({-halfSize, 0, -halfSize}, {-halfSize, 0, halfSize}, {halfSize, 0, halfSize},
                  {halfSize, 0, -halfSize}, material);
}

Image render(const GltfBuilder& scene, const TempDir& dir, const std::string& options) {
    scene.write(dir.file("scene.gltf"));
    const CliResult result = runPenumbra("render " + dir.file("scene.gltf") + " -o " +
                                         dir.file("out.exr") + " --quiet " + options);
    EXPECT_EQ(result.status, 0) << result.output;
    return readImage(dir.file("out.exr"));
}

TEST(AnalyticRender, PointLightOverLambertianFloor) {
    // L = rho I / (pi h^2) directly below a point light of I candela at height h.
    constexpr float kRho = 0.5f, kIntensity = 100.0f, kHeight = 2.0f;
    GltfBuilder scene;
    addFloor(scene, scene.addMaterial({.baseColor = Color(kRho)}), 50.0f);
    scene.addLight({.type = "point", .intensity = kIntensity, .position = {0, kHeight, 0}});
    // 1 cm field of view: the cos^3 falloff across it is below 1e-4.
    scene.setOrthographicCamera({0, 5, 0}, kLookDown, 0.005f, 0.005f);
    TempDir dir("point-light");
    const Image image = render(scene, dir, "--width 16 --height 16 --spp 4");
    const double expected = kRho * kIntensity / (kPi * kHeight * kHeight);
    // The estimate has no noise here (one delta light, no other surface to bounce from), so 1 %
    // is the bound with a wide margin for float rounding.
    EXPECT_NEAR(luminanceMean(image), expected, 0.01 * expected);
}

// The `illuminance` AOV reads what a light meter lying on the floor reads, E = I / h² below a
// point light whatever the floor's albedo, in the path tracer and the radiosity view; the
// `luminance` AOV is the beauty's Rec. 709 luminance.
TEST(AnalyticRender, IlluminanceAndLuminanceLayersUnderAPointLight) {
    constexpr float kRho = 0.3f, kIntensity = 100.0f, kHeight = 2.0f;
    GltfBuilder scene;
    addFloor(scene, scene.addMaterial({.baseColor = Color(kRho)}), 50.0f);
    scene.addLight({.type = "point", .intensity = kIntensity, .position = {0, kHeight, 0}});
    scene.setOrthographicCamera({0, 5, 0}, kLookDown, 0.005f, 0.005f);
    const double lux = kIntensity / (kHeight * kHeight);
    for (const char* pipeline : {"reference", "radiosity"}) {
        SCOPED_TRACE(pipeline);
        TempDir dir("illuminance-aov");
        const Image image = render(scene, dir,
                                   std::string("--width 8 --height 8 --spp 4 --aov "
                                               "illuminance,luminance --pipeline ") +
                                       pipeline);
        const int E = image.channelIndex("illuminance.G"), Y = image.channelIndex("luminance.Y");
        ASSERT_GE(E, 0);
        ASSERT_GE(Y, 0);
        // Next-event estimation of one delta light with nothing to bounce from: no noise; the
        // radiosity view's sensor reads the light itself the same way.
        EXPECT_NEAR(regionMean(image, E, 0, 0, 8, 8), lux, 1e-3 * lux);
        for (int y = 0; y < 8; ++y) {
            for (int x = 0; x < 8; ++x) {
                const float luminance = 0.2126f * image.at(x, y, 0) + 0.7152f * image.at(x, y, 1) +
                                        0.0722f * image.at(x, y, 2);
                EXPECT_NEAR(image.at(x, y, Y), luminance, 1e-5f * luminance);
            }
        }
    }
}

// Form factor from a differential area to a parallel rectangle a x b at distance c, the area
// element facing it below one corner (Howell's catalogue, configuration B-3).
double cornerFormFactor(double a, double b, double c) {
    const double x = a / c, y = b / c;
    const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * M_PI);
}

TEST(AnalyticRender, RectangularEmitterOverLambertianFloor) {
    // L = rho Le F with F the form factor from the floor point to the emitter.
    constexpr float kRho = 0.5f, kLe = 10.0f, kSide = 1.0f, kHeight = 1.0f;
    GltfBuilder scene;
    addFloor(scene, scene.addMaterial({.baseColor = Color(kRho)}), 50.0f);
    const int emitter = scene.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = kLe});
    const float s = kSide / 2;
    // Facing down (-Y): counter-clockwise seen from below.
    scene.addQuad({-s, kHeight, -s}, {s, kHeight, -s}, {s, kHeight, s}, {-s, kHeight, s}, emitter);
    scene.setOrthographicCamera({0, 0.5f, 0}, kLookDown, 0.005f, 0.005f);
    TempDir dir("rect-emitter");
    const Image image = render(scene, dir, "--width 32 --height 32 --spp 64");
    const double F = 4.0 * cornerFormFactor(s, s, kHeight);
    const double expected = kRho * kLe * F;
    // 65536 light samples of a square seen under ~50 degrees: relative standard error of the
    // mean below 0.2 %, so 1 % is a 5-sigma bound.
    EXPECT_NEAR(luminanceMean(image), expected, 0.01 * expected);
}

TEST(AnalyticRender, ClosedFurnaceBoxGivesLeOverOneMinusRho) {
    // Every wall emits Le and reflects rho: L = Le / (1 - rho) everywhere (the radiosity
    // equation of a closed uniform enclosure).
    constexpr float kRho = 0.8f, kLe = 1.0f;
    GltfBuilder scene;
    const int wall = scene.addMaterial(
        {.baseColor = Color(kRho), .emissive = Color(1.0f), .emissiveStrength = kLe});
    // Cube [-1, 1]^3, all faces counter-clockwise seen from inside.
    const Vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    scene.addQuad(c[0], c[1], c[2], c[3], wall);  // z = -1, faces +z
    scene.addQuad(c[5], c[4], c[7], c[6], wall);  // z = +1, faces -z
    scene.addQuad(c[4], c[0], c[3], c[7], wall);  // x = -1, faces +x
    scene.addQuad(c[1], c[5], c[6], c[2], wall);  // x = +1, faces -x
    scene.addQuad(c[4], c[5], c[1], c[0], wall);  // y = -1, faces +y
    scene.addQuad(c[3], c[2], c[6], c[7], wall);  // y = +1, faces -y
    scene.setPerspectiveCamera({0, 0, 0.5f}, {0, 0, 0, 1}, 1.2f);
    TempDir dir("furnace");
    const Image image = render(scene, dir, "--width 32 --height 32 --spp 64");
    const double expected = kLe / (1.0 - kRho);
    EXPECT_NEAR(luminanceMean(image), expected, 0.01 * expected);
    // Everywhere: each 8 x 8 block (4096 paths) within 3 %. The per-path relative standard
    // deviation measured at this setting is about 0.6, so a block's is about 0.9 %: 3 % is a
    // 3-sigma bound over 16 blocks.
    for (int by = 0; by < 4; ++by) {
        for (int bx = 0; bx < 4; ++bx) {
            const double block = regionMean(image, 1, 8 * bx, 8 * by, 8 * bx + 8, 8 * by + 8);
            EXPECT_NEAR(block, expected, 0.03 * expected) << "block " << bx << "," << by;
        }
    }
}

}  // namespace
}  // namespace penumbra::test
