// The environment light end to end, through the command line and every pipeline: closed forms
// of a convex body under a uniform sky (every point sees a whole hemisphere of it) and of a floor
// lit through an opening (the form factor of the opening), the map's orientation and rotation,
// and the ways of attaching one (option, pass script, a converted scene's extras).
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/csv_table.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace penumbra::test {
namespace {

constexpr float kRho = 0.5f;

// An equirectangular map of W x H pixels, value(u, v) at each pixel centre, as an EXR.
template <typename Value>
void writeMap(const std::string& path, int width, int height, const Value& value) {
    Image map(width, height, {"R", "G", "B"});
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const Color c = value((x + 0.5f) / width, (y + 0.5f) / height);
            for (int ch = 0; ch < 3; ++ch)
                map.at(x, y, ch) = c[ch];
        }
    }
    writeImage(path, map, {}, ImageMetadata{}, ToneMapping{});
}

// The unit cube [-1, 1]^3, counter-clockwise seen from outside.
void addCube(GltfBuilder& scene, int material) {
    const Vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    scene.addQuad(c[3], c[2], c[1], c[0], material);  // z = -1, faces -z
    scene.addQuad(c[4], c[5], c[6], c[7], material);  // z = +1, faces +z
    scene.addQuad(c[7], c[3], c[0], c[4], material);  // x = -1, faces -x
    scene.addQuad(c[1], c[2], c[6], c[5], material);  // x = +1, faces +x
    scene.addQuad(c[0], c[1], c[5], c[4], material);  // y = -1, faces -y
    scene.addQuad(c[7], c[6], c[2], c[3], material);  // y = +1, faces +y
}

// An orthographic camera 5 m from the origin along `axis` (+z, +x or -x), looking back at it and
// seeing a 1 m square of the cube's face: rotations about +Y turning -Z (the camera's view) to
// -axis.
void lookAtFace(GltfBuilder& scene, const Vec3& axis) {
    const float h = std::sqrt(0.5f);
    const Vec4 rotation = axis.z > 0.0f   ? Vec4(0, 0, 0, 1)
                          : axis.x > 0.0f ? Vec4(0, h, 0, h)
                                          : Vec4(0, -h, 0, h);
    scene.setOrthographicCamera(axis * 5.0f, rotation, 0.5f, 0.5f);
}

Image renderWith(const GltfBuilder& scene, const TempDir& dir, const std::string& options) {
    scene.write(dir.file("scene.gltf"));
    return renderImage(dir.file("scene.gltf"), dir.file("out.exr"), "--quiet " + options);
}

class UniformSky : public testing::TestWithParam<const char*> {};

// A convex Lambertian body under a uniform environment L: every point of it sees L over its
// whole hemisphere and nothing else, so its radiance is rho L exactly, in every pipeline (the
// light paths L D E, which every pipeline counts).
TEST_P(UniformSky, AConvexBodyReflectsRhoL) {
    constexpr float kL = 2.0f;
    TempDir dir("uniform-sky");
    writeMap(dir.file("sky.exr"), 64, 32, [](float, float) { return Color(kL); });
    GltfBuilder scene;
    addCube(scene, scene.addMaterial({.baseColor = Color(kRho)}));
    lookAtFace(scene, {0, 0, 1});
    const Image image = renderWith(scene, dir,
                                   "--environment " + dir.file("sky.exr") +
                                       " --width 16 --height 16 --spp 64 --pipeline " + GetParam());
    const double expected = kRho * kL;
    // Measured: 1.00001 of it in the tracers (16 384 samples; next-event estimation of a uniform
    // sky with MIS has little variance on a face that sees a whole hemisphere of it), 0.9984 in
    // the radiosity view (64 fixed directions of each strategy at its corners). 2 % bounds both.
    EXPECT_NEAR(luminanceMean(image), expected, 0.02 * expected);
}

// Form factor from a differential area to a parallel rectangle a x b at distance c, the area
// element facing it below one corner (Howell's catalogue, configuration B-3).
double cornerFormFactor(double a, double b, double c) {
    const double x = a / c, y = b / c;
    const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * M_PI);
}

// The form factor from a floor point (x, z) below a horizontal rectangle [x0, x1] x [z0, z1] at
// height c, the point's projection inside it: the four rectangles the projection cuts it into.
double formFactorBelow(double x, double z, double x0, double x1, double z0, double z1, double c) {
    return cornerFormFactor(x - x0, z - z0, c) + cornerFormFactor(x1 - x, z - z0, c) +
           cornerFormFactor(x - x0, z1 - z, c) + cornerFormFactor(x1 - x, z1 - z, c);
}

