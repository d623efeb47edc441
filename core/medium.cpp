#include "core/medium.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

HomogeneousMedium::HomogeneousMedium(const MediumDesc& desc, const Bounds3& box)
    : box_(box), sigmaS_(desc.sigmaS), sigmaT_(desc.sigmaA + desc.sigmaS), phase_(desc.g) {}

std::optional<HomogeneousMedium::Span> HomogeneousMedium::span(const Ray& ray, float tMax) const {
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

Color HomogeneousMedium::transmittance(const Ray& ray, float tMax) const {
    const std::optional<Span> s = span(ray, tMax);
    return s ? glm::exp(-sigmaT_ * (s->t1 - s->t0)) : Color(1.0f);
}

float HomogeneousMedium::flightPdf(float distance) const {
    if (!scatters())
        return 0.0f;
    // The density of the three channels' strategies together (balance heuristic).
    const Color T = glm::exp(-sigmaT_ * distance);
    return (sigmaT_[0] * T[0] + sigmaT_[1] * T[1] + sigmaT_[2] * T[2]) / 3.0f;
}

HomogeneousMedium::Flight HomogeneousMedium::sampleFlight(const Span& span, float uChannel,
                                                          float uDistance) const {
    const float length = span.t1 - span.t0;
    if (!scatters())
        return {false, 0.0f, glm::exp(-sigmaT_ * length)};
    const int channel = std::min(int(uChannel * 3.0f), 2);
    const float sigma = sigmaT_[channel];
    // Distance to the event in the chosen channel's exponential; infinite where it is clear.
    const float distance =
        sigma > 0.0f ? -std::log1p(-std::min(uDistance, 0.99999994f)) / sigma : INFINITY;
    if (distance < length)
        return {true, span.t0 + distance,
                glm::exp(-sigmaT_ * distance) * sigmaS_ / flightPdf(distance)};
    const Color T = glm::exp(-sigmaT_ * length);
    const float pass = (T[0] + T[1] + T[2]) / 3.0f;
    return {false, 0.0f, T / pass};
}

}  // namespace penumbra
