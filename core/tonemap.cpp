#include "core/tonemap.h"

#include "core/errors.h"
#include "core/histogram_adjustment.h"
#include "core/texture.h"

#include <algorithm>
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
        case ToneMapOperator::Ward:       // scaled in apply(): clamp to the display's range
        case ToneMapOperator::Histogram:  // whole-image operators: toneMapImage()
        case ToneMapOperator::Human:
            return glm::clamp(x, 0.0f, 1.0f);
    }
    return 0.0f;
}

}  // namespace

ToneMapOperator parseToneMapOperator(std::string_view name) {
    for (ToneMapOperator op :
         {ToneMapOperator::Clamp, ToneMapOperator::Reinhard, ToneMapOperator::Aces,
          ToneMapOperator::Ward, ToneMapOperator::Histogram, ToneMapOperator::Human}) {
        if (name == toneMapOperatorName(op)) {
            return op;
        }
    }
    throw UsageError("--tonemap: unknown tone-mapping operator \"" + std::string(name) +
                     "\" (valid: clamp, reinhard, aces, ward, histogram, human)");
}

std::string_view toneMapOperatorName(ToneMapOperator op) {
    switch (op) {
        case ToneMapOperator::Clamp:
            return "clamp";
        case ToneMapOperator::Reinhard:
            return "reinhard";
        case ToneMapOperator::Aces:
            return "aces";
        case ToneMapOperator::Ward:
            return "ward";
        case ToneMapOperator::Histogram:
            return "histogram";
        case ToneMapOperator::Human:
            return "human";
    }
    return "clamp";
}

Color ToneMapping::apply(const Color& linear) const {
    const float ward = op == ToneMapOperator::Ward
                           ? wardScaleFactor(adaptationLuminance) / kWardDisplayMaximum
                           : 1.0f;
    const float scale = std::exp2(exposure) * ward;
    Color out;
    for (int c = 0; c < 3; ++c) {
        out[c] = applyOperator(op, glm::max(linear[c] * scale, 0.0f));
    }
    return out;
}

float wardScaleFactor(float adaptationLuminance) {
    const double display = std::pow(0.5 * double(kWardDisplayMaximum), 0.4);
    const double world = std::pow(std::max(double(adaptationLuminance), 0.0), 0.4);
    return float(std::pow((1.219 + display) / (1.219 + world), 2.5));
}

float wardAdaptationLuminance(const Image& image) {
    double sum = 0.0;
    size_t count = 0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            const Color c(image.at(x, y, 0), image.at(x, y, std::min(1, image.channels() - 1)),
                          image.at(x, y, std::min(2, image.channels() - 1)));
            const float Y = luminance(glm::max(c, Color(0.0f)));
            if (!std::isfinite(Y))
                continue;
            sum += std::log(1e-4 + double(Y));
            ++count;
        }
    return count > 0 ? float(std::exp(sum / double(count))) : 0.0f;
}

uint8_t encodeSrgb8(float displayLinear) {
    const float encoded = linearToSrgb(glm::clamp(displayLinear, 0.0f, 1.0f));
    return uint8_t(std::lround(glm::clamp(encoded, 0.0f, 1.0f) * 255.0f));
}

float automaticExposure(const Image& image) {
    return std::log2(0.18f / wardAdaptationLuminance(image));
}

Image toneMapImage(const Image& sceneLinear, const ToneMapping& toneMapping) {
    const ToneMapOperator op = toneMapping.op;
    if (op == ToneMapOperator::Histogram || op == ToneMapOperator::Human) {
        Image exposed = sceneLinear;
        const float scale = std::exp2(toneMapping.exposure);
        for (float& v : exposed.pixels())
            v *= scale;
        HistogramAdjustmentSettings settings;
        settings.displayMaximum = kWardDisplayMaximum;
        settings.humanAcuity = op == ToneMapOperator::Human;
        settings.horizontalFieldOfViewDegrees = toneMapping.horizontalFieldOfViewDegrees;
        return histogramAdjust(exposed, settings);
    }
    const int r = sceneLinear.channelIndex("R"), g = sceneLinear.channelIndex("G"),
              b = sceneLinear.channelIndex("B");
    Image display(sceneLinear.width(), sceneLinear.height(), {"R", "G", "B"});
    for (int y = 0; y < sceneLinear.height(); ++y) {
        for (int x = 0; x < sceneLinear.width(); ++x) {
            const Color shown = toneMapping.apply(
                Color(sceneLinear.at(x, y, r), sceneLinear.at(x, y, g), sceneLinear.at(x, y, b)));
            for (int c = 0; c < 3; ++c)
                display.at(x, y, c) = shown[c];
        }
    }
    return display;
}

}  // namespace penumbra
