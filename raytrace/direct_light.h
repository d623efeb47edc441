// Next-event estimation: the light arriving at a surface point directly from the scene's lights,
// shared by every tracer that forms images (path tracing, distribution ray tracing).
#pragma once

#include "core/bsdf.h"
#include "core/scene.h"

namespace penumbra {

class Sampler;
struct PathCounters;

// Whether the light sample is weighted against BSDF sampling of the same light (a tracer that
// also counts emission its BSDF samples reach) or stands alone (one that never does).
enum class DirectLightWeight { PowerHeuristic, LightOnly };

// Reflected radiance towards wo from one light chosen by power and one point on it, with a
// shadow ray (thin glass and alpha cut-outs transmit). With PowerHeuristic the sample carries the
// power heuristic weight against bsdf.pdf() (Veach 1997, Eq. 9.13); a delta light's weight is 1
// either way, as BSDF sampling cannot reach it.
Color sampleDirectLight(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                        Sampler& sampler, PathCounters& counters, DirectLightWeight weighting);

}  // namespace penumbra
