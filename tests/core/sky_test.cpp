// The sky models against oracles they did not make: the general sky's table against ISO 15469's
// as Darula and Kittler publish it (six gradation and six indicatrix groups), values printed by
// colour-science's independent implementation, type 12 against the CIE 1973 clear-sky formula,
// the overcast and uniform skies' illuminance against closed forms, the 2D integral of the
// zenith luminance against a 1D one (the sun at the zenith) and against a rule in the sun's polar
// coordinates, the map's pixels against the environment light's mapping; then the refusals and a
// sweep for NaN and negative luminance.
#include "core/sky.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::test {
namespace {

using std::numbers::pi;

double radians(double degrees) {
    return degrees * pi / 180.0;
}

std::vector<std::string> allModels() {
    std::vector<std::string> models = {"uniform", "cie-overcast", "cie-clear"};
    for (int type = 1; type <= 15; ++type)
        models.push_back("cie:" + std::to_string(type));
    return models;
}

// The angles of sky element (Z, alpha) seen against a sun at zenith angle Zs and azimuth 0,
// chi from the dot product of their unit vectors (not from the law of cosines the code uses).
SunAngles sunAngles(double Z, double alpha, double Zs) {
    const double element[3] = {std::sin(Z) * std::cos(alpha), std::cos(Z),
                               std::sin(Z) * std::sin(alpha)};
    const double sun[3] = {std::sin(Zs), std::cos(Zs), 0.0};
    const double cosChi = element[0] * sun[0] + element[1] * sun[1] + element[2] * sun[2];
    return {Zs, std::acos(std::fmax(-1.0, std::fmin(1.0, cosChi)))};
}

// A unit vector towards a sun at zenith angle Zs and map azimuth `turn` (radians), in world axes
// by the environment light's mapping (core/environment_light.h): turn 0 looks along -Z, a
// quarter turn along +X.
Vec3 sunTowards(double Zs, double turn) {
    return Vec3(float(std::sin(Zs) * std::sin(turn)), float(std::cos(Zs)),
                float(-std::sin(Zs) * std::cos(turn)));
}

SkySettings settingsOf(const std::string& model, std::optional<Vec3> sun = std::nullopt) {
    SkySettings settings;
    settings.model = model;
    settings.sunDirection = sun;
    return settings;
}

// The message of the std::invalid_argument that `f` throws, or "" if it throws none.
std::string refusal(const std::function<void()>& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

// ISO 15469:2004 Table 1 as Darula and Kittler publish it ("CIE general sky standard defining
// luminance distributions", eSim 2002): six gradation groups (a, b), six indicatrix groups
// (c, d, e), and each type one of each.
TEST(SkyTest, GeneralSkyTableIsIso15469Table1) {
    const std::array<std::array<double, 2>, 6> gradation = {
        {{4.0, -0.70}, {1.1, -0.80}, {0.0, -1.00}, {-1.0, -0.55}, {-1.0, -0.32}, {-1.0, -0.15}}};
    const std::array<std::array<double, 3>, 6> indicatrix = {{{0.0, -1.0, 0.00},
                                                              {2.0, -1.5, 0.15},
                                                              {5.0, -2.5, 0.30},
                                                              {10.0, -3.0, 0.45},
                                                              {16.0, -3.0, 0.30},
                                                              {24.0, -2.8, 0.15}}};
    // Type t's groups (gradation I-VI as 1-6, indicatrix 1-6).
    const std::array<std::array<int, 2>, 15> groups = {{{1, 1},
                                                        {1, 2},
                                                        {2, 1},
                                                        {2, 2},
                                                        {3, 1},
                                                        {3, 2},
                                                        {3, 3},
                                                        {3, 4},
                                                        {4, 2},
                                                        {4, 3},
                                                        {4, 4},
                                                        {5, 4},
                                                        {5, 5},
                                                        {6, 5},
                                                        {6, 6}}};
    for (int type = 1; type <= 15; ++type) {
        SCOPED_TRACE("type " + std::to_string(type));
        const auto [g, i] = groups[size_t(type - 1)];
        const CieSkyParameters p = cieGeneralSkyParameters(type);
        EXPECT_EQ(p.a, gradation[size_t(g - 1)][0]);
        EXPECT_EQ(p.b, gradation[size_t(g - 1)][1]);
        EXPECT_EQ(p.c, indicatrix[size_t(i - 1)][0]);
        EXPECT_EQ(p.d, indicatrix[size_t(i - 1)][1]);
        EXPECT_EQ(p.e, indicatrix[size_t(i - 1)][2]);
    }
    // Type 7 (group III, indicatrix 3) has the e of type 10 (group IV, indicatrix 3), not 0.35.
    EXPECT_EQ(cieGeneralSkyParameters(7).e, 0.30);
}

// The relative luminances printed by colour-science (colour.phenomena.
// sky_luminance_distribution_CIE2003's examples) for an element at Z = 45 degrees, azimuth 180,
// the sun at Zs = 30 degrees, azimuth 0: 0.8325846 for type 1, 0.4544524 for type 12, to the
// seven digits printed.
TEST(SkyTest, RelativeLuminanceMatchesColourScience) {
    const SunAngles sun = sunAngles(radians(45.0), radians(180.0), radians(30.0));
    EXPECT_NEAR(skyRelativeLuminance("cie:1", radians(45.0), sun), 0.8325846, 1e-7);
    EXPECT_NEAR(skyRelativeLuminance("cie:12", radians(45.0), sun), 0.4544524, 1e-7);
}

// Type 12's indicatrix is the clear sky's but for its constant, 1 - 10 exp(-3 pi/2) = 0.910167
// against 0.91, and their gradations are the same function. With f_12 = f_clear + delta,
// delta = 1.67e-4, and f_clear >= 0.91, the ratio of the two skies' f(chi) / f(Z_s) is within
// delta / 0.91 = 1.84e-4 of 1, and so are their luminances and their integrals over the sky.
TEST(SkyTest, GeneralType12IsTheCieClearSky) {
    constexpr double kBound = 1.84e-4;
    for (double zs = 0.0; zs <= 95.0; zs += 5.0) {
        for (double z = 0.0; z <= 90.0; z += 2.5) {
            for (double alpha = 0.0; alpha <= 180.0; alpha += 10.0) {
                const SunAngles sun = sunAngles(radians(z), radians(alpha), radians(zs));
                const double general = skyRelativeLuminance("cie:12", radians(z), sun);
                const double clear = skyRelativeLuminance("cie-clear", radians(z), sun);
                ASSERT_NEAR(general / clear, 1.0, kBound)
                    << "Z " << z << ", alpha " << alpha << ", Zs " << zs;
            }
        }
    }
    for (double zs : {0.0, 30.0, 60.0, 89.0}) {
        const Vec3 sun = sunTowards(radians(zs), radians(40.0));
        EXPECT_NEAR(skyZenithLuminance(settingsOf("cie:12", sun)) /
                        skyZenithLuminance(settingsOf("cie-clear", sun)),
                    1.0, kBound)
            << "Zs " << zs;
    }
}

// E_h = integral of L cos Z over the hemisphere: L_z (1 + 2 cos Z) / 3 gives 7 pi L_z / 9, a
// uniform L_z gives pi L_z; to the 1e-6 the header promises (measured: 1e-7). A sun changes
// neither.
TEST(SkyTest, OvercastAndUniformZenithLuminanceAreClosedForms) {
    const Vec3 sun = sunTowards(radians(30.0), 1.0);
    for (const auto& settings : {settingsOf("cie-overcast"), settingsOf("cie-overcast", sun)})
        EXPECT_NEAR(skyZenithLuminance(settings) / (10000.0 * 9.0 / (7.0 * pi)), 1.0, 1e-6);
    for (const std::string model : {"uniform", "cie:5"}) {
        EXPECT_NEAR(skyZenithLuminance(settingsOf(model)) / (10000.0 / pi), 1.0, 1e-6);
        EXPECT_NEAR(skyZenithLuminance(settingsOf(model, sun)) / (10000.0 / pi), 1.0, 1e-6);
    }
}

// E_h / L_z by a rule in the sun's own polar coordinates: chi from the sun and psi about it,
// cos Z = cos chi cos Zs + sin chi sin Zs cos psi, dω = sin chi dchi dpsi, the luminance's cusp
// at the sun a pole of the grid; symmetric in psi, so [0, pi] twice. Its own error at 1 500 x 750
// (the horizon cuts its cells, so it converges as h²) was at most 2.6e-6 against itself at
// 8 000 x 4 000 (clear, 15 and 14 and 7 skies, the sun from 30 to 95 degrees).
double illuminanceAroundTheSun(const std::string& model, double Zs) {
    constexpr int kChi = 1500, kPsi = 750;
    const double dChi = pi / kChi, dPsi = pi / kPsi;
    double sum = 0.0;
    for (int i = 0; i < kChi; ++i) {
        const double chi = (i + 0.5) * dChi;
        for (int j = 0; j < kPsi; ++j) {
            const double psi = (j + 0.5) * dPsi;
            const double cosZ =
                std::cos(chi) * std::cos(Zs) + std::sin(chi) * std::sin(Zs) * std::cos(psi);
            if (cosZ > 0.0) {
                sum += skyRelativeLuminance(model, std::acos(cosZ), SunAngles{Zs, chi}) * cosZ *
                       std::sin(chi);
            }
        }
    }
    return 2.0 * sum * dChi * dPsi;
}

// The 2D midpoint rule of skyZenithLuminance() against two others: with the sun at the zenith
// chi = Z, and the integral is 2 pi times a 1D one (Simpson's rule on 20 000 intervals, exact to
// far below 1e-9 for this smooth integrand), for every model, to the header's 1e-6 (measured:
// 2.6e-7); and the rule around the sun for three skies with the sun high, near the horizon and
// below it (type 15 there is the worst case of the rule's own convergence study, sky.cpp), to
// 1e-5, the sum of the header's 1e-6 and that rule's own error.
TEST(SkyTest, ZenithLuminanceMatchesIndependentIntegrals) {
    constexpr double kEh = 10000.0;
    for (const std::string& model : allModels()) {
        constexpr int kIntervals = 20000;
        const double h = (pi / 2.0) / kIntervals;
        double simpson = 0.0;
        for (int k = 0; k <= kIntervals; ++k) {
            const double Z = k * h;
            const double weight = (k == 0 || k == kIntervals) ? 1.0 : (k % 2 ? 4.0 : 2.0);
            simpson += weight * skyRelativeLuminance(model, Z, SunAngles{0.0, Z}) * std::cos(Z) *
                       std::sin(Z);
        }
        const double expected = kEh / (2.0 * pi * simpson * h / 3.0);
        const double Lz = skyZenithLuminance(settingsOf(model, Vec3(0.0f, 1.0f, 0.0f)));
        EXPECT_NEAR(Lz / expected, 1.0, 1e-6) << model;
    }
    const std::array<std::pair<std::string, double>, 3> cases = {
        {{"cie-clear", 30.0}, {"cie:15", 89.0}, {"cie:15", 95.0}}};
    for (const auto& [model, zs] : cases) {
        const double expected = kEh / illuminanceAroundTheSun(model, radians(zs));
        const double Lz = skyZenithLuminance(settingsOf(model, sunTowards(radians(zs), 2.0)));
        EXPECT_NEAR(Lz / expected, 1.0, 1e-5) << model << ", Zs " << zs;
    }
}

// Types 1, 3 and 5 have c = e = 0, so f = 1 and the sun changes nothing; "uniform" and
// "cie-overcast" neither. Types 2 and 4 (c = 2) do brighten towards the sun.
TEST(SkyTest, SunIndependentTypesIgnoreTheSun) {
    for (const std::string model : {"cie:1", "cie:3", "cie:5", "uniform", "cie-overcast"}) {
        SCOPED_TRACE(model);
        EXPECT_FALSE(skyNeedsSun(model));
        for (double z = 0.0; z <= 90.0; z += 5.0) {
            const double alone = skyRelativeLuminance(model, radians(z));
            for (double zs : {0.0, 40.0, 95.0}) {
                const SunAngles sun = sunAngles(radians(z), radians(z * 2.0), radians(zs));
                EXPECT_EQ(skyRelativeLuminance(model, radians(z), sun), alone);
            }
        }
        const Vec3 sun = sunTowards(radians(40.0), 0.5);
        EXPECT_EQ(skyZenithLuminance(settingsOf(model, sun)),
                  skyZenithLuminance(settingsOf(model)));
        // Every row of the map is one luminance.
        const Image map = skyMap(settingsOf(model), 64);
        for (int y = 0; y < map.height(); ++y)
            for (int x = 0; x < map.width(); ++x)
                ASSERT_EQ(map.at(x, y, 0), map.at(0, y, 0)) << x << ", " << y;
    }
    for (const std::string model : {"cie:2", "cie:4"}) {
        EXPECT_TRUE(skyNeedsSun(model));
        const double towards =
            skyRelativeLuminance(model, radians(45.0), SunAngles{radians(45.0), 0.0});
        const double away =
            skyRelativeLuminance(model, radians(45.0), SunAngles{radians(45.0), pi / 2});
        EXPECT_GT(towards, away) << model;
    }
}

// With the sun at Zs = 45 degrees, the element at the sun (chi = 0) and the one at the same
// height opposite (chi = 90 degrees) share phi(Z), so their ratio is f(0) / f(pi/2) =
// 1 + c (1 - exp(d pi/2)) + e from the published table: > 1 for every type with c > 0; the clear
// sky's is (0.91 + 10 + 0.45) / (0.91 + 10 exp(-3 pi/2)).
TEST(SkyTest, SunDependentSkiesAreBrighterAtTheSun) {
    const double zs = radians(45.0);
    const SunAngles atSun = sunAngles(zs, 0.0, zs);
    const SunAngles opposite = sunAngles(zs, pi, zs);
    ASSERT_NEAR(atSun.distance, 0.0, 1e-7);
    ASSERT_NEAR(opposite.distance, pi / 2, 1e-12);
    for (int type = 1; type <= 15; ++type) {
        const std::string model = "cie:" + std::to_string(type);
        const CieSkyParameters p = cieGeneralSkyParameters(type);
        const double ratio = skyRelativeLuminance(model, zs, SunAngles{zs, 0.0}) /
                             skyRelativeLuminance(model, zs, opposite);
        EXPECT_NEAR(ratio, 1.0 + p.c * (1.0 - std::exp(p.d * pi / 2.0)) + p.e, 1e-12) << model;
        if (p.c > 0.0) {
            EXPECT_GT(ratio, 1.0) << model;
        }
    }
    const double clear = skyRelativeLuminance("cie-clear", zs, SunAngles{zs, 0.0}) /
                         skyRelativeLuminance("cie-clear", zs, opposite);
    EXPECT_NEAR(clear, (0.91 + 10.0 + 0.45) / (0.91 + 10.0 * std::exp(-1.5 * pi)), 1e-12);
}

// Each pixel is L_z times the relative luminance at its centre's direction, whose angle to the
// sun is taken here from the environment light's mapping (u = atan2(x, -z) / 2 pi,
// v = acos(y) / pi: the pixel's centre is at zenith angle v pi and azimuth 2 pi u, the sun at its
// own); below the horizon the ground, R (E_h + E_sun) / pi. The brightest pixel of a clear sky is
// the one the mapping puts the sun in.
TEST(SkyTest, MapPixelsFollowTheEnvironmentMapping) {
    const double zs = radians(35.0), turn = radians(100.0);
    const Vec3 sun = sunTowards(zs, turn);
    SkySettings settings = settingsOf("cie:13", sun);
    settings.groundReflectance = 0.3f;
    settings.sunHorizontalIlluminance = 50000.0f;
    const int width = 128, height = 64;
    const Image map = skyMap(settings, width);
    ASSERT_EQ(map.width(), width);
    ASSERT_EQ(map.height(), height);
    const double Lz = skyZenithLuminance(settings);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const double v = (y + 0.5) / height, u = (x + 0.5) / width;
            const double Z = v * pi;
            // The pixel's azimuth differs from the sun's by 2 pi u - turn.
            const SunAngles angles = sunAngles(Z, 2.0 * pi * u - turn, zs);
            const double expected = Z < pi / 2
                                        ? Lz * skyRelativeLuminance(settings.model, Z, angles)
                                        : 0.3 * (10000.0 + 50000.0) / pi;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(map.at(x, y, c) / expected, 1.0, 1e-6) << x << ", " << y;
        }
    }
    const Image clear = skyMap(settingsOf("cie-clear", sun), width);
    int bestX = 0, bestY = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            if (clear.at(x, y, 0) > clear.at(bestX, bestY, 0)) {
                bestX = x;
                bestY = y;
            }
    double u = std::atan2(double(sun.x), -double(sun.z)) / (2.0 * pi);
    if (u < 0.0)
        u += 1.0;
    const double v = std::acos(double(sun.y)) / pi;
    EXPECT_EQ(bestX, int(u * width));
    EXPECT_EQ(bestY, int(v * height));
}