// A room of black walls and ceiling with a square opening in the ceiling, under a uniform sky
// L: the floor below the opening sees the sky only through it, so its radiance is rho L F, F the
// form factor from the floor point to the opening (the sky's light through a roof light; nothing
// else reflects). Compared on the mean over the floor below the opening, whose closed form is
// integrated here by the midpoint rule (a 200 x 200 grid: its error is below 1e-5).
TEST_P(UniformSky, AFloorUnderAnOpeningReflectsRhoLF) {
    constexpr float kL = 10.0f, kHalf = 2.0f, kHeight = 1.0f, kOpening = 0.5f;
    TempDir dir("opening");
    writeMap(dir.file("sky.exr"), 64, 32, [](float, float) { return Color(kL); });
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(kRho)});
    const int black = scene.addMaterial({.baseColor = Color(0.0f)});
    const float h = kHalf, y = kHeight, o = kOpening;
    scene.addQuad({-h, 0, -h}, {-h, 0, h}, {h, 0, h}, {h, 0, -h}, floor);
    // The walls, facing in.
    scene.addQuad({-h, 0, -h}, {h, 0, -h}, {h, y, -h}, {-h, y, -h}, black);
    scene.addQuad({h, 0, h}, {-h, 0, h}, {-h, y, h}, {h, y, h}, black);
    scene.addQuad({-h, 0, h}, {-h, 0, -h}, {-h, y, -h}, {-h, y, h}, black);
    scene.addQuad({h, 0, -h}, {h, 0, h}, {h, y, h}, {h, y, -h}, black);
    // The ceiling around the opening, facing down.
    scene.addQuad({-h, y, -h}, {h, y, -h}, {h, y, -o}, {-h, y, -o}, black);
    scene.addQuad({-h, y, o}, {h, y, o}, {h, y, h}, {-h, y, h}, black);
    scene.addQuad({-h, y, -o}, {-o, y, -o}, {-o, y, o}, {-h, y, o}, black);
    scene.addQuad({o, y, -o}, {h, y, -o}, {h, y, o}, {o, y, o}, black);
    // Looking straight down at the floor below the opening from inside the room.
    scene.setOrthographicCamera({0, 0.5f, 0}, {-std::sqrt(0.5f), 0, 0, std::sqrt(0.5f)}, o, o);
    const Image image =
        renderWith(scene, dir,
                   "--environment " + dir.file("sky.exr") +
                       " --width 16 --height 16 --spp 256 --pipeline " + GetParam());
    constexpr int kGrid = 200;
    double F = 0.0;
    for (int i = 0; i < kGrid; ++i) {
        for (int j = 0; j < kGrid; ++j) {
            const double x = -o + 2.0 * o * (i + 0.5) / kGrid, z = -o + 2.0 * o * (j + 0.5) / kGrid;
            F += formFactorBelow(x, z, -o, o, -o, o, y);
        }
    }
    const double expected = kRho * kL * F / (kGrid * kGrid);
    // Measured: 0.9964 in the tracers (65 536 samples of a sky seen through a quarter of the
    // hemisphere's cosine weight: a relative standard error of about 0.6 %), 0.992 in the
    // radiosity view (its corners' fixed directions and the refinement they drive, shown_direct.h).
    // 2 % is over three standard errors of the tracers and twice the view's error.
    EXPECT_NEAR(luminanceMean(image), expected, 0.02 * expected);
}

INSTANTIATE_TEST_SUITE_P(EveryPipeline, UniformSky,
                         testing::Values("reference", "distribution", "hybrid", "hybrid-preview",
                                         "radiosity"));

// A map lit on its left half (u < 1/2: the map's directions with x > 0) and black on the right.
Color leftHalf(float u, float) {
    return u < 0.5f ? Color(2.0f) : Color(0.0f);
}

// A face sees the lit half of the sky over its whole hemisphere (rho L), over half of it
// (rho L / 2, the dividing plane containing its normal) or not at all.
struct Lighting {
    Vec3 face;            // the cube face the camera looks at
    std::string options;  // what turns the map
    float expectedShare;  // of rho L
};

class HalfLitSky : public testing::TestWithParam<Lighting> {};

