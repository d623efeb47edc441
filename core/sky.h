// Skies as environment lights (core/environment_light.h): the radiance of the sky vault from a
// sky model, written into an equirectangular map in the world's frame (+Y the zenith), with a
// ground of uniform luminance below the horizon.
//
// Every model has the form of the CIE standard general sky (ISO 15469:2004 / CIE S 011/E:2003):
// the luminance of a sky element at zenith angle Z, an angle chi from the sun whose zenith angle
// is Z_s, relative to the zenith's,
//     L / L_z = phi(Z) f(chi) / (phi(0) f(Z_s)),
// phi the gradation (how the luminance changes from the zenith to the horizon) and f the
// scattering indicatrix (how it changes with the distance from the sun). Models (the names of
// `--sky`):
//  - "uniform": phi = f = 1, the same luminance everywhere above the horizon (general type 5);
//  - "cie-overcast": the CIE standard overcast sky (Moon and Spencer 1942, kept by ISO 15469 as a
//    separate formula, "type 16"), phi(Z) = 1 + 2 cos Z, f = 1;
//  - "cie-clear": the CIE standard clear sky (CIE 1973, after Kittler 1967; the sunny sky of
//    Radiance's gensky), phi(Z) = 1 - exp(-0.32 / cos Z), f(chi) = 0.91 + 10 exp(-3 chi) +
//    0.45 cos² chi;
//  - "cie:1" ... "cie:15": the 15 general skies, phi(Z) = 1 + a exp(b / cos Z) and
//    f(chi) = 1 + c (exp(d chi) - exp(d pi/2)) + e cos² chi, with a ... e the type's row of
//    ISO 15469 Table 1 (cieGeneralSkyParameters()). Type 12 is the clear sky again, up to the
//    rounding of 1 - 10 exp(-3 pi/2) = 0.91017 to 0.91.
// Types 1, 3 and 5 (c = e = 0, so f = 1), "uniform" and "cie-overcast" do not depend on the sun;
// the others need its direction. Where the formulas need cos Z > 0, Z is held at the horizon
// (their limit there); a sun below the horizon is allowed (the indicatrix is defined for every
// chi and Z_s in [0, pi]) and every model stays finite and > 0.
//
// Units: horizontalIlluminance is the sky's unobstructed horizontal illuminance E_h in lux
// (the ground excluded); the sky's luminance is scaled so that its integral of L cos Z over the
// upper hemisphere is E_h. Below the horizon the ground, a diffuse reflector of reflectance R
// lit by the sky and the sun, glows with luminance R (E_h + E_sun) / pi, E_sun the sun's
// horizontal illuminance (as Radiance's gensky). The map is grey: each channel carries the
// luminance, in cd/m².
#pragma once

#include "core/image.h"
#include "core/math.h"

#include <optional>
#include <string>

namespace penumbra {

struct SkySettings {
    std::string model = "cie-overcast";
    float horizontalIlluminance = 10000.0f;  // lux, > 0
    float groundReflectance = 0.2f;          // in [0, 1]
    // The sun's illuminance on the ground (lux, finite, >= 0): its direct normal illuminance
    // times cos Z_s, 0 without a sun disc. Only the ground's glow counts it; the sky's luminance
    // is E_h's alone.
    float sunHorizontalIlluminance = 0.0f;
    // Towards the sun, in world axes (+Y up): finite and non-zero, normalised here. Needed by the
    // models that depend on the sun (skyNeedsSun()), ignored by the others.
    std::optional<Vec3> sunDirection;
};

// One row of ISO 15469:2004 Table 1: the gradation parameters a, b and the indicatrix
// parameters c, d, e of a CIE standard general sky.
struct CieSkyParameters {
    double a, b, c, d, e;
};

// The parameters of general sky `type`, 1 to 15. Throws std::invalid_argument for another type.
CieSkyParameters cieGeneralSkyParameters(int type);

// Where the sun is as a sky element sees it, in radians: the sun's zenith angle Z_s, in [0, pi]
// (above pi/2 when it is below the horizon), and the angular distance chi from the element to
// the sun, in [0, pi].
struct SunAngles {
    double zenith = 0.0;
    double distance = 0.0;
};

// Whether `model` needs the sun's direction. Throws std::invalid_argument for a model that is not
// one of the names above (the message lists them).
bool skyNeedsSun(const std::string& model);

// The sky's relative luminance L / L_z at zenith angle Z (radians, in [0, pi/2]) with the sun
// where `sun` says. Throws std::invalid_argument for an unknown model, or for a model that needs
// the sun when `sun` is empty; the models that do not need it ignore it.
double skyRelativeLuminance(const std::string& model, double zenithAngle,
                            std::optional<SunAngles> sun = std::nullopt);

// The zenith luminance L_z (cd/m²) of `settings`: E_h over the integral of the relative
// luminance times cos Z over the upper hemisphere, by the midpoint rule on 2 048 rings of zenith
// angle times 256 azimuths over the half of the sky on one side of the sun's vertical plane (the
// luminance is symmetric about it): accurate to 1e-6 relative for every model and sun (measured,
// sky.cpp). Throws std::invalid_argument as skyMap() does.
double skyZenithLuminance(const SkySettings& settings);

// The map: width x width / 2 pixels, each the luminance at its centre's direction, by the
// mapping of core/environment_light.h (the top row the zenith, the left edge looking along -Z,
// a quarter across along +X): an EnvironmentLight whose worldToLocal is the identity shows the
// sun's glow towards settings.sunDirection. Throws std::invalid_argument for an unknown model, a
// model that needs the sun without a valid sun direction, a horizontal illuminance that is not
// > 0, a reflectance outside [0, 1] or a sun's horizontal illuminance that is not finite and >= 0
// (the callers check their own first, to name the option).
Image skyMap(const SkySettings& settings, int width = 1024);

// The names `--sky` accepts, for messages.
const char* skyModelNames();

}  // namespace penumbra
