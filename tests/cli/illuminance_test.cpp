// `penumbra illuminance` end to end: calculation points against closed forms (a point light over
// a plane, uniform and overcast skies, a furnace), sensors lying on surfaces, the CSV formats,
// and the refusal of bad input.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/csv_table.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace penumbra::test {
namespace {

struct Reading {
    std::vector<double> given;  // x, y, z, nx, ny, nz
    double lux = 0.0;
    double standardError = 0.0;
};

std::string readText(const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
}

// The rows of an output file, after checking its header.
std::vector<Reading> readResults(const std::string& path) {
    const CsvTable table = readCsvTable(path);
    EXPECT_EQ(table.header, "x,y,z,nx,ny,nz,illuminance_lux,stderr_lux");
    std::vector<Reading> rows;
    for (const std::vector<double>& values : table.rows) {
        EXPECT_EQ(values.size(), 8u);
        if (values.size() != 8)
            continue;
        rows.push_back({{values.begin(), values.begin() + 6}, values[6], values[7]});
    }
    return rows;
}

// Runs `illuminance` on the scene and points and returns the results (exit status 0 expected).
std::vector<Reading> measure(const GltfBuilder& scene, const TempDir& dir,
                             const std::string& points, const std::string& options) {
    scene.write(dir.file("scene.gltf"));
    writeText(dir.file("points.csv"), points);
    const CliResult result =
        runPenumbra("illuminance " + dir.file("scene.gltf") + " --points " +
                    dir.file("points.csv") + " -o " + dir.file("out.csv") + " --quiet " + options);
    EXPECT_EQ(result.status, 0) << result.output;
    return readResults(dir.file("out.csv"));
}

// Within four standard errors of `expected`, with a standard error below `relativeError` of it:
// the estimate is right and its error bar is honest and small.
void expectNear(const Reading& r, double expected, double relativeError) {
    EXPECT_NEAR(r.lux, expected, 4.0 * r.standardError + 1e-4 * expected)
        << "at " << r.given[0] << "," << r.given[1] << "," << r.given[2];
    EXPECT_LT(r.standardError, relativeError * expected);
}

// A square of side 2 s centred on the origin in the plane y = height, facing +Y.
void addFloor(GltfBuilder& scene, float s, float height, int material) {
    scene.addQuad({-s, height, s}, {s, height, s}, {s, height, -s}, {-s, height, -s}, material);
}

// A point light of I cd 2 m above a black floor: on the floor E = I cos(theta) / d² = I h / d³,
// exactly, as the light is a delta and nothing reflects.
TEST(Illuminance, PointLightOverAPlaneIsIhOverDCubed) {
    constexpr float kIntensity = 100.0f, kHeight = 2.0f;
    TempDir dir("illuminance-point");
    GltfBuilder scene;
    addFloor(scene, 50.0f, 0.0f, scene.addMaterial({.baseColor = Color(0.0f)}));
    scene.addLight({.type = "point", .intensity = kIntensity, .position = {0, kHeight, 0}});
    const std::vector<Reading> rows = measure(scene, dir,
                                              "0,0,0,0,1,0\n1,0,0,0,1,0\n0,0,-2,0,1,0\n"
                                              "3,0,4,0,1,0\n0,1,0,0,-1,0\n",
                                              "--spp 16");
    ASSERT_EQ(rows.size(), 5u);
    for (int i = 0; i < 4; ++i) {
        const double d = std::hypot(rows[i].given[0], kHeight, rows[i].given[2]);
        EXPECT_NEAR(rows[i].lux, kIntensity * kHeight / (d * d * d), 1e-5 * kIntensity)
            << "point " << i;
    }
    // Facing down, under the light: nothing reaches it.
    EXPECT_EQ(rows[4].lux, 0.0);
}

// A uniform sky of horizontal illuminance E_h over a ground of reflectance R: facing up E_h,
// facing down R E_h (the ground's luminance R E_h / pi over a hemisphere), a vertical sensor
// half of each.
TEST(Illuminance, UniformSkyUpDownAndSideways) {
    TempDir dir("illuminance-uniform");
    GltfBuilder scene;
    addFloor(scene, 0.1f, -100.0f, scene.addMaterial({}));  // far below: the scene needs a mesh
    const std::vector<Reading> rows =
        measure(scene, dir, "x,y,z,nx,ny,nz\n0,0,0,0,1,0\n0,0,0,0,-2,0\n0,0,0,1,0,0\n",
                "--sky uniform --sky-illuminance 10000 --ground-reflectance 0.3 --spp 4096");
    ASSERT_EQ(rows.size(), 3u);
    expectNear(rows[0], 10000.0, 0.01);
    expectNear(rows[1], 3000.0, 0.01);
    // A vertical sensor wastes half of the environment's light samples behind it: its standard
    // error was 0.8 % at 4096 samples (0.3 % facing up).
    expectNear(rows[2], 6500.0, 0.015);
}

// The CIE overcast sky, L = L_z (1 + 2 cos Z) / 3, E_h = 7 pi L_z / 9. A vertical sensor receives
// 2 integral of L(Z) sin² Z dZ = L_z (pi / 6 + 4 / 9) from the sky (0.396 E_h) and R E_h / 2
// from the ground.
TEST(Illuminance, OvercastSkyOnAVerticalSensor) {
    constexpr double kEh = 20000.0, kR = 0.2;
    TempDir dir("illuminance-overcast");
    GltfBuilder scene;
    addFloor(scene, 0.1f, -100.0f, scene.addMaterial({}));
    const std::vector<Reading> rows = measure(scene, dir, "0,0,0,0,0,1\n0,0,0,0,1,0\n",
                                              "--sky cie-overcast --sky-illuminance 20000 "
                                              "--spp 4096");
    ASSERT_EQ(rows.size(), 2u);
    const double zenith = kEh / (7.0 * M_PI / 9.0);
    expectNear(rows[0], zenith * (M_PI / 6.0 + 4.0 / 9.0) + kR * kEh / 2.0, 0.015);
    expectNear(rows[1], kEh, 0.01);
}

// Inside a closed box whose walls reflect rho and emit Le towards the inside, the radiance is
// Le / (1 - rho) everywhere and in every direction, so any sensor reads pi Le / (1 - rho): the
// interreflected light (here half of it) is counted, once, by every pipeline's estimator.
class IlluminanceFurnace : public testing::TestWithParam<const char*> {};

TEST_P(IlluminanceFurnace, CountsEveryBounceOnce) {
    constexpr float kRho = 0.5f, kLe = 2.0f;
    TempDir dir("illuminance-furnace");
    GltfBuilder scene;
    const int wall = scene.addMaterial(
        {.baseColor = Color(kRho), .emissive = Color(1.0f), .emissiveStrength = kLe});
    const Vec3 c[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    // Counter-clockwise seen from inside.
    scene.addQuad(c[0], c[1], c[2], c[3], wall);
    scene.addQuad(c[7], c[6], c[5], c[4], wall);
    scene.addQuad(c[4], c[0], c[3], c[7], wall);
    scene.addQuad(c[5], c[6], c[2], c[1], wall);
    scene.addQuad(c[4], c[5], c[1], c[0], wall);
    scene.addQuad(c[3], c[2], c[6], c[7], wall);
    const std::vector<Reading> rows =
        measure(scene, dir, "0,0,0,0,1,0\n0.5,-0.3,0.2,1,1,0\n0.9,0,0,-1,0,0\n",
                std::string("--spp 2048 --pipeline ") + GetParam());
    ASSERT_EQ(rows.size(), 3u);
    for (const Reading& r : rows)
        expectNear(r, kPi * kLe / (1.0f - kRho), 0.02);
}

INSTANTIATE_TEST_SUITE_P(Pipelines, IlluminanceFurnace,
                         testing::Values("reference", "hybrid", "hybrid-preview", "distribution",
                                         "radiosity"));

// The sun at a published position: NREL's solar position paper (Reda and Andreas 2004) works
// the example of Golden, Colorado, 2003-10-17 12:30:30 at UTC-7: zenith 50.11162 degrees,
// azimuth 194.34024 degrees (from north, clockwise). penumbra's position (NOAA's algorithm) is
// within 0.05 degrees of it (tests/core/solar_position_test.cpp), which moves E_n cos Z by 0.1 %.
constexpr double kSunZenith = 50.11162 * M_PI / 180.0, kSunAzimuth = 194.34024 * M_PI / 180.0;
const std::string kGolden = " --site 39.742476,-105.1786 --time 2003-10-17T12:30:30-07:00 ";

// The unit direction towards the published sun, north along -Z and east along +X, turned about
// +Y by `north` radians as --north turns it.
Vec3 publishedSun(double north) {
    const double x = std::sin(kSunAzimuth) * std::sin(kSunZenith), y = std::cos(kSunZenith),
                 z = -std::cos(kSunAzimuth) * std::sin(kSunZenith);
    return Vec3(float(x * std::cos(north) + z * std::sin(north)), float(y),
                float(-x * std::sin(north) + z * std::cos(north)));
}

std::string pointFacing(const Vec3& n) {
    std::ostringstream row;
    row.precision(9);
    row << "0,0,0," << n.x << "," << n.y << "," << n.z << "\n";
    return row.str();
}

// The sun's disc adds E_n cos(theta) to what the sky gives: on a horizontal sensor E_h + E_n cos Z;
// facing the sun E_n plus the uniform sky seen by a plane tilted by Z, E_h (1 + cos Z) / 2 over a
// black ground; facing away from it (vertical) the sky's half, E_h / 2. The ground below glows
// with R (E_h + E_n cos Z) / pi: a downward sensor reads R (E_h + E_n cos Z).
TEST(Illuminance, SunAtItsPublishedPositionAddsEnCosTheta) {
    constexpr double kEh = 10000.0, kEn = 60000.0, kR = 0.25;
    TempDir dir("illuminance-sun");
    GltfBuilder scene;
    addFloor(scene, 0.1f, -100.0f, scene.addMaterial({}));
    const Vec3 sun = publishedSun(0.0);
    const Vec3 away = glm::normalize(Vec3(-sun.x, 0.0f, -sun.z));
    const std::string points = pointFacing({0, 1, 0}) + pointFacing(sun) + pointFacing(away);
    const std::string sky = "--sky uniform --sky-illuminance 10000 --sun-direct-normal 60000 ";
    const std::vector<Reading> rows =
        measure(scene, dir, points, sky + "--ground-reflectance 0 --spp 4096" + kGolden);
    ASSERT_EQ(rows.size(), 3u);
    const double cosZ = std::cos(kSunZenith);
    // The disc takes three quarters of the light samples (its share of the power), so a sensor
    // that does not see it is noisier: 1.5 % at 4096 samples facing away.
    const auto expectWithin = [](const Reading& r, double expected, double relativeError = 0.01) {
        EXPECT_NEAR(r.lux, expected, 4.0 * r.standardError + 2e-3 * expected);
        EXPECT_LT(r.standardError, relativeError * expected);
    };
    expectWithin(rows[0], kEh + kEn * cosZ);
    expectWithin(rows[1], kEn + kEh * (1.0 + cosZ) / 2.0);
    expectWithin(rows[2], kEh / 2.0, 0.025);

    const std::vector<Reading> ground =
        measure(scene, dir, pointFacing({0, -1, 0}), sky + "--ground-reflectance 0.25" + kGolden);
    ASSERT_EQ(ground.size(), 1u);
    expectWithin(ground[0], kR * (kEh + kEn * cosZ));

    // --north 90 puts north along -X: the sun turns with it. A sensor still facing where the
    // sun was is now cos(theta) = cos² Z off it (the turn about +Y keeps the sun's height).
    const std::vector<Reading> turned =
        measure(scene, dir, pointFacing(publishedSun(M_PI / 2.0)) + pointFacing(sun),
                sky + "--ground-reflectance 0 --north 90 --spp 4096" + kGolden);
    ASSERT_EQ(turned.size(), 2u);
    expectWithin(turned[0], kEn + kEh * (1.0 + cosZ) / 2.0);
    expectWithin(turned[1], kEn * cosZ * cosZ + kEh * (1.0 + cosZ) / 2.0);
}

// The CIE clear sky glows around the sun: a vertical sensor facing the sun's azimuth reads more
// than one facing away (no disc: the sky alone), and both skies that need the sun run.
TEST(Illuminance, ClearSkiesBrightenTowardsTheSun) {
    TempDir dir("illuminance-clear");
    GltfBuilder scene;
    addFloor(scene, 0.1f, -100.0f, scene.addMaterial({}));
    const Vec3 sun = publishedSun(0.0);
    const Vec3 toward = glm::normalize(Vec3(sun.x, 0.0f, sun.z));
    for (const char* model : {"cie-clear", "cie:12", "cie:7"}) {
        const std::vector<Reading> rows =
            measure(scene, dir, pointFacing(toward) + pointFacing(-toward) + pointFacing({0, 1, 0}),
                    std::string("--sky ") + model + " --ground-reflectance 0 --spp 4096" + kGolden);
        ASSERT_EQ(rows.size(), 3u);
        EXPECT_GT(rows[0].lux,
                  rows[1].lux + 4.0 * std::hypot(rows[0].standardError, rows[1].standardError))
            << model;
        expectNear(rows[2], 10000.0, 0.01);
    }
}

// The daylight factor under a roof light: a black room (4 x 4 m, 3 m high) with a 1 x 1 m opening
// in its roof over the sensor, under the CIE overcast sky L = L_z (1 + 2 cos Z) / 3. The sensor
// reads E = integral over the opening of L(Z) cos Z cos Z / r² dA = integral of L(Z) h² / r⁴ dA
// (midpoint quadrature here, 400 x 400 cells: smooth integrand, far below the tolerance), and
// the daylight factor is 100 E / E_h with E_h = 7 pi L_z / 9.
TEST(Illuminance, DaylightFactorUnderARoofLight) {
    constexpr double kHeight = 3.0, kHalf = 0.5;
    TempDir dir("illuminance-daylight-factor");
    GltfBuilder scene;
    const int black = scene.addMaterial({.baseColor = Color(0.0f)});
    const float h = float(kHeight), a = float(kHalf);
    scene.addQuad({-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, black);  // floor, up
    scene.addQuad({-2, 0, -2}, {2, 0, -2}, {2, h, -2}, {-2, h, -2}, black);
    scene.addQuad({-2, 0, 2}, {-2, 0, -2}, {-2, h, -2}, {-2, h, 2}, black);
    scene.addQuad({2, 0, -2}, {2, 0, 2}, {2, h, 2}, {2, h, -2}, black);
    scene.addQuad({2, 0, 2}, {-2, 0, 2}, {-2, h, 2}, {2, h, 2}, black);
    // The roof around the opening |x|, |z| < a, facing down.
    scene.addQuad({-2, h, -2}, {2, h, -2}, {2, h, -a}, {-2, h, -a}, black);
    scene.addQuad({-2, h, a}, {2, h, a}, {2, h, 2}, {-2, h, 2}, black);
    scene.addQuad({-2, h, -a}, {-a, h, -a}, {-a, h, a}, {-2, h, a}, black);
    scene.addQuad({a, h, -a}, {2, h, -a}, {2, h, a}, {a, h, a}, black);
    scene.write(dir.file("scene.gltf"));
    writeText(dir.file("points.csv"), "0,0,0,0,1,0\n");
    const CliResult result = runPenumbra(
        "illuminance " + dir.file("scene.gltf") + " --points " + dir.file("points.csv") + " -o " +
        dir.file("out.csv") + " --quiet --sky cie-overcast --sky-illuminance 10000 --spp 32768 " +
        "--daylight-factor --portal none");
    ASSERT_EQ(result.status, 0) << result.output;
    const CsvTable table = readCsvTable(dir.file("out.csv"));
    EXPECT_EQ(table.header,
              "x,y,z,nx,ny,nz,illuminance_lux,stderr_lux,daylight_factor_percent,"
              "stderr_percent");
    ASSERT_EQ(table.rows.size(), 1u);
    const std::vector<double>& values = table.rows[0];
    ASSERT_EQ(values.size(), 10u);

    constexpr int kCells = 400;
    const double zenith = 10000.0 / (7.0 * M_PI / 9.0), cell = 2.0 * kHalf / kCells;
    double E = 0.0;
    for (int i = 0; i < kCells; ++i)
        for (int j = 0; j < kCells; ++j) {
            const double x = -kHalf + (i + 0.5) * cell, z = -kHalf + (j + 0.5) * cell;
            const double r = std::sqrt(x * x + z * z + kHeight * kHeight);
            const double L = zenith * (1.0 + 2.0 * kHeight / r) / 3.0;
            E += L * kHeight * kHeight / (r * r * r * r) * cell * cell;
        }
    const double df = 100.0 * E / 10000.0;
    std::printf("[ measured ] E = %.3f +- %.3f lux (quadrature %.3f), DF = %.4f %% (%.4f %%)\n",
                values[6], values[7], E, values[8], df);
    EXPECT_NEAR(values[6], E, 4.0 * values[7] + 1e-3 * E);
    // The sky's light samples cover the whole vault, and the opening is 2 % of it: 6.8 % of
    // standard error at 4096 samples, 2.4 % expected at 32 768 (portals would take them
    // through the opening).
    EXPECT_LT(values[7], 0.03 * E);
    EXPECT_NEAR(values[8], 100.0 * values[6] / 10000.0, 1e-6 * df);
    EXPECT_NEAR(values[9], 100.0 * values[7] / 10000.0, 1e-6 * df);

    // The illuminance and its standard error at 4096 samples with `portals`; NaN if it failed.
    const auto at4096Samples = [&](const std::string& name, const std::string& portals) {
        const CliResult r =
            runPenumbra("illuminance " + dir.file("scene.gltf") + " --points " +
                        dir.file("points.csv") + " -o " + dir.file(name + ".csv") +
                        " --quiet --sky cie-overcast --sky-illuminance 10000 --spp 4096" + portals);
        EXPECT_EQ(r.status, 0) << r.output;
        const CsvTable t = readCsvTable(dir.file(name + ".csv"));
        if (t.rows.size() != 1u || t.rows[0].size() != 8u)
            return std::pair{std::nan(""), std::nan("")};
        std::printf("[ measured ] %s, 4096 samples: E = %.3f +- %.3f lux\n", name.c_str(),
                    t.rows[0][6], t.rows[0][7]);
        return std::pair{t.rows[0][6], t.rows[0][7]};
    };
    // A portal over the opening aims the sky's samples through it, and by default the opening is
    // found and made one: at an eighth of the samples the standard error is smaller still, and
    // the value the same within it.
    for (const auto& [name, portals] :
         {std::pair<std::string, std::string>{"given-portal",
                                              " --portal -0.5,3,-0.5,0.5,3,-0.5,-0.5,3,0.5"},
          {"opening-found", ""}}) {
        const auto [illuminance, error] = at4096Samples(name, portals);
        EXPECT_NEAR(illuminance, E, 4.0 * error + 1e-3 * E) << name;
        EXPECT_LT(error, values[7]) << name;
    }

    // Only under an overcast sky without the sun.
    const CliResult clear =
        runPenumbra("illuminance " + dir.file("scene.gltf") + " --points " +
                    dir.file("points.csv") + " -o " + dir.file("clear.csv") +
                    " --sky cie-clear --site 0,0 --time 2026-03-21T12:00Z " + "--daylight-factor");
    EXPECT_EQ(clear.status, 2);
    EXPECT_NE(clear.output.find("--daylight-factor is defined under an overcast sky"),
              std::string::npos)
        << clear.output;
}

// A sensor lying on a surface reads the light from the side its normal faces: on a white floor
// under a uniform sky, E_h facing up (the floor it lies on adds nothing and hides nothing), and
// on the floor's underside facing down, the ground's R E_h.
TEST(Illuminance, ASensorOnASurfaceReadsTheSideItFaces) {
    TempDir dir("illuminance-on-surface");
    GltfBuilder scene;
    addFloor(scene, 5.0f, 0.0f, scene.addMaterial({.baseColor = Color(0.8f)}));
    const std::vector<Reading> rows =
        measure(scene, dir, "0,0,0,0,1,0\n4.99,0,-4.99,0,1,0\n1,0,1,0,-1,0\n",
                "--sky uniform --sky-illuminance 1000 --spp 1024");
    ASSERT_EQ(rows.size(), 3u);
    expectNear(rows[0], 1000.0, 0.01);
    expectNear(rows[1], 1000.0, 0.01);
    expectNear(rows[2], 200.0, 0.01);
}

// The rows come back in the input's order with the input's values; the same seed gives the same
// results whatever the thread count.
TEST(Illuminance, EchoesTheInputAndIsDeterministic) {
    TempDir dir("illuminance-format");
    GltfBuilder scene;
    addFloor(scene, 5.0f, 0.0f, scene.addMaterial({}));
    scene.addLight({.type = "point", .intensity = 10.0f, .position = {0, 2, 0}});
    const std::string points = "# a comment\n\n1.5, 0.25 ,-3,0,2,0\n+0,1e-1,0,0,0,-1\n";
    const std::vector<Reading> rows = measure(scene, dir, points, "--spp 8 --threads 1");
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].given, (std::vector<double>{1.5, 0.25, -3, 0, 2, 0}));
    EXPECT_EQ(rows[1].given, (std::vector<double>{0, 0.1, 0, 0, 0, -1}));
    const std::string first = readText(dir.file("out.csv"));
    measure(scene, dir, points, "--spp 8 --threads 2");
    EXPECT_EQ(readText(dir.file("out.csv")), first);
}

// A workplane grid: sensors at the cells' centres, row by row from Z0, each reading I h / d³
// under a point light over a black floor; the false-colour picture is written with its legend.
TEST(Illuminance, WorkplaneGrid) {
    TempDir dir("illuminance-grid");
    GltfBuilder scene;
    addFloor(scene, 50.0f, 0.0f, scene.addMaterial({.baseColor = Color(0.0f)}));
    scene.addLight({.type = "point", .intensity = 100.0f, .position = {0, 2, 0}});
    scene.write(dir.file("scene.gltf"));
    const CliResult result = runPenumbra("illuminance " + dir.file("scene.gltf") +
                                         " --grid -2,-1,2,1.5,0,1 -o " + dir.file("grid.csv") +
                                         " --picture " + dir.file("grid.png") + " --spp 4 --quiet");
    ASSERT_EQ(result.status, 0) << result.output;
    const std::vector<Reading> rows = readResults(dir.file("grid.csv"));
    // 4 columns of 1 m; 3 rows, the last cut short to 0.5 m (its centre at z = 1.25).
    ASSERT_EQ(rows.size(), 12u);
    const double zs[] = {-0.5, 0.5, 1.25}, xs[] = {-1.5, -0.5, 0.5, 1.5};
    for (size_t k = 0; k < rows.size(); ++k) {
        const double x = xs[k % 4], z = zs[k / 4];
        EXPECT_EQ(rows[k].given, (std::vector<double>{x, 0, z, 0, 1, 0})) << k;
        const double d = std::sqrt(x * x + 4.0 + z * z);
        EXPECT_NEAR(rows[k].lux, 100.0 * 2.0 / (d * d * d), 1e-4) << k;
    }
    const Image picture = readImage(dir.file("grid.png"));
    EXPECT_GE(picture.width(), 320);
    EXPECT_GT(picture.height(), 64);

    const auto refused = [&](const std::string& options, const std::string& message) {
        const CliResult r = runPenumbra("illuminance " + dir.file("scene.gltf") + " -o " +
                                        dir.file("bad.csv") + " " + options);
        EXPECT_EQ(r.status, 2) << options << "\n" << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
    };
    refused("--grid 1,2,3", "expected six numbers");
    refused("--grid 1,0,0,1,0.8,0.5", "expected X0 < X1 and Z0 < Z1");
    refused("--grid 0,0,1,1,0.8,0", "the spacing must be > 0");
    refused("", "one of --points IN.csv, --grid");
    refused("--grid 0,0,1,1,0.8,0.5 --picture " + dir.file("grid.txt"), "grid.txt");
}

// A workplane over a polygon: the cells whose centres lie inside it, here the triangle (0, 0),
// (4, 0), (0, 4) with 1-m cells, whose centres (i + 0.5, j + 0.5) are inside when i + j <= 2: six
// of them, each reading I h / d³.
TEST(Illuminance, WorkplaneOverAPolygon) {
    TempDir dir("illuminance-polygon");
    GltfBuilder scene;
    addFloor(scene, 50.0f, 0.0f, scene.addMaterial({.baseColor = Color(0.0f)}));
    scene.addLight({.type = "point", .intensity = 100.0f, .position = {0, 2, 0}});
    scene.write(dir.file("scene.gltf"));
    const CliResult result = runPenumbra(
        "illuminance " + dir.file("scene.gltf") + " --grid-polygon 0.5,1,0,0,4,0,0,4 -o " +
        dir.file("polygon.csv") + " --picture " + dir.file("polygon.png") + " --spp 4 --quiet");
    ASSERT_EQ(result.status, 0) << result.output;
    const std::vector<Reading> rows = readResults(dir.file("polygon.csv"));
    const std::vector<std::pair<double, double>> centres = {{0.5, 0.5}, {1.5, 0.5}, {2.5, 0.5},
                                                            {0.5, 1.5}, {1.5, 1.5}, {0.5, 2.5}};
    ASSERT_EQ(rows.size(), centres.size());
    for (size_t k = 0; k < rows.size(); ++k) {
        const auto [x, z] = centres[k];
        EXPECT_EQ(rows[k].given, (std::vector<double>{x, 0.5, z, 0, 1, 0})) << k;
        const double d = std::sqrt(x * x + 1.5 * 1.5 + z * z);
        EXPECT_NEAR(rows[k].lux, 100.0 * 1.5 / (d * d * d), 1e-4) << k;
    }
    const CliResult bad = runPenumbra("illuminance " + dir.file("scene.gltf") +
                                      " --grid-polygon 0.5,1,0,0,4,0 -o " + dir.file("bad.csv"));
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("three or more vertices"), std::string::npos) << bad.output;
}

