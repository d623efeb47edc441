// What every tracer from the eye records the same way (path tracing, distribution ray tracing,
// the caustic pass's view): the AOVs of the first visible surface. How rays cross surfaces is in
// core/surface_crossing.h.
#pragma once

#include "core/bsdf.h"
#include "core/surface_crossing.h"
#include "raytrace/path_tracer.h"

namespace penumbra {

// Fills `guide` from the surface at `hit`, `depth` metres along the camera path.
void recordSurfaceGuide(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, float depth,
                        SurfaceGuide& guide);

// Fills the AOV record from the first surface that is not passed straight through.
void recordFirstHit(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                    const Vec3& cameraOrigin, FirstHit* firstHit);

}  // namespace penumbra