TEST_P(HalfLitSky, TurnsAsTheOptionsSay) {
    TempDir dir("half-sky");
    writeMap(dir.file("sky.exr"), 64, 32, leftHalf);
    GltfBuilder scene;
    addCube(scene, scene.addMaterial({.baseColor = Color(kRho)}));
    lookAtFace(scene, GetParam().face);
    const Image image = renderWith(scene, dir,
                                   "--environment " + dir.file("sky.exr") +
                                       " --width 8 --height 8 --spp 64 " + GetParam().options);
    const double expected = kRho * 2.0 * GetParam().expectedShare;
    // 4 096 samples of a sky that lights half of the directions or none: 2 % of rho L.
    EXPECT_NEAR(luminanceMean(image), expected, 0.02 * kRho * 2.0);
}

// The map's left half looks along +X; turned by -90 degrees (clockwise seen from above) +X goes to
// +Z (R_y(-90) (1, 0, 0) = (0, 0, 1)), by +90 to -Z; the scale multiplies.
INSTANTIATE_TEST_SUITE_P(Orientations, HalfLitSky,
                         testing::Values(Lighting{{1, 0, 0}, "", 1.0f},
                                         Lighting{{-1, 0, 0}, "", 0.0f},
                                         Lighting{{0, 0, 1}, "", 0.5f},
                                         Lighting{{0, 0, 1}, "--environment-rotation -90", 1.0f},
                                         Lighting{{0, 0, 1}, "--environment-rotation 90", 0.0f},
                                         Lighting{{-1, 0, 0}, "--environment-rotation 90", 0.5f},
                                         Lighting{{-1, 0, 0}, "--environment-rotation 180", 1.0f},
                                         Lighting{{1, 0, 0}, "--environment-scale 3", 3.0f}));

// A converted Mitsuba scene records its envmap in the scene's extras, with the map's toWorld:
// R_y(-90) there is what --environment-rotation -90 does, and the file is found next to the glTF.
TEST(EnvironmentFromExtras, ReadsTheConvertedSceneRecord) {
    TempDir dir("extras");
    writeMap(dir.file("sky.exr"), 64, 32, leftHalf);
    GltfBuilder scene;
    addCube(scene, scene.addMaterial({.baseColor = Color(kRho)}));
    lookAtFace(scene, {0, 0, 1});
    scene.setSceneExtras(
        R"({"mitsuba_environment": [{"type": "envmap", "file": "sky.exr", "scale": 1.5,
            "toWorld_rowmajor": [0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1]}]})");
    const Image image = renderWith(scene, dir, "--width 8 --height 8 --spp 64");
    EXPECT_NEAR(luminanceMean(image), kRho * 2.0 * 1.5, 0.02 * kRho * 2.0 * 1.5);
    // The options adjust the scene's own environment: turned back, the +Z face sees half of it.
    const Image turned = renderWith(scene, dir,
                                    "--width 8 --height 8 --spp 64 "
                                    "--environment-rotation 90");
    EXPECT_NEAR(luminanceMean(turned), kRho * 1.5, 0.02 * kRho * 2.0 * 1.5);
}

// A pass script attaches an environment by its own keys, relative to the script.
TEST(EnvironmentFromScript, TakesTheScriptsKeys) {
    TempDir dir("script");
    writeMap(dir.file("sky.exr"), 64, 32, [](float, float) { return Color(1.0f); });
    GltfBuilder scene;
    addCube(scene, scene.addMaterial({.baseColor = Color(kRho)}));
    lookAtFace(scene, {0, 0, 1});
    scene.write(dir.file("scene.gltf"));
    std::ofstream(dir.file("script.toml")) << "scene = \"scene.gltf\"\n"
                                              "environment = \"sky.exr\"\n"
                                              "environment_scale = 4\n"
                                              "width = 8\nheight = 8\nspp = 64\n"
                                              "[[pass]]\ntype = \"path\"\n";
    const Image image = renderImage(dir.file("script.toml"), dir.file("out.exr"), "--quiet");
    EXPECT_NEAR(luminanceMean(image), kRho * 4.0, 0.02 * kRho * 4.0);
    // A sky by the script's keys: a uniform sky of E_h = pi L has luminance L = 2 here.
    std::ofstream(dir.file("sky.toml")) << "scene = \"scene.gltf\"\n"
                                           "sky = \"uniform\"\n"
                                           "sky_illuminance = 6.2831853\n"
                                           "width = 8\nheight = 8\nspp = 64\n"
                                           "[[pass]]\ntype = \"path\"\n";
    const Image sky = renderImage(dir.file("sky.toml"), dir.file("sky-render.exr"), "--quiet");
    // The cube's face sees half of its hemisphere's sky and half of the ground's 0.2 E_h / pi.
    const double expected = kRho * (0.5 * 2.0 + 0.5 * 0.2 * 2.0);
    EXPECT_NEAR(luminanceMean(sky), expected, 0.02 * expected);
}

