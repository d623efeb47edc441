#include "core/sky.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace penumbra {

namespace {

using std::numbers::pi;

// ISO 15469:2004 / CIE S 011/E:2003, Table 1, as Darula and Kittler publish it ("CIE general
// sky standard defining luminance distributions", eSim 2002): each type combines one of six
// gradation groups (a, b: I 4, -0.7; II 1.1, -0.8; III 0, -1; IV -1, -0.55; V -1, -0.32;
// VI -1, -0.15) with one of six indicatrix groups (c, d, e: 1 0, -1, 0; 2 2, -1.5, 0.15;
// 3 5, -2.5, 0.30; 4 10, -3, 0.45; 5 16, -3, 0.30; 6 24, -2.8, 0.15). The same fifteen rows are
// in colour-science's CIE 2003 sky (which names each row's groups) and in the CIE lighting
// toolbox's ciesky.m, both from ISO 15469:2004. Type 7's e is 0.30, not the 0.35 a transcription
// gives: type 7 is indicatrix group 3, as type 10 is, whose e is 0.30 in every source, and the
// three sources give 0.30 for type 7 itself. (A table with other a, b and d for types 6 to 15
// circulates too; it cannot be the standard's, whose type 12 is the CIE clear sky, c = 10,
// d = -3, e = 0.45.)
constexpr std::array<CieSkyParameters, 15> kGeneralSkies = {{
    {4.0, -0.70, 0.0, -1.0, 0.00},    // 1: I.1, overcast, steep gradation, azimuthal uniformity
    {4.0, -0.70, 2.0, -1.5, 0.15},    // 2: I.2, overcast, slight brightening towards the sun
    {1.1, -0.80, 0.0, -1.0, 0.00},    // 3: II.1, overcast, moderately graded, uniform in azimuth
    {1.1, -0.80, 2.0, -1.5, 0.15},    // 4: II.2, overcast, moderately graded, towards the sun
    {0.0, -1.00, 0.0, -1.0, 0.00},    // 5: III.1, uniform luminance
    {0.0, -1.00, 2.0, -1.5, 0.15},    // 6: III.2, partly cloudy, slight brightening to the sun
    {0.0, -1.00, 5.0, -2.5, 0.30},    // 7: III.3, partly cloudy, brighter circumsolar region
    {0.0, -1.00, 10.0, -3.0, 0.45},   // 8: III.4, partly cloudy, distinct solar corona
    {-1.0, -0.55, 2.0, -1.5, 0.15},   // 9: IV.2, partly cloudy, the sun obscured
    {-1.0, -0.55, 5.0, -2.5, 0.30},   // 10: IV.3, partly cloudy, brighter circumsolar region
    {-1.0, -0.55, 10.0, -3.0, 0.45},  // 11: IV.4, white-blue sky, distinct solar corona
    {-1.0, -0.32, 10.0, -3.0, 0.45},  // 12: V.4, CIE standard clear sky, low turbidity
    {-1.0, -0.32, 16.0, -3.0, 0.30},  // 13: V.5, CIE standard clear sky, polluted atmosphere
    {-1.0, -0.15, 16.0, -3.0, 0.30},  // 14: VI.5, cloudless turbid sky, broad solar corona
    {-1.0, -0.15, 24.0, -2.8, 0.15},  // 15: VI.6, white-blue turbid sky, broad solar corona
}};

// A model of sky.h by the form of its gradation phi and indicatrix f.
struct SkyModel {
    enum class Form { Overcast, Clear, General };
    Form form = Form::General;
    CieSkyParameters p{};  // Form::General only
    bool needsSun = false;

    // phi(Z), with cos Z held at 0 below the horizon, where each formula takes its limit.
    double gradation(double zenithAngle) const {
        const double cosZ = std::max(std::cos(zenithAngle), 0.0);
        switch (form) {
            case Form::Overcast:  // Moon and Spencer 1942
                return 1.0 + 2.0 * cosZ;
            case Form::Clear:  // CIE 1973: 1 - exp(-0.32 / cos Z), 1 at the horizon
                return cosZ > 0.0 ? 1.0 - std::exp(-0.32 / cosZ) : 1.0;
            case Form::General:  // ISO 15469: 1 + a exp(b / cos Z), b < 0: 1 at the horizon
                return cosZ > 0.0 ? 1.0 + p.a * std::exp(p.b / cosZ) : 1.0;
        }
        return 1.0;
    }

