// How light crosses a surface without scattering, the same way for every tracer (camera paths,
// distribution rays, photons), so that they agree: absorption inside solids, and straight-through
// transparency (thin glass, alpha cut-outs), which is not a scattering vertex
// (docs/light-paths.md).
#pragma once

#include "core/bsdf.h"
#include "core/scene.h"

namespace penumbra {

class Sampler;

// Whether the segment of a ray in `direction` that ends at `hit` runs inside a volume material:
// it ends on the material's back face (a closed solid leaves through its back faces). Such a
// segment is not in the scene's participating medium (core/medium.h).
bool insideSolid(const Scene& scene, const SurfaceHit& hit, const Vec3& direction);

// Beer-Lambert attenuation exp(-sigma t) of a segment inside a volume material (insideSolid).
Color volumeAttenuation(const Scene& scene, const SurfaceHit& hit, const Vec3& direction);

// The attenuation of a whole segment of `ray` (unit direction), from its origin to `hit` or out
// of the scene (hit null): a solid's own absorption inside it (volumeAttenuation), else the
// participating medium's transmittance over the segment's part in its box (core/medium.h).
Color segmentAttenuation(const Scene& scene, const Ray& ray, const SurfaceHit* hit);

// Straight-through transparency: the ray continues unchanged with probability q = min(max
// transmittance, 1), else the surface scatters; either branch is reweighted by its probability,
// so the choice is unbiased. A uniform sample is drawn only when the surface transmits.
struct StraightThrough {
    bool passes = false;  // continue the same ray through the surface
    Color weight{1.0f};   // factor for the throughput in the branch taken
};
StraightThrough chooseStraightThrough(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                                      const Vec3& wo, Sampler& sampler);

}  // namespace penumbra
