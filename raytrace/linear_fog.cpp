#include "raytrace/linear_fog.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

LinearFog linearFog(const Medium& medium, const Ray& ray, const Medium::Span& span,
                    const Color& ambient) {
    // tau per channel from the exact transmittance, which holds the density's integral.
    const Color exact = medium.transmittance(ray, span.t0, span.t1);
    LinearFog fog;
    for (int c = 0; c < 3; ++c) {
        const float sigmaT = medium.sigmaT()[c];
        if (!(sigmaT > 0.0f))
            continue;  // clear in this channel: nothing taken, nothing added
        const float tau = exact[c] > 0.0f ? -std::log(exact[c]) : INFINITY;
        fog.transmittance[c] = std::max(0.0f, 1.0f - 0.5f * tau);
        const float fogRadiance = (medium.sigmaS()[c] * ambient[c] +
                                   (sigmaT - medium.sigmaS()[c]) * medium.emission()[c]) /
                                  sigmaT;
        fog.radiance[c] = (1.0f - fog.transmittance[c]) * fogRadiance;
    }
    return fog;
}

}  // namespace penumbra