    // f(chi), chi in [0, pi].
    double indicatrix(double chi) const {
        const double cosChi = std::cos(chi);
        switch (form) {
            case Form::Overcast:
                return 1.0;
            case Form::Clear:  // CIE 1973
                return 0.91 + 10.0 * std::exp(-3.0 * chi) + 0.45 * cosChi * cosChi;
            case Form::General:  // ISO 15469
                return 1.0 + p.c * (std::exp(p.d * chi) - std::exp(p.d * pi / 2.0)) +
                       p.e * cosChi * cosChi;
        }
        return 1.0;
    }
};

SkyModel generalSky(int type) {
    const CieSkyParameters p = cieGeneralSkyParameters(type);
    // f = 1 for every sun when c = e = 0 (types 1, 3, 5).
    return {SkyModel::Form::General, p, p.c != 0.0 || p.e != 0.0};
}

SkyModel findModel(const std::string& name) {
    if (name == "uniform")
        return generalSky(5);
    if (name == "cie-overcast")
        return {SkyModel::Form::Overcast, {}, false};
    if (name == "cie-clear")
        return {SkyModel::Form::Clear, {}, true};
    // "cie:N", N from 1 to 15 in decimal without leading zeros.
    constexpr std::string_view kPrefix = "cie:";
    const std::string_view digits =
        std::string_view(name).substr(name.starts_with(kPrefix) ? kPrefix.size() : name.size());
    int type = 0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), type);
    if (error == std::errc() && end == digits.data() + digits.size() && digits.front() != '0' &&
        type >= 1 && type <= int(kGeneralSkies.size()))
        return generalSky(type);
    throw std::invalid_argument("unknown sky '" + name + "'; valid: " + skyModelNames());
}

std::invalid_argument sunMissing(const std::string& model) {
    return std::invalid_argument("sky '" + model +
                                 "' needs the sun: give --site and --time, or a sun direction");
}

// The unit direction towards the sun of `settings`, when its model needs one.
std::optional<glm::dvec3> sunDirection(const SkySettings& settings, const SkyModel& model) {
    if (!model.needsSun)
        return std::nullopt;
    if (!settings.sunDirection)
        throw sunMissing(settings.model);
    const glm::dvec3 s(*settings.sunDirection);
    const double length = glm::length(s);
    if (!std::isfinite(length) || !(length > 0.0))
        throw std::invalid_argument("sky '" + settings.model +
                                    "': the sun direction must be finite and non-zero");
    return s / length;
}

// The checks of skyMap() and skyZenithLuminance(); returns the model.
SkyModel checkSettings(const SkySettings& settings) {
    if (!(settings.horizontalIlluminance > 0.0f) || !std::isfinite(settings.horizontalIlluminance))
        throw std::invalid_argument("skyMap: the horizontal illuminance must be > 0");
    if (!(settings.groundReflectance >= 0.0f && settings.groundReflectance <= 1.0f))
        throw std::invalid_argument("skyMap: the ground reflectance must be in [0, 1]");
    if (!(settings.sunHorizontalIlluminance >= 0.0f) ||
        !std::isfinite(settings.sunHorizontalIlluminance))
        throw std::invalid_argument("skyMap: the sun's horizontal illuminance must be >= 0");
    return findModel(settings.model);
}

// E_h / L_z = integral over the upper hemisphere of (L / L_z) cos Z dω, dω = sin Z dZ dα, by the
// midpoint rule. The azimuth α is measured from the sun's vertical plane, about which L is
// symmetric, so [0, pi] is integrated and counted twice; chi follows from the spherical law of
// cosines in the triangle of the zenith, the element and the sun (as ISO 15469 computes chi):
// cos chi = cos Z cos Z_s + sin Z sin Z_s cos α.
// The resolution: the error is the midpoint rule's O(h²) in Z, largest where the sun is just
// below the horizon and its glow makes the luminance steep there, plus O(h³) from the cells
// around the cusp of exp(d chi) at the sun; in α the integrand is even and periodic, for which
// the midpoint rule converges much faster. Over every model and sun zenith angles from 0 to 95
// degrees, against the same rule at 8 192 x 4 096, 1 024 rings were at most 1.6e-6 off and 2 048
// rings 3.9e-7 (type 15, the sun 5 degrees below the horizon), the same with 256 azimuths as
// with 1 024; a rule in the sun's own polar coordinates at 8 000 x 4 000, where the cusp is a
// pole, agrees within 4.1e-7 (tests/core/sky_test.cpp runs it coarser). So 2 048 x 256, 13 ms,
// keeps L_z well within 1e-5.
double relativeIlluminance(const SkyModel& model, std::optional<double> sunZenith) {
    constexpr int kRings = 2048, kAzimuths = 256;
    constexpr double dZ = (pi / 2.0) / kRings, dAlpha = pi / kAzimuths;
    std::vector<double> cosAlpha(kAzimuths);
    for (int j = 0; j < kAzimuths; ++j)
        cosAlpha[size_t(j)] = std::cos((j + 0.5) * dAlpha);
    const double phi0 = model.gradation(0.0);
    const double fSun = sunZenith ? model.indicatrix(*sunZenith) : 1.0;
    const double cosZs = sunZenith ? std::cos(*sunZenith) : 1.0;
    const double sinZs = sunZenith ? std::sin(*sunZenith) : 0.0;
    double integral = 0.0;
    for (int i = 0; i < kRings; ++i) {
        const double Z = (i + 0.5) * dZ;
        const double cosZ = std::cos(Z), sinZ = std::sin(Z);
        // The ring's integral of f(chi) / f(Z_s) over α in [0, pi].
        double ring = pi;
        if (sunZenith) {
            ring = 0.0;
            for (double c : cosAlpha) {
                const double cosChi = std::clamp(cosZ * cosZs + sinZ * sinZs * c, -1.0, 1.0);
                ring += model.indicatrix(std::acos(cosChi));
            }
            ring *= dAlpha / fSun;
        }
        integral += model.gradation(Z) / phi0 * ring * cosZ * sinZ;
    }
    return 2.0 * integral * dZ;
}

