// Light groups (`render --light-groups`): a layer per group of sources, each against the closed
// form of its sources alone (the inverse-square law of a point light, E_n cos(zenith) of the sun,
// the sky's given horizontal illuminance), the layers summing to the beauty, in the path tracer
// and in the pipelines that reuse a radiosity solution.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/csv_table.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

namespace penumbra::test {
namespace {

constexpr float kAlbedo = 0.5f;
constexpr float kHalfSize = 2.0f;  // the floor spans [-2, 2] in x and z
constexpr int kSize = 64;          // pixels across the floor
// R_x(-90 degrees): the camera looks down -Y, the image's right along +X and its top along -Z.
const Vec4 kLookingDown(-std::sqrt(0.5f), 0.0f, 0.0f, std::sqrt(0.5f));

const TestLight kLightA{
    .type = "point", .name = "A", .intensity = 100.0f, .position = {-1, 1, 0.5f}};
const TestLight kLightB{.type = "point",
                        .name = "B",
                        .color = Color(1.0f, 0.0f, 0.0f),
                        .intensity = 50.0f,
                        .position = {1, 2, -0.5f}};

// A Lambertian floor filling an orthographic view from above, so that pixel (x, y) sees the
// floor point pixelPoint(x, y) and nothing but the floor.
GltfBuilder floorSeenFromAbove() {
    GltfBuilder scene;
    const int grey = scene.addMaterial({.baseColor = Color(kAlbedo)});
    const float s = kHalfSize;
    scene.addQuad({-s, 0, s}, {s, 0, s}, {s, 0, -s}, {-s, 0, -s}, grey);
    scene.setOrthographicCamera({0, 10, 0}, kLookingDown, s, s);
    return scene;
}

// The floor under lights A and B, written to `path`.
void writeFloorUnderBothLights(const std::string& path) {
    GltfBuilder scene = floorSeenFromAbove();
    scene.addLight(kLightA);
    scene.addLight(kLightB);
    scene.write(path);
}

Vec3 pixelPoint(int x, int y) {
    const float step = 2.0f * kHalfSize / kSize;
    return Vec3(-kHalfSize + (float(x) + 0.5f) * step, 0.0f, -kHalfSize + (float(y) + 0.5f) * step);
}

// The radiance of the Lambertian floor at p under a point light: (rho / pi) I cos(theta) / d².
double pointLightRadiance(const TestLight& light, const Vec3& p) {
    const Vec3 d = light.position - p;
    const double distance = glm::length(d);
    return kAlbedo / std::numbers::pi * light.intensity * (d.y / distance) / (distance * distance);
}

int channel(const Image& image, const std::string& name) {
    const int c = image.channelIndex(name);
    EXPECT_GE(c, 0) << name << " missing";
    return c;
}

// Every pixel of the beauty equals the sum of the groups' layers (float rounding only).
void expectLayersSumToBeauty(const Image& image, const std::vector<std::string>& groups) {
    for (const char* c : {"R", "G", "B"}) {
        double largest = 0.0, worst = 0.0;
        for (int y = 0; y < image.height(); ++y) {
            for (int x = 0; x < image.width(); ++x) {
                double sum = 0.0;
                for (const std::string& group : groups)
                    sum += image.at(x, y, channel(image, "light." + group + "." + c));
                const double beauty = image.at(x, y, channel(image, c));
                largest = std::max(largest, std::abs(beauty));
                worst = std::max(worst, std::abs(beauty - sum));
            }
        }
        EXPECT_LE(worst, 1e-5 * largest) << c;
    }
}

TEST(LightGroups, EachPointLightHasItsOwnLayer) {
    TempDir dir("light-groups-points");
    writeFloorUnderBothLights(dir.file("scene.gltf"));
    const std::string size =
        " --width " + std::to_string(kSize) + " --height " + std::to_string(kSize);
    CliResult run;
    const Image image = renderImage(dir.file("scene.gltf"), dir.file("groups.exr"),
                                    "--light-groups --filter box --spp 64" + size, &run);
    // The path tracer files both groups in one render.
    EXPECT_NE(run.output.find("light groups, in one render: light-A, light-B"), std::string::npos)
        << run.output;
    expectLayersSumToBeauty(image, {"light-A", "light-B"});
    // Delta lights over an open floor: next-event estimation is exact; what is left is the box
    // filter's mean over a 6-cm pixel from 64 stratified samples against its centre's value
    // (measured 0.1 % at worst, where I h / d³ changes by 9 % across a pixel).
    double worstA = 0.0, worstB = 0.0, leakB = 0.0;
    for (int y = 0; y < kSize; ++y) {
        for (int x = 0; x < kSize; ++x) {
            const Vec3 p = pixelPoint(x, y);
            const double a = pointLightRadiance(kLightA, p), b = pointLightRadiance(kLightB, p);
            worstA = std::max(worstA,
                              std::abs(image.at(x, y, channel(image, "light.light-A.G")) / a - 1));
            worstB = std::max(worstB,
                              std::abs(image.at(x, y, channel(image, "light.light-B.R")) / b - 1));
            leakB = std::max(leakB, double(image.at(x, y, channel(image, "light.light-B.G"))));
        }
    }
    EXPECT_LT(worstA, 0.005);
    EXPECT_LT(worstB, 0.005);
    EXPECT_EQ(leakB, 0.0);  // B is red

    ImageMetadata metadata;
    readImage(dir.file("groups.exr"), &metadata);
    const ImageMetadata::Value* groups = metadata.find("penumbra:light_groups");
    ASSERT_NE(groups, nullptr);
    EXPECT_EQ(std::get<std::string>(*groups), "light-A light-B");
}

// The pipelines that reuse a radiosity solution take the groups too: each solution is lit by its
// group alone (the solution is linear in its sources).
TEST(LightGroups, EveryPipelineSplitsItsLight) {
    TempDir dir("light-groups-pipelines");
    writeFloorUnderBothLights(dir.file("scene.gltf"));
    double meanA = 0.0, meanB = 0.0;
    for (int y = 0; y < 16; ++y) {
        for (int x = 0; x < 16; ++x) {
            const Vec3 p = pixelPoint(4 * x + 2, 4 * y + 2);
            meanA += pointLightRadiance(kLightA, p) / 256.0;
            meanB += pointLightRadiance(kLightB, p) / 256.0;
        }
    }
    for (const char* pipeline : {"distribution", "hybrid", "radiosity"}) {
        SCOPED_TRACE(pipeline);
        const Image image = renderImage(
            dir.file("scene.gltf"), dir.file(std::string(pipeline) + ".exr"),
            std::string("--quiet --light-groups --width 16 --height 16 --spp 4 --pipeline ") +
                pipeline);
        expectLayersSumToBeauty(image, {"light-A", "light-B"});
        // 2 %: the mean of 16 x 16 pixel centres against the pixels' means (0.3 % here), and the
        // radiosity view's corners, which interpolate the direct light within 1 %.
        EXPECT_NEAR(regionMean(image, channel(image, "light.light-A.G"), 0, 0, 16, 16), meanA,
                    0.02 * meanA);
        EXPECT_NEAR(regionMean(image, channel(image, "light.light-B.R"), 0, 0, 16, 16), meanB,
                    0.02 * meanB);
    }
}

// The sun and the sky are groups of their own. At the June solstice's solar noon on the prime
// meridian at latitude 53.44°, the sun's zenith is the latitude less the declination, 23.44°:
// 30.00° (within 0.01° a minute either side of the meridian).
TEST(LightGroups, TheSunAndTheSkyAreSplit) {
    TempDir dir("light-groups-daylight");
    floorSeenFromAbove().write(dir.file("scene.gltf"));
    const double sunNormal = 80000.0, skyHorizontal = 10000.0;
    const Image image =
        renderImage(dir.file("scene.gltf"), dir.file("daylight.exr"),
                    "--quiet --light-groups --width 32 --height 32 --spp 16 --sky cie-clear "
                    "--sky-illuminance 10000 --site 53.44,0 --time 2026-06-21T12:02+00:00 "
                    "--sun-direct-normal 80000");
    expectLayersSumToBeauty(image, {"sky", "sun"});
    const double sun =
        kAlbedo / std::numbers::pi * sunNormal * std::cos(30.0 * std::numbers::pi / 180.0);
    const double sky = kAlbedo / std::numbers::pi * skyHorizontal;
    // The sun's disc (0.53°) changes cos(zenith) by under 0.3 % across it; the sky's samples
    // (32 x 32 x 16) leave a standard error of its mean well under 1 %.
    EXPECT_NEAR(regionMean(image, channel(image, "light.sun.G"), 0, 0, 32, 32), sun, 0.005 * sun);
    EXPECT_NEAR(regionMean(image, channel(image, "light.sky.G"), 0, 0, 32, 32), sky, 0.02 * sky);
}

// `penumbra illuminance --light-groups`: a column pair per group, each point light's own
// I cos(theta) / d² (a grey floor under two point lights reflects nothing back up), their sum in
// illuminance_lux.
TEST(LightGroups, IlluminanceHasAColumnPerGroup) {
    TempDir dir("light-groups-illuminance");
    writeFloorUnderBothLights(dir.file("scene.gltf"));
    std::ofstream(dir.file("points.csv")) << "0,0,0,0,1,0\n1.5,0,-1,0,1,0\n";
    const CliResult r = runPenumbra("illuminance " + dir.file("scene.gltf") + " --points " +
                                    dir.file("points.csv") + " -o " + dir.file("lux.csv") +
                                    " --light-groups --spp 4 --quiet");
    ASSERT_EQ(r.status, 0) << r.output;
    const CsvTable table = readCsvTable(dir.file("lux.csv"));
    EXPECT_EQ(
        table.header,
        "x,y,z,nx,ny,nz,illuminance_lux,stderr_lux,illuminance_lux_light-A,stderr_lux_light-A,"
        "illuminance_lux_light-B,stderr_lux_light-B");
    ASSERT_EQ(table.rows.size(), 2u);
    for (const std::vector<double>& row : table.rows) {
        ASSERT_EQ(row.size(), 12u);
        const Vec3 p{float(row[0]), float(row[1]), float(row[2])};
        // Lux is the Rec. 709 luminance of the irradiance: B is red, Y = 0.2126 of it.
        const double a = pointLightRadiance(kLightA, p) * std::numbers::pi / kAlbedo;
        const double b = 0.2126 * pointLightRadiance(kLightB, p) * std::numbers::pi / kAlbedo;
        EXPECT_NEAR(row[8], a, 1e-4 * a);
        EXPECT_NEAR(row[10], b, 1e-4 * b);
        EXPECT_NEAR(row[6], row[8] + row[10], 1e-6 * row[6]);
    }
}

TEST(LightGroups, ASceneWithoutLightIsRefused) {
    TempDir dir("light-groups-dark");
    floorSeenFromAbove().write(dir.file("scene.gltf"));
    const CliResult r = runPenumbra("render " + dir.file("scene.gltf") + " -o " +
                                    dir.file("dark.exr") + " --light-groups --quiet");
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_NE(r.output.find("--light-groups"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir.file("dark.exr")));
}

}  // namespace
}  // namespace penumbra::test
