// Unidirectional Monte Carlo path tracing: the `reference` estimator of the radiance arriving at
// the camera, against which every other pass is measured. Unbiased: no clamping, no depth cut
// unless the user sets one, Russian roulette that reweights what survives.
//
// Light transport: all paths L (D|S)* E, i.e. emission seen directly, direct light, indirect
// diffuse and glossy light, specular reflection and refraction, and caustics.
#pragma once

#include "core/math.h"
#include "core/ray.h"
#include "core/scene.h"

#include <cstdint>

namespace penumbra {

class Sampler;

struct PathTracerSettings {
    int maxDepth = -1;  // maximum number of scattering events; -1 = unlimited (roulette ends paths)
};

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

class PathTracer {
  public:
    PathTracer(const Scene& scene, const PathTracerSettings& settings);

    // Radiance (cd/m²) arriving along -ray.d at the ray's origin, estimated with one path.
    // The result may be non-finite only through a bug or broken input; callers drop such samples.
    Color Li(Ray ray, Sampler& sampler, FirstHit* firstHit, PathCounters& counters) const;

  private:
    // Next-event estimate at a non-delta vertex: one light chosen by power, one point on it,
    // weighted by the power heuristic against BSDF sampling.
    Color sampleDirectLight(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                            Sampler& sampler, PathCounters& counters) const;

    const Scene& scene_;
    PathTracerSettings settings_;
};

}  // namespace penumbra
