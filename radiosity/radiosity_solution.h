// What a radiosity solver hands to the passes that show or reuse its solution, whatever the
// method (hierarchical, progressive): the radiance leaving every meshed surface point on either
// side, its indirect part (without the first reflection of the light sources), and the solver's
// figures for the log.
#pragma once

#include "core/bsdf.h"
#include "core/math.h"
#include "core/stats.h"

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
    // The indirect-only solution of the two-pass methods (Wallace, Cohen and Greenberg 1987, "A
    // Two-Pass Solution to the Rendering Equation", SIGGRAPH '87; Sillion and Puech 1989): the part
    // of radiance(mesh, triangle, b, false, front) that light paths L D D+ E ending there carry,
    // i.e. the reflected radiance less the first reflection of the sources' light (of the
    // emissive surfaces and of the punctual lights, and of deposited caustic photons when the
    // solver took them: L S+ D), which a ray tracer adds back itself with shadow rays (or a
    // caustic pass with its photon map): the ambient term of distribution ray tracing (the
    // seed's two-pass method).
    // Radiance in cd/m², Gouraud-interpolated like radiance(), never negative; zero on a triangle
    // the solver's mesh does not hold.
    virtual Color indirectRadiance(uint32_t mesh, uint32_t triangle, Vec3 b,
                                   bool front = true) const = 0;
    // Counters and timings, in the order they should be printed.
    virtual PassStats stats() const = 0;
    // Whether the solution reflects the sharp glossy lobes spread as Lambertian (false: its
    // specular transfer carried their reflection; MeshingSettings::spreadSharpGlossy).
    virtual bool spreadsSharpGlossy() const { return true; }
};

// A tracer that follows the rough glossy lobes itself takes only the Lambertian layer's share of
// radiance() or indirectRadiance(): matteShare() in raytrace/reused_light.h.

}  // namespace penumbra
