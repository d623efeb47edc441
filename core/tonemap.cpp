#include "core/tonemap.h"

#include "core/errors.h"
#include "core/texture.h"

#include <cmath>
#include <initializer_list>
#include <string>

namespace penumbra {
namespace {

float applyOperator(ToneMapOperator op, float x) {
    switch (op) {
        case ToneMapOperator::Clamp:
            return glm::clamp(x, 0.0f, 1.0f);
        case ToneMapOperator::Reinhard:
            // L_d = L / (1 + L) (Reinhard et al. 2002, "Photographic Tone Reproduction for
            // Digital Images", Eq. 3), applied to each channel rather than to luminance.
            return x / (1.0f + x);
        case ToneMapOperator::Aces: {
            // Narkowicz's fit of the ACES RRT + ODT (sRGB/Rec. 709 without its gamma):
            // x (a x + b) / (x (c x + d) + e), then saturate; input pre-exposed so that 1 maps to
            // ~0.8 (Narkowicz 2016, "ACES Filmic Tone Mapping Curve", knarkowicz.wordpress.com,
            // 2016-01-06).
            constexpr float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
            return glm::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0f, 1.0f);
        }
    }
    return 0.0f;
}

}  // namespace

ToneMapOperator parseToneMapOperator(std::string_view name) {
    for (ToneMapOperator op :
         {ToneMapOperator::Clamp, ToneMapOperator::Reinhard, ToneMapOperator::Aces}) {
        if (name == toneMapOperatorName(op)) {
            return op;
        }
    }
    throw UsageError("--tonemap: unknown tone-mapping operator \"" + std::string(name) +
                     "\" (valid: clamp, reinhard, aces)");
}

std::string_view toneMapOperatorName(ToneMapOperator op) {
    switch (op) {
        case ToneMapOperator::Clamp:
            return "clamp";
        case ToneMapOperator::Reinhard:
            return "reinhard";
        case ToneMapOperator::Aces:
            return "aces";
    }
    return "clamp";
}

Color ToneMapping::apply(const Color& linear) const {
    const float scale = std::exp2(exposure);
    Color out;
    for (int c = 0; c < 3; ++c) {
        out[c] = applyOperator(op, glm::max(linear[c] * scale, 0.0f));
    }
    return out;
}

uint8_t encodeSrgb8(float displayLinear) {
    const float encoded = linearToSrgb(glm::clamp(displayLinear, 0.0f, 1.0f));
    return uint8_t(std::lround(glm::clamp(encoded, 0.0f, 1.0f) * 255.0f));
}

}  // namespace penumbra
