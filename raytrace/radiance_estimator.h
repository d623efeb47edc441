// The interface between the image renderer and the tracers that estimate radiance along camera
// rays (path tracing, distribution ray tracing, the caustic and radiosity views): what one
// estimate returns and records besides its radiance.
#pragma once

#include "core/math.h"
#include "core/path_components.h"
#include "core/ray.h"

#include <cstdint>
#include <functional>

namespace penumbra {

class Sampler;

// What a surface looked like from the camera: its base colour, shading normal (world space) and
// distance along the camera path (metres).
struct SurfaceGuide {
    bool valid = false;
    Color albedo{0.0f};
    Vec3 normal{0.0f};
    float depth = 0.0f;
};

// What the first visible surface looked like, for AOV layers.
struct FirstHit : SurfaceGuide {
    // Where the surface was seen and its geometric normal on the camera's side: the light meter
    // of the `illuminance` AOV lies there (raytrace/sensor_irradiance.h).
    Vec3 position{0.0f};
    Vec3 viewerSideNormal{0.0f};
    // The first vertex the path left through a non-delta lobe: the first hit, or the surface
    // seen in a mirror or through glass (depth: the length of the path to it). Filled by the
    // tracers that correct a solution, for the filter that reconstructs the correction
    // (raytrace/correction_filter.h), which must compare what is reflected, not the mirror.
    SurfaceGuide firstDiffuse;
};

struct PathCounters {
    uint64_t rays = 0;  // closest-hit and shadow rays traced
};

// Radiance (cd/m²) arriving along -ray.d at the ray's origin, estimated with one sample and
// filed by light-path component; fills firstHit when it is not null and not yet valid. The
// result may be non-finite only through a bug or broken input: the renderer drops such samples.
using RadianceEstimator =
    std::function<PathRadiance(const Ray&, Sampler&, FirstHit*, PathCounters&)>;

}  // namespace penumbra