TEST(SkyTest, RefusesWhatItCannotMake) {
    for (const std::string model :
         {"clear", "cie:", "cie:0", "cie:16", "cie:07", "cie:7 ", "cie:-1", "CIE:7", "cie-"}) {
        const std::string message = refusal([&] { skyMap(settingsOf(model), 16); });
        EXPECT_NE(message.find("unknown sky '" + model + "'"), std::string::npos) << message;
        EXPECT_NE(message.find("cie-clear"), std::string::npos) << message;
        EXPECT_NE(message.find("cie:15"), std::string::npos) << message;
        EXPECT_NE(refusal([&] { skyNeedsSun(model); }), "");
    }
    for (const std::string& model : allModels()) {
        if (!skyNeedsSun(model))
            continue;
        SCOPED_TRACE(model);
        const std::string expected =
            "sky '" + model + "' needs the sun: give --site and --time, or a sun direction";
        EXPECT_EQ(refusal([&] { skyMap(settingsOf(model), 16); }), expected);
        EXPECT_EQ(refusal([&] { skyZenithLuminance(settingsOf(model)); }), expected);
        EXPECT_EQ(refusal([&] { skyRelativeLuminance(model, 0.5); }), expected);
        for (const Vec3 bad : {Vec3(0.0f), Vec3(std::nanf(""), 1.0f, 0.0f)}) {
            EXPECT_EQ(refusal([&] { skyMap(settingsOf(model, bad), 16); }),
                      "sky '" + model + "': the sun direction must be finite and non-zero");
        }
    }
    SkySettings dark = settingsOf("uniform");
    dark.horizontalIlluminance = 0.0f;
    EXPECT_EQ(refusal([&] { skyMap(dark, 16); }), "skyMap: the horizontal illuminance must be > 0");
    SkySettings shiny = settingsOf("uniform");
    shiny.groundReflectance = 1.5f;
    EXPECT_EQ(refusal([&] { skyMap(shiny, 16); }),
              "skyMap: the ground reflectance must be in [0, 1]");
    for (const float sunlight : {-1.0f, std::nanf("")}) {
        SkySettings lit = settingsOf("uniform");
        lit.sunHorizontalIlluminance = sunlight;
        EXPECT_EQ(refusal([&] { skyMap(lit, 16); }),
                  "skyMap: the sun's horizontal illuminance must be >= 0");
    }
    for (int type : {0, 16})
        EXPECT_NE(refusal([&] { cieGeneralSkyParameters(type); }), "");
}