// Skies (core/sky.h) from the command line. Looking straight down on a floor open to the sky of
// unobstructed horizontal illuminance E_h, the floor's radiance is rho E_h / pi whatever the sky's
// distribution; looking up, the CIE overcast sky's zenith luminance is 9 E_h / (7 pi) (its
// E_h = 7 pi L_z / 9); a face looking down sees only the ground, of luminance R E_h / pi.
class Skies : public testing::TestWithParam<const char*> {};

TEST_P(Skies, LightAnOpenFloorWithTheirIlluminance) {
    constexpr float kIlluminance = 5000.0f;
    TempDir dir("sky-floor");
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(kRho)});
    scene.addQuad({-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}, floor);
    scene.setOrthographicCamera({0, 1, 0}, {-std::sqrt(0.5f), 0, 0, std::sqrt(0.5f)}, 0.005f,
                                0.005f);
    const Image image =
        renderWith(scene, dir,
                   std::string("--sky ") + GetParam() + " --sky-illuminance " +
                       std::to_string(kIlluminance) + " --width 8 --height 8 --spp 256");
    const double expected = kRho * kIlluminance / kPi;
    // 16 384 samples of a smooth sky over a whole hemisphere, with MIS: well below 1 % of noise;
    // the map's own quadrature error (512 rows) is below 1e-4.
    EXPECT_NEAR(luminanceMean(image), expected, 0.01 * expected);
}

INSTANTIATE_TEST_SUITE_P(EveryModel, Skies,
                         testing::Values("uniform", "cie-overcast", "cie:1", "cie:3", "cie:5"));

TEST(Skies, OvercastZenithAndGround) {
    constexpr float kIlluminance = 7000.0f, kGround = 0.3f;
    TempDir dir("sky-zenith");
    GltfBuilder scene;
    const int grey = scene.addMaterial({.baseColor = Color(kRho)});
    // A small square at 1 m facing down, and the camera below it looking up past its side.
    scene.addQuad({-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0.5f, 1, 0.5f}, {-0.5f, 1, 0.5f}, grey);
    const Vec4 lookUp{std::sqrt(0.5f), 0, 0, std::sqrt(0.5f)};
    const std::string sky = "--sky cie-overcast --sky-illuminance " + std::to_string(kIlluminance) +
                            " --ground-reflectance " + std::to_string(kGround) +
                            " --width 8 --height 8 --spp 64";
    scene.setOrthographicCamera({3, 0, 0}, lookUp, 0.005f, 0.005f);
    const Image zenith = renderWith(scene, dir, sky);
    EXPECT_NEAR(luminanceMean(zenith), 9.0 * kIlluminance / (7.0 * kPi),
                1e-3 * 9.0 * kIlluminance / (7.0 * kPi));
    scene.setOrthographicCamera({0, 0, 0}, lookUp, 0.005f, 0.005f);
    const Image underside = renderWith(scene, dir, sky);
    const double ground = kRho * kGround * kIlluminance / kPi;
    EXPECT_NEAR(luminanceMean(underside), ground, 0.01 * ground);
}

