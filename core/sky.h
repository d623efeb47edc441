// Skies as environment lights (core/environment_light.h): the radiance of the sky vault from a
// sky model, written into an equirectangular map in the world's frame (+Y the zenith), with a
// ground of uniform luminance below the horizon.
//
// Models (the names of `--sky`):
//  - "uniform": the same luminance everywhere above the horizon (CIE general sky type 5);
//  - "cie-overcast": the CIE standard overcast sky (Moon and Spencer 1942, kept by ISO 15469 /
//    CIE S 011 as a separate formula), L(Z) = L_z (1 + 2 cos Z) / 3, Z the zenith angle;
//  - "cie:1", "cie:3", "cie:5": the CIE standard general skies whose luminance does not depend on
//    the sun (their indicatrix is 1: c = 0, e = 0), L(Z) = L_z phi(Z) / phi(0) with the gradation
//    phi(Z) = 1 + a exp(b / cos Z) (ISO 15469:2004, Table 1: type 1 a = 4, b = -0.7; type 3
//    a = 1.1, b = -0.8; type 5 a = 0, b = -1).
// The other types and the clear skies need the sun's position, which is not modelled yet.
//
// Units: horizontalIlluminance is the sky's unobstructed horizontal illuminance E_h in lux
// (the ground excluded); the sky's luminance is scaled so that its integral of L cos Z over the
// upper hemisphere is E_h. Below the horizon the ground glows with luminance R E_h / pi, R the
// ground reflectance (as Radiance's gensky). The map is grey: each channel carries the
// luminance, in cd/m².
#pragma once

#include "core/image.h"

#include <string>

namespace penumbra {

struct SkySettings {
    std::string model = "cie-overcast";
    float horizontalIlluminance = 10000.0f;  // lux, > 0
    float groundReflectance = 0.2f;          // in [0, 1]
};

// The sky's relative luminance L / L_z at zenith angle Z (radians, in [0, pi/2]). Throws
// std::invalid_argument for a model that is not one of the names above (the message lists them).
double skyRelativeLuminance(const std::string& model, double zenithAngle);

// The zenith luminance L_z (cd/m²) of `settings`: E_h over the integral of the relative
// luminance times cos Z over the upper hemisphere (computed by the midpoint rule on 4 096 rings,
// which is exact to 1e-7 for these smooth functions).
double skyZenithLuminance(const SkySettings& settings);

// The map: width x width / 2 pixels, each the luminance at its centre's direction. Throws
// std::invalid_argument for a bad model, a horizontal illuminance that is not > 0 or a reflectance
// outside [0, 1] (the callers check their own first, to name the option).
Image skyMap(const SkySettings& settings, int width = 1024);

// The names `--sky` accepts, for messages.
const char* skyModelNames();

}  // namespace penumbra