// Every model, the sun from the zenith to 5 degrees below the horizon: finite and > 0 on a grid
// that includes the horizon itself (cos Z = 6e-17 there) and the element at the sun; the maps,
// their L_z included, finite, > 0 above the horizon and >= 0 below it.
TEST(SkyTest, NoNanOrNegativeLuminance) {
    for (const std::string& model : allModels()) {
        SCOPED_TRACE(model);
        for (double zs = 0.0; zs <= 95.0; zs += 5.0) {
            for (double z = 0.0; z <= 90.0; z += 1.0) {
                for (double alpha = 0.0; alpha <= 180.0; alpha += 5.0) {
                    const double Z = z == 90.0 ? pi / 2 : radians(z);
                    const double L =
                        skyRelativeLuminance(model, Z, sunAngles(Z, radians(alpha), radians(zs)));
                    ASSERT_TRUE(std::isfinite(L) && L > 0.0) << z << ", " << alpha << ", " << zs;
                }
            }
        }
        for (double zs : {0.0, 90.0, 95.0}) {
            const Image map = skyMap(settingsOf(model, sunTowards(radians(zs), 1.0)), 64);
            for (int y = 0; y < map.height(); ++y) {
                for (int x = 0; x < map.width(); ++x) {
                    const float L = map.at(x, y, 0);
                    ASSERT_TRUE(std::isfinite(L) && (y < map.height() / 2 ? L > 0.0f : L >= 0.0f))
                        << x << ", " << y << ", Zs " << zs;
                }
            }
        }
    }
}

}  // namespace
}  // namespace penumbra::test
