#include "raytrace/single_scattering.h"

#include "core/sampler.h"
#include "raytrace/direct_light.h"

namespace penumbra {

Color marchSingleScattering(const Scene& scene, const Medium& medium, const Ray& ray,
                            const Medium::Span& span, int steps, Sampler& sampler,
                            PathCounters& counters) {
    if (!medium.scatters() || steps <= 0)
        return Color(0.0f);
    const float part = (span.t1 - span.t0) / float(steps);
    Color sum(0.0f);
    // The transmittance from the span's start to the last point, extended point by point so
    // that the march reads each stretch of the medium once.
    Color T(1.0f);
    float tLast = span.t0;
    for (int k = 0; k < steps; ++k) {
        const float t = span.t0 + (float(k) + sampler.get1D()) * part;
        const Vec3 p = ray.o + t * ray.d;
        const Color sigmaS = medium.sigmaSAt(p);
        if (!(maxComponent(sigmaS) > 0.0f))
            continue;
        T *= medium.transmittance(ray, tLast, t);
        tLast = t;
        const MediumPoint point{p, medium.phase(), -ray.d};
        sum += T * sigmaS * estimateInScattering(scene, point, sampler, counters);
    }
    return sum * part;
}

}  // namespace penumbra