// A workplane over a room's floor found by its material's name: an L of two squares at two levels
// (y = 0 and a step up to y = 0.3), sensors 0.8 m above each, I h / d³ from the light at each;
// the cells of the bounding square off the L are left out.
TEST(Illuminance, WorkplaneOverANamedFloor) {
    TempDir dir("illuminance-floor");
    GltfBuilder scene;
    const int floor = scene.addMaterial({.baseColor = Color(0.0f), .name = "Floor"});
    // Squares [0, 2] x [0, 2] at y = 0, [2, 4] x [0, 2] at y = 0.3, [0, 2] x [2, 4] at y = 0.
    const auto square = [&](float x, float z, float y) {
        scene.addQuad({x, y, z + 2}, {x + 2, y, z + 2}, {x + 2, y, z}, {x, y, z}, floor);
    };
    square(0, 0, 0);
    square(2, 0, 0.3f);
    square(0, 2, 0);
    // A ceiling-height black slab that faces down (not floor) carries the same material.
    scene.addQuad({0, 3, 0}, {4, 3, 0}, {4, 3, 4}, {0, 3, 4}, floor);
    scene.addLight({.type = "point", .intensity = 100.0f, .position = {1, 2.5f, 1}});
    scene.write(dir.file("scene.gltf"));
    const CliResult result =
        runPenumbra("illuminance " + dir.file("scene.gltf") + " --grid-floor Floor,0.8,1 -o " +
                    dir.file("floor.csv") + " --spp 4 --quiet");
    ASSERT_EQ(result.status, 0) << result.output;
    const std::vector<Reading> rows = readResults(dir.file("floor.csv"));
    // Rows from z = 0: (0.5, 0.5) (1.5, 0.5) (2.5, 0.5) (3.5, 0.5), then z = 1.5 likewise, then
    // z = 2.5 and 3.5 over the first two columns only.
    std::vector<std::array<double, 3>> expected;
    for (const double z : {0.5, 1.5, 2.5, 3.5})
        for (const double x : {0.5, 1.5, 2.5, 3.5})
            if (x < 2.0 || z < 2.0)
                expected.push_back({x, (x > 2.0 ? 0.3 : 0.0) + 0.8, z});
    ASSERT_EQ(rows.size(), expected.size());
    for (size_t k = 0; k < rows.size(); ++k) {
        const auto [x, y, z] = expected[k];
        EXPECT_NEAR(rows[k].given[0], x, 1e-6) << k;
        EXPECT_NEAR(rows[k].given[1], y, 1e-6) << k;
        EXPECT_NEAR(rows[k].given[2], z, 1e-6) << k;
        const double h = 2.5 - y, d = std::sqrt((x - 1) * (x - 1) + h * h + (z - 1) * (z - 1));
        EXPECT_NEAR(rows[k].lux, 100.0 * h / (d * d * d), 1e-4) << k;
    }
    const CliResult bad = runPenumbra("illuminance " + dir.file("scene.gltf") +
                                      " --grid-floor Carpet,0.8,1 -o " + dir.file("bad.csv"));
    EXPECT_EQ(bad.status, 2) << bad.output;
    EXPECT_NE(bad.output.find("'Carpet'"), std::string::npos) << bad.output;
}

