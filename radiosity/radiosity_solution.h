// What a radiosity solver hands to the passes that show or reuse its solution, whatever the
// method (hierarchical, progressive): the radiance leaving every meshed surface point on either
// side, and the solver's figures for the log.
#pragma once

#include "core/math.h"
#include "core/pass.h"

#include <cstdint>

namespace penumbra {

class RadiositySolution {
  public:
    virtual ~RadiositySolution() = default;

    // Radiance (cd/m²) leaving the surface at barycentric b of scene triangle (mesh, triangle) on
    // its front (or back) side, the front being the side its counter-clockwise winding faces: the
    // Gouraud interpolation of the diffusely reflected light (light paths L D+ E ending there)
    // plus, if includeEmission, the element's own flat emitted radiance Le. Zero on a triangle
    // the solver's mesh does not hold.
    virtual Color radiance(uint32_t mesh, uint32_t triangle, Vec3 b, bool includeEmission,
                           bool front = true) const = 0;
    // Counters and timings, in the order they should be printed.
    virtual PassStats stats() const = 0;
};

}  // namespace penumbra
