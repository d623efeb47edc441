// Display transforms for 8-bit outputs: exposure, a tone-mapping operator, and the sRGB encoding.
// Float (EXR) outputs stay scene-linear and are never tone-mapped.
#pragma once

#include "core/math.h"

#include <cstdint>
#include <string_view>

namespace penumbra {

enum class ToneMapOperator { Clamp, Reinhard, Aces };

// "clamp", "reinhard" or "aces"; anything else throws UsageError listing these.
ToneMapOperator parseToneMapOperator(std::string_view name);
std::string_view toneMapOperatorName(ToneMapOperator op);

struct ToneMapping {
    float exposure = 0.0f;  // EV: linear values are multiplied by 2^exposure first
    ToneMapOperator op = ToneMapOperator::Clamp;

    // Scene-linear colour (cd/m²; 1 maps to display white under clamp) to display-linear values
    // in [0, 1], per channel. Negative inputs count as 0.
    Color apply(const Color& linear) const;
};

// 8-bit code value of a display-linear value in [0, 1] (clamped): the IEC 61966-2-1 sRGB
// encoding, then rounding to the nearest of 0..255.
uint8_t encodeSrgb8(float displayLinear);

}  // namespace penumbra
