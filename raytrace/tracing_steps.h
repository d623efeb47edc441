// Steps every tracer from the eye takes the same way (path tracing, distribution ray tracing, the
// caustic pass's view), so that they agree on transparency, absorption and AOVs.
#pragma once

#include "core/bsdf.h"
#include "core/scene.h"
#include "raytrace/path_tracer.h"

namespace penumbra {

// Beer-Lambert attenuation exp(-sigma t) of a segment inside a volume material, known when the
// segment ends on the material's back face (a closed solid leaves through its back faces).
Color volumeAttenuation(const Scene& scene, const SurfaceHit& hit, const Vec3& direction);

// Straight-through transparency (thin glass, alpha cut-outs): the ray continues unchanged with
// probability q = min(max transmittance, 1), else the surface scatters; either branch is
// reweighted by its probability, so the choice is unbiased. The vertex is not a scattering
// event. u: a uniform sample, drawn only when the surface transmits.
struct StraightThrough {
    bool passes = false;  // continue the same ray through the surface
    Color weight{1.0f};   // factor for the throughput in the branch taken
};
StraightThrough chooseStraightThrough(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                                      const Vec3& wo, Sampler& sampler);

// Fills the AOV record from the first surface that is not passed straight through.
void recordFirstHit(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                    const Vec3& cameraOrigin, FirstHit* firstHit);

}  // namespace penumbra
