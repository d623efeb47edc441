// Display transforms for 8-bit outputs: exposure, a tone-mapping operator, and the sRGB encoding.
// Float (EXR) outputs stay scene-linear and are never tone-mapped.
#pragma once

#include "core/image.h"
#include "core/math.h"

#include <cstdint>
#include <string_view>

namespace penumbra {

enum class ToneMapOperator { Clamp, Reinhard, Aces, Ward, Histogram, Human };

// "clamp", "reinhard", "aces", "ward", "histogram" or "human"; anything else throws UsageError
// listing these.
ToneMapOperator parseToneMapOperator(std::string_view name);
std::string_view toneMapOperatorName(ToneMapOperator op);

// Ward 1994 ("A contrast-based scalefactor for luminance display", Graphics Gems IV): the
// display's maximum luminance, cd/m², that its scale factor maps to display white.
inline constexpr float kWardDisplayMaximum = 100.0f;

struct ToneMapping {
    float exposure = 0.0f;  // EV: linear values are multiplied by 2^exposure first
    ToneMapOperator op = ToneMapOperator::Clamp;
    // Ward: the world adaptation luminance L_wa (cd/m²), the log-average of the image's
    // (wardAdaptationLuminance()); the default is the display's own adaptation, which maps
    // cd/m² to display luminance one to one.
    float adaptationLuminance = 0.5f * kWardDisplayMaximum;
    // Histogram and Human: the view's horizontal field of view, which sizes the eye's foveal
    // samples and its acuity in pixels (core/histogram_adjustment.h).
    float horizontalFieldOfViewDegrees = 39.6f;

    // Scene-linear colour (cd/m²; 1 maps to display white under clamp) to display-linear values
    // in [0, 1], per channel. Negative inputs count as 0. Not for the operators that adapt to
    // the whole image (histogram, human): toneMapImage() applies every operator.
    Color apply(const Color& linear) const;
};

// The display-linear image, channels R, G, B in [0, 1], of a scene-linear one (channels R, G, B,
// finite): exposure, then the operator, pixel by pixel, or over the whole image for
//  - histogram: Ward Larson, Rushmeier and Piatko 1997's histogram adjustment with the human
//    contrast sensitivity ceiling (core/histogram_adjustment.h), on a display of 1 to 100 cd/m²;
//  - human: the same and the loss of visual acuity in dim light (their section 5.3), as
//    Radiance's `pcond -h` mimics human vision.
Image toneMapImage(const Image& sceneLinear, const ToneMapping& toneMapping);

// Ward's scale factor m, display luminance over world luminance: at world adaptation L_wa a
// just-noticeable difference of luminance maps to one at the display's adaptation,
// Ld_max / 2 (Ward 1994, after Blackwell's contrast sensitivity):
//     m = [(1.219 + (Ld_max / 2)^0.4) / (1.219 + L_wa^0.4)]^2.5,
// and the display value is m L / Ld_max.
float wardScaleFactor(float adaptationLuminance);

// The world adaptation luminance of an image for Ward's operator: the log-average of its pixels'
// Rec. 709 luminance, exp(mean(log(1e-4 + Y))) (the floor keeps black pixels finite).
float wardAdaptationLuminance(const Image& image);

// Automatic exposure, EV: the one that shows the image's log-average luminance (as
// wardAdaptationLuminance) at middle grey, 0.18 (Reinhard et al. 2002's "key" of a normal scene,
// their Eq. 2), log2(0.18 / L_avg).
float automaticExposure(const Image& image);

// 8-bit code value of a display-linear value in [0, 1] (clamped): the IEC 61966-2-1 sRGB
// encoding, then rounding to the nearest of 0..255.
uint8_t encodeSrgb8(float displayLinear);

}  // namespace penumbra