// A sky of sky.h made from checked settings.
struct Sky {
    SkyModel model;
    std::optional<glm::dvec3> sun;  // unit, when the model needs it
    double fSun = 1.0;              // f(Z_s)
    double zenithLuminance = 0.0;   // L_z, cd/m²
};

Sky makeSky(const SkySettings& settings) {
    Sky sky;
    sky.model = checkSettings(settings);
    sky.sun = sunDirection(settings, sky.model);
    std::optional<double> sunZenith;
    if (sky.sun) {
        sunZenith = std::acos(std::clamp(sky.sun->y, -1.0, 1.0));
        sky.fSun = sky.model.indicatrix(*sunZenith);
    }
    sky.zenithLuminance =
        settings.horizontalIlluminance / relativeIlluminance(sky.model, sunZenith);
    return sky;
}

}  // namespace

CieSkyParameters cieGeneralSkyParameters(int type) {
    if (type < 1 || type > int(kGeneralSkies.size()))
        throw std::invalid_argument("CIE general sky type " + std::to_string(type) +
                                    ": the types are 1 to 15");
    return kGeneralSkies[size_t(type - 1)];
}

const char* skyModelNames() {
    return "uniform, cie-overcast, cie:1, cie:3, cie:5, and with the sun: cie-clear, cie:2, "
           "cie:4, cie:6, cie:7, cie:8, cie:9, cie:10, cie:11, cie:12, cie:13, cie:14, cie:15";
}

bool skyNeedsSun(const std::string& model) {
    return findModel(model).needsSun;
}

double skyRelativeLuminance(const std::string& model, double zenithAngle,
                            std::optional<SunAngles> sun) {
    const SkyModel m = findModel(model);
    const double gradation = m.gradation(zenithAngle) / m.gradation(0.0);
    if (!m.needsSun)
        return gradation;
    if (!sun)
        throw sunMissing(model);
    return gradation * m.indicatrix(sun->distance) / m.indicatrix(sun->zenith);
}

double skyZenithLuminance(const SkySettings& settings) {
    return makeSky(settings).zenithLuminance;
}

Image skyMap(const SkySettings& settings, int width) {
    const Sky sky = makeSky(settings);
    const double phi0 = sky.model.gradation(0.0);
    // The ground: a Lambertian reflector of the sky's and the sun's illuminance.
    const double ground =
        settings.groundReflectance *
        (double(settings.horizontalIlluminance) + double(settings.sunHorizontalIlluminance)) / pi;
    const int height = width / 2;
    Image map(width, height, {"R", "G", "B"});
    for (int y = 0; y < height; ++y) {
        // Row y's centre is at zenith angle (y + 1/2) pi / height (the map's v = Z / pi).
        const double Z = (y + 0.5) * pi / height;
        const double rowL = sky.zenithLuminance * sky.model.gradation(Z) / phi0;
        for (int x = 0; x < width; ++x) {
            double L = ground;
            if (Z < pi / 2.0) {
                L = rowL;
                if (sky.sun) {
                    // The direction of the pixel's centre (core/environment_light.h):
                    // (sin Z sin 2 pi u, cos Z, -sin Z cos 2 pi u).
                    const double turn = 2.0 * pi * (x + 0.5) / width;
                    const glm::dvec3 d(std::sin(Z) * std::sin(turn), std::cos(Z),
                                       -std::sin(Z) * std::cos(turn));
                    const double cosChi = std::clamp(glm::dot(d, *sky.sun), -1.0, 1.0);
                    L *= sky.model.indicatrix(std::acos(cosChi)) / sky.fSun;
                }
            }
            for (int c = 0; c < 3; ++c)
                map.at(x, y, c) = static_cast<float>(L);
        }
    }
    return map;
}

}  // namespace penumbra