// --environment-illuminance scales a map so that an upward plane in the open gets that many lux,
// whatever the map's distribution: a sensor in the open (penumbra illuminance) reads it.
TEST(EnvironmentInput, IlluminanceSetsTheScale) {
    TempDir dir("environment-illuminance");
    writeMap(dir.file("sky.exr"), 64, 32, [](float u, float v) {
        return v < 0.5f ? Color(1.0f + 3.0f * u, 2.0f, 0.5f + v) : Color(0.1f);
    });
    GltfBuilder scene;
    scene.addQuad({-0.1f, -100, 0.1f}, {0.1f, -100, 0.1f}, {0.1f, -100, -0.1f},
                  {-0.1f, -100, -0.1f}, scene.addMaterial({}));
    scene.write(dir.file("scene.gltf"));
    std::ofstream(dir.file("points.csv")) << "0,0,0,0,1,0\n";
    const CliResult result = runPenumbra("illuminance " + dir.file("scene.gltf") + " --points " +
                                         dir.file("points.csv") + " -o " + dir.file("out.csv") +
                                         " --quiet --spp 4096 --environment " +
                                         dir.file("sky.exr") + " --environment-illuminance 5000");
    ASSERT_EQ(result.status, 0) << result.output;
    const CsvTable table = readCsvTable(dir.file("out.csv"));
    ASSERT_EQ(table.rows.size(), 1u);
    const std::vector<double>& values = table.rows[0];
    ASSERT_EQ(values.size(), 8u);
    // 4 standard errors, plus the midpoint rule's error on the bilinear map (well under 0.1 %).
    EXPECT_NEAR(values[6], 5000.0, 4.0 * values[7] + 5.0);
    EXPECT_LT(values[7], 0.01 * 5000.0);
    const CliResult both =
        runPenumbra("illuminance " + dir.file("scene.gltf") + " --points " +
                    dir.file("points.csv") + " -o " + dir.file("both.csv") + " --environment " +
                    dir.file("sky.exr") + " --environment-illuminance 5000 --environment-scale 2");
    EXPECT_EQ(both.status, 2);
    EXPECT_NE(both.output.find("not with --environment-scale"), std::string::npos) << both.output;
}

// Bad environments are refused with the file and the place, exit status 2, and no image.
TEST(EnvironmentInput, RefusesWhatItCannotUse) {
    TempDir dir("bad-environment");
    GltfBuilder scene;
    addCube(scene, scene.addMaterial({.baseColor = Color(kRho)}));
    lookAtFace(scene, {0, 0, 1});
    scene.write(dir.file("scene.gltf"));
    const std::string render =
        "render " + dir.file("scene.gltf") + " -o " + dir.file("out.exr") + " --width 4 ";
    const auto refused = [&](const std::string& options, const std::string& message) {
        const CliResult result = runPenumbra(render + options);
        EXPECT_EQ(result.status, 2) << options << "\n" << result.output;
        EXPECT_NE(result.output.find(message), std::string::npos) << result.output;
        EXPECT_FALSE(std::filesystem::exists(dir.file("out.exr"))) << options;
    };
    refused("--environment-scale 2", "need an environment");
    refused("--environment " + dir.file("missing.exr"), "missing.exr");
    writeMap(dir.file("negative.exr"), 4, 2,
             [](float u, float v) { return u > 0.6f && v > 0.5f ? Color(-1.0f) : Color(1.0f); });
    refused("--environment " + dir.file("negative.exr"),
            "negative.exr: pixel (2, 1) channel R: -1");
    refused("--environment " + dir.file("scene.gltf"), "scene.gltf");
    refused("--sky cie:16", "--sky: unknown sky 'cie:16'");
    refused("--sky cie:12", "--sky cie:12: this sky depends on the sun; place it with --site");
    refused("--sky uniform --environment " + dir.file("negative.exr"), "not both");
    refused("--ground-reflectance 0.5", "needs --sky or --sun-direct-normal");
    // The sun: its position needs both the site and the time, well formed, and a sun above the
    // horizon to give direct light.
    const std::string noon = " --site 48.85,2.35 --time 2026-06-21T13:00+02:00";
    refused("--sun-direct-normal 50000", "--sun-direct-normal needs the sun's position");
    refused("--sky cie-clear --site 48.85,2.35", "--site and --time place the sun together");
    refused("--sky cie-clear --site 48.85,2.35 --time 2026-06-21T13:00",
            "time \"2026-06-21T13:00\"");
    refused("--sky cie-clear --site 95,2 --time 2026-06-21T13:00+02:00", "site \"95,2\"");
    refused("--sun-direct-normal 50000 --site 48.85,2.35 --time 2026-06-21T01:00+02:00",
            "is below the horizon");
    refused("--north 30", "--north turns the sun's position: it needs --site and --time");
    refused(noon, "--site and --time place the sun for --sky or --sun-direct-normal");
    refused("--sky cie-clear --environment-rotation 10" + noon, "turn the site with --north");

    GltfBuilder mirrored = scene;
    mirrored.setSceneExtras(R"({"mitsuba_environment": [{"type": "envmap", "file": "sky.exr",
        "toWorld_rowmajor": [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]}]})");
    mirrored.write(dir.file("scene.gltf"));
    refused("", "/scenes/0/extras/mitsuba_environment/0/toWorld_rowmajor: must be a rotation");
}

}  // namespace
}  // namespace penumbra::test
