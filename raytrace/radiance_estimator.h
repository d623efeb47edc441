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

// What the first visible surface looked like, for AOV layers.
struct FirstHit {
    bool valid = false;
    Color albedo{0.0f};  // base colour at the first non-transparent hit
    Vec3 normal{0.0f};   // shading normal, world space
    float depth = 0.0f;  // distance from the camera, metres
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
