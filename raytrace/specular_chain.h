// Following a camera ray through specular vertices to the surfaces it shows: the eye half of the
// passes that evaluate something at the first diffuse vertex (distribution ray tracing's direct
// and ambient light, the caustic pass's photon map).
//
// At each hit: emission (if counted), straight-through transparency (thin glass passes the ray
// on), then, at a vertex with a non-delta lobe, the caller's term; then one lobe is sampled and
// the chain goes on only if it is a delta lobe (mirror, smooth refraction), the non-delta share
// being what the caller's term stands for. Unbiased for the delta part: the lobe choice is
// reweighted by its probability (Bsdf::sample's pdf).
//
// With `mediumSteps`, each segment of the chain through the participating medium adds the light
// the medium scatters once into it (raytrace/single_scattering.h) and its emission, and
// attenuates what lies behind by its transmittance (L V S* E; multiple scattering is left out);
// or, with `linearFogAmbient`, the seed's linear fog does both (raytrace/linear_fog.h; filed
// with the ambient term, as indirect light, or as specular past a specular vertex).
//
// Components (core/path_components.h): emission at the first hit is emission, the caller's term
// at the first vertex keeps its own split, and everything seen after a specular vertex is
// specular.
#pragma once

#include "core/bsdf.h"
#include "core/path_components.h"
#include "core/scene.h"
#include "raytrace/path_tracer.h"

#include <functional>
#include <optional>

namespace penumbra {

class Sampler;

// The radiance the caller adds at a vertex with a non-delta lobe, towards wo, split into
// components as if that vertex were the first.
using DiffuseVertexTerm =
    std::function<PathRadiance(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                               Sampler& sampler, PathCounters& counters)>;

struct SpecularChainSettings {
    int maxSpecularDepth = 16;  // specular vertices followed from the eye
    bool countEmission = true;  // add the emission every vertex of the chain shows (L S* E)
    // Points marched per segment through the medium for its single scattering; 0: the chain
    // ignores the medium (for a caller the planner keeps from scenes with one).
    int mediumSteps = 0;
    // With mediumSteps > 0 and a value: the seed's linear fog in place of the single scattering,
    // lit by this ambient radiance (raytrace/linear_fog.h).
    std::optional<Color> linearFogAmbient = std::nullopt;
};

// Radiance (cd/m²) arriving along -ray.d at the ray's origin (contract of PathTracer::Li).
PathRadiance traceSpecularChain(const Scene& scene, Ray ray, Sampler& sampler, FirstHit* firstHit,
                                PathCounters& counters, const SpecularChainSettings& settings,
                                const DiffuseVertexTerm& atDiffuseVertex);

}  // namespace penumbra
