// Histogram adjustment: the visibility-matching tone reproduction operator of Ward Larson,
// Rushmeier and Piatko, "A Visibility Matching Tone Reproduction Operator for High Dynamic Range
// Scenes" (IEEE TVCG 3(4), 1997; section and equation numbers as in its report LBNL-39882). A
// global tone curve made from the histogram of the scene's 1° (foveal) adaptation luminances,
// its slope capped so that the display never shows a contrast that a viewer of the real scene
// could not see (or, without the human model, never more contrast than a linear mapping shows),
// and optionally the eye's loss of acuity in the dark. The paper's veiling glare (§5.1) and
// mesopic loss of colour (§5.2) are not modelled.
#pragma once

#include "core/image.h"

#include <array>
#include <span>

namespace penumbra {

struct HistogramAdjustmentSettings {
    float displayMinimum = 1.0f;    // cd/m², the display's black, Ld_min
    float displayMaximum = 100.0f;  // cd/m², its white, Ld_max (kWardDisplayMaximum)
    // Cap the histogram by the ratio of the human detection thresholds at the display and world
    // luminances (§4.5, Eq. 7c); false caps it by the linear ceiling alone (§4.4, Eq. 5c).
    bool humanContrast = true;
    // Blur each place as the eye resolves detail at its adaptation luminance (§5.3).
    bool humanAcuity = false;
    // Of the image, a perspective view with square pixels: it sizes the 1° foveal samples (Eq. 1)
    // and the acuity blur in pixels.
    float horizontalFieldOfViewDegrees = 39.6f;
};

// ΔL_t(L_a), cd/m²: the just-noticeable luminance difference at adaptation luminance L_a
// (cd/m²), the paper's Table 1 (Eq. 6): Ferwerda et al. 1996's rod and cone threshold fits,
// joined at their crossover 10^-0.0184 cd/m². It is 10^-2.86 below 10^-3.94 cd/m², and for 0 or
// a non-finite L_a.
float detectionThreshold(float adaptationLuminance);

// R(L_a), cycles per degree: the finest grating resolved at adaptation luminance L_a (cd/m²),
// the paper's fit to Shaler's data (Eq. 15). L_a is floored at 1e-4 cd/m², the lower threshold of
// vision (§4.2), where R = 1.87; the fit would turn negative below 6e-10 cd/m².
float visualAcuity(float adaptationLuminance);

// The tone curve of one scene: world luminance to display luminance.
class HistogramToneCurve {
  public:
    static constexpr int kBins = 100;  // the paper's choice for all its examples (§4.2)

    // From the scene's foveal adaptation samples, cd/m²: a non-finite or negative sample counts
    // as 0, and all are floored at 1e-4 cd/m² (§4.2). Throws std::invalid_argument unless
    // 0 < Ld_min < Ld_max < infinity.
    HistogramToneCurve(std::span<const float> adaptationLuminances,
                       const HistogramAdjustmentSettings& settings);

    // Ld (cd/m²) of world luminance Lw (cd/m²), nondecreasing in Lw and at most Ld_max. The
    // histogram curve spans [Ld_min, Ld_max] from the dimmest sample to the brightest; the
    // linear one is m Lw and may fall below Ld_min, which the display shows as its black.
    float displayLuminance(float worldLuminance) const;

    // Whether the curve is the linear operator Ld = m Lw: when the samples' range fits the
    // display's (§4.4, Eq. 5d), or when the ceiling iteration fails to converge.
    bool isLinear() const { return linear_; }

    // T / T_0, the share of the samples that the histogram keeps under the ceiling (1 when
    // linear). The iteration stops once a pass trims at most 2.5% of T_0 (§4.4), so the final T is
    // lower than the one of the last ceilings by up to that much: the curve's slope may exceed
    // the linear ceiling (Eq. 5c) by a factor 1 + 0.025 / keptFraction(), and the human one
    // (Eq. 7c) also moves with the Ld that the last trims shift.
    double keptFraction() const { return keptFraction_; }

  private:
    bool trimToCeiling(std::array<double, kBins>& counts, bool humanContrast);
    void setCumulative(const std::array<double, kBins>& counts);
    double displayBrightness(double worldBrightness) const;

    double displayMinimum_, displayMaximum_;
    double brightnessMinimum_ = 0.0, brightnessMaximum_ = 0.0;  // log(cd/m²), the histogram's ends
    std::array<double, kBins + 1> cumulative_{};                // P(b) at the bin edges (Eq. 2)
    bool linear_ = true;
    double keptFraction_ = 1.0;
    double scale_ = 0.0;  // m, of the linear operator
};

// The operator on a scene-linear image (channels "R", "G", "B" in cd/m², others ignored; a
// non-finite or negative value counts as 0), in the paper's order (§6): the foveal samples, the
// acuity blur, the histogram and its ceiling, the mapping. Returns an image of the same size,
// channels "R", "G", "B", display-linear in [0, 1]: each pixel's colour scaled so that its Rec. 709
// luminance is v = (Ld - Ld_min) / (Ld_max - Ld_min), which a display of black Ld_min and white
// Ld_max shows as Ld (the paper's §6: the display's black is subtracted before its encoding), each
// channel then clipped at 1. Throws std::invalid_argument if a channel is missing or the
// settings are out of range (the field of view in (0°, 180°)).
Image histogramAdjust(const Image& sceneLinear, const HistogramAdjustmentSettings& settings = {});

}  // namespace penumbra
