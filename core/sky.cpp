#include "core/sky.h"

#include "core/math.h"

#include <cmath>
#include <stdexcept>

namespace penumbra {

namespace {

// The gradation parameters of the CIE general skies that do not depend on the sun (ISO 15469,
// Table 1).
struct Gradation {
    double a, b;
};

Gradation gradation(const std::string& model) {
    if (model == "cie:1")
        return {4.0, -0.7};
    if (model == "cie:3")
        return {1.1, -0.8};
    if (model == "cie:5" || model == "uniform")
        return {0.0, -1.0};
    throw std::invalid_argument("unknown sky '" + model + "'; valid: " + skyModelNames());
}

// phi(Z) = 1 + a exp(b / cos Z), which tends to 1 at the horizon.
double phi(const Gradation& g, double zenithAngle) {
    const double c = std::cos(zenithAngle);
    return c > 0.0 ? 1.0 + g.a * std::exp(g.b / c) : 1.0;
}

}  // namespace

const char* skyModelNames() {
    return "uniform, cie-overcast, cie:1, cie:3, cie:5 (the other CIE skies need the sun, not "
           "modelled yet)";
}

double skyRelativeLuminance(const std::string& model, double zenithAngle) {
    if (model == "cie-overcast")
        return (1.0 + 2.0 * std::cos(zenithAngle)) / 3.0;
    const Gradation g = gradation(model);
    return phi(g, zenithAngle) / phi(g, 0.0);
}

double skyZenithLuminance(const SkySettings& settings) {
    // E_h / L_z = integral over the hemisphere of (L / L_z) cos Z sin Z dZ dphi.
    constexpr int kRings = 4096;
    double integral = 0.0;
    for (int i = 0; i < kRings; ++i) {
        const double Z = (i + 0.5) * (kPi / 2.0) / kRings;
        integral += skyRelativeLuminance(settings.model, Z) * std::cos(Z) * std::sin(Z);
    }
    integral *= 2.0 * kPi * (kPi / 2.0) / kRings;
    return settings.horizontalIlluminance / integral;
}

Image skyMap(const SkySettings& settings, int width) {
    if (!(settings.horizontalIlluminance > 0.0f) || !std::isfinite(settings.horizontalIlluminance))
        throw std::invalid_argument("skyMap: the horizontal illuminance must be > 0");
    if (!(settings.groundReflectance >= 0.0f && settings.groundReflectance <= 1.0f))
        throw std::invalid_argument("skyMap: the ground reflectance must be in [0, 1]");
    const double zenith = skyZenithLuminance(settings);
    const double ground = settings.groundReflectance * settings.horizontalIlluminance / kPi;
    const int height = width / 2;
    Image map(width, height, {"R", "G", "B"});
    for (int y = 0; y < height; ++y) {
        // Row y's centre is at zenith angle (y + 1/2) pi / height (the map's v = Z / pi).
        const double Z = (y + 0.5) * kPi / height;
        const double L = Z < kPi / 2.0 ? zenith * skyRelativeLuminance(settings.model, Z) : ground;
        for (int x = 0; x < width; ++x) {
            for (int c = 0; c < 3; ++c)
                map.at(x, y, c) = static_cast<float>(L);
        }
    }
    return map;
}

}  // namespace penumbra
