// Following a camera ray through specular vertices to the surfaces it shows: the eye half of the
// passes that evaluate something at the first diffuse vertex (distribution ray tracing's direct
// and ambient light, the caustic pass's photon map).
//
// At each hit: emission (if counted), straight-through transparency (thin glass passes the ray
// on), then, at a vertex with a non-delta lobe, the caller's term; then one lobe is sampled and
// the chain goes on only if it is a delta lobe (mirror, smooth refraction), the non-delta share
// being what the caller's term stands for. Unbiased for the delta part: the lobe choice is
// reweighted by its probability (Bsdf::sample's pdf).
#pragma once

#include "core/bsdf.h"
#include "core/scene.h"
#include "raytrace/path_tracer.h"

#include <functional>

namespace penumbra {

class Sampler;

// The radiance the caller adds at a vertex with a non-delta lobe, towards wo.
using DiffuseVertexTerm =
    std::function<Color(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo, Sampler& sampler,
                        PathCounters& counters)>;

struct SpecularChainSettings {
    int maxSpecularDepth = 16;  // specular vertices followed from the eye
    bool countEmission = true;  // add the emission every vertex of the chain shows (L S* E)
};

// Radiance (cd/m²) arriving along -ray.d at the ray's origin (contract of PathTracer::Li).
Color traceSpecularChain(const Scene& scene, Ray ray, Sampler& sampler, FirstHit* firstHit,
                         PathCounters& counters, const SpecularChainSettings& settings,
                         const DiffuseVertexTerm& atDiffuseVertex);

}  // namespace penumbra
