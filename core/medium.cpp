#include "core/medium.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

Medium::Medium(const MediumDesc& desc, const Bounds3& box)
    : box_(desc.density ? desc.density->box() : box),
      sigmaS_(desc.sigmaS),
      sigmaT_(desc.sigmaA + desc.sigmaS),
      sigmaA_(desc.sigmaA),
      emission_(desc.emission),
      phase_(desc.g),
      density_(desc.density) {}

std::optional<Medium::Span> Medium::span(const Ray& ray, float tMax) const {
    // The slab test (Kay and Kajiya 1986): the ray's entry into and exit from each axis's slab.
    float t0 = 0.0f, t1 = tMax;
    for (int axis = 0; axis < 3; ++axis) {
        const float inverse = 1.0f / ray.d[axis];
        float near = (box_.lo[axis] - ray.o[axis]) * inverse;
        float far = (box_.hi[axis] - ray.o[axis]) * inverse;
        if (near > far)
            std::swap(near, far);
        // A ray parallel to a slab outside it gives NaN or an empty interval: no overlap.
        if (!(near <= far))
            return std::nullopt;
        t0 = std::max(t0, near);
        t1 = std::min(t1, far);
        if (!(t0 < t1))
            return std::nullopt;
    }
    return Span{t0, t1};
}

float Medium::opticalLength(const Ray& ray, float t0, float t1) const {
    return density_ ? density_->integral(ray, t0, t1) : t1 - t0;
}

Color Medium::transmittance(const Ray& ray, float tMax) const {
    const std::optional<Span> s = span(ray, tMax);
    return s ? transmittance(ray, s->t0, s->t1) : Color(1.0f);
}

Color Medium::transmittance(const Ray& ray, float t0, float t) const {
    return glm::exp(-sigmaT_ * opticalLength(ray, t0, t));
}

Color Medium::emitted(const Ray& ray, const Span& span) const {
    if (!emits())
        return Color(0.0f);
    const Color T = transmittance(ray, span.t0, span.t1);
    Color L(0.0f);
    for (int c = 0; c < 3; ++c) {
        if (sigmaT_[c] > 0.0f)
            L[c] = emission_[c] * sigmaA_[c] / sigmaT_[c] * (1.0f - T[c]);
    }
    return L;
}

float Medium::channelsPdf(float D) const {
    // The density of the three channels' strategies together (balance heuristic), each
    // sigma_t exp(-sigma_t D) per unit of density at the event.
    const Color T = glm::exp(-sigmaT_ * D);
    return (sigmaT_[0] * T[0] + sigmaT_[1] * T[1] + sigmaT_[2] * T[2]) / 3.0f;
}

float Medium::flightPdf(const Ray& ray, float t0, float t) const {
    if (!scatters())
        return 0.0f;
    const float densityAtEvent = density_ ? density_->at(ray.o + t * ray.d) : 1.0f;
    return densityAtEvent * channelsPdf(opticalLength(ray, t0, t));
}

Medium::Flight Medium::sampleFlight(const Ray& ray, const Span& span, float uChannel,
                                    float uDistance) const {
    if (!scatters())
        return {false, 0.0f, transmittance(ray, span.t0, span.t1)};
    const int channel = std::min(int(uChannel * 3.0f), 2);
    const float sigma = sigmaT_[channel];
    // The optical length D to the event in the chosen channel (its optical depth sigma D drawn
    // from an exponential); infinite where that channel is clear.
    const float D =
        sigma > 0.0f ? -std::log1p(-std::min(uDistance, 0.99999994f)) / sigma : INFINITY;
    std::optional<float> t;
    if (!density_) {
        if (D < span.t1 - span.t0)
            t = span.t0 + D;
    } else if (D < INFINITY) {
        t = density_->invertIntegral(ray, span.t0, span.t1, D);
    }
    // The event's weight T sigma_s / pdf, the density at the event cancelled.
    if (t)
        return {true, *t, glm::exp(-sigmaT_ * D) * sigmaS_ / channelsPdf(D)};
    const Color T = transmittance(ray, span.t0, span.t1);
    const float pass = (T[0] + T[1] + T[2]) / 3.0f;
    return {false, 0.0f, T / pass};
}

}  // namespace penumbra