// Bad input: exit status 2, a message naming the file and line, no output written.
TEST(Illuminance, RefusesBadInput) {
    TempDir dir("illuminance-refusals");
    GltfBuilder scene;
    addFloor(scene, 5.0f, 0.0f, scene.addMaterial({}));
    scene.write(dir.file("scene.gltf"));
    const std::string output = dir.file("out.csv");
    const auto run = [&](const std::string& points, const std::string& options) {
        writeText(dir.file("points.csv"), points);
        return runPenumbra("illuminance " + dir.file("scene.gltf") + " --points " +
                           dir.file("points.csv") + " " + options);
    };
    const struct {
        std::string points, options, message;
    } cases[] = {
        {"x,y,z,nx,ny,nz\n0,0,0,0,1,0\n0,0,0,1\n", "-o " + output, "points.csv:3: expected six"},
        {"0,0,0,0,0,0\n", "-o " + output, "points.csv:1: the normal"},
        {"0,0,0,0,1,zero\n", "-o " + output, "points.csv:1: expected six"},
        {"0,0,0,0,1,0\n0,0,nan,0,1,0\n", "-o " + output, "points.csv:2: a value is not finite"},
        {"x,y,z,nx,ny,nz\n", "-o " + output, "no calculation point"},
        {"0,0,0,0,1,0\n", "-o " + dir.file("out.txt"), "is a .csv file"},
        {"0,0,0,0,1,0\n", "-o " + dir.file("missing/out.csv"), "does not exist"},
        {"0,0,0,0,1,0\n", "-o " + output + " --pipeline nonsense", "unknown pipeline 'nonsense'"},
        {"0,0,0,0,1,0\n", "-o " + output + " --spp 1", "less than 2"},
    };
    for (const auto& c : cases) {
        const CliResult result = run(c.points, c.options);
        EXPECT_EQ(result.status, 2) << c.points << c.options << "\n" << result.output;
        EXPECT_NE(result.output.find(c.message), std::string::npos) << result.output;
        EXPECT_FALSE(std::filesystem::exists(output)) << c.points;
    }
}

// A time limit ends the work at a whole round, every point with the same number of samples.
TEST(Illuminance, StopsAtTheTimeLimit) {
    TempDir dir("illuminance-time");
    GltfBuilder scene;
    addFloor(scene, 5.0f, 0.0f, scene.addMaterial({}));
    const std::vector<Reading> rows = measure(scene, dir, "0,1,0,0,1,0\n0,1,0,0,-1,0\n",
                                              "--sky uniform --spp 1000000000 --time-limit 1");
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_NEAR(rows[0].lux, 10000.0, 4.0 * rows[0].standardError);
    EXPECT_GT(rows[0].standardError, 0.0);
}

}  // namespace
}  // namespace penumbra::test
