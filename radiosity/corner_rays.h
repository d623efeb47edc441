// The rays a gather casts from one point of a leaf side: cosine-distributed about the side's
// normal, from an Owen-scrambled (0,2)-sequence of the sampler seeded by `seed` at "pixel" `key`
// (reproducible whatever the thread), each to the first surface the mesh holds (meshed_hit.h).
// The corner gather of the indirect light (indirect_at_corners.h) reads the solution where they
// land; the refinement at creases (crease_refinement.h) only how far they go. Both name the
// corners they share alike (cornerKey).
#pragma once

#include "core/math.h"
#include "core/ray.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "radiosity/element_sampling.h"
#include "radiosity/meshed_hit.h"
#include "radiosity/radiosity_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>

namespace penumbra {

// What names a corner of a leaf side for the gathers that share it between the leaves that have
// it: the mesh vertex, the side, and the leaf's normal to a ten-thousandth (one plane, so that a
// crease's two faces keep a value each).
using CornerKey = std::array<int32_t, 5>;

inline CornerKey cornerKey(const RadiosityMesh& mesh, int leaf, bool front, size_t k) {
    const auto quantized = [](float v) { return static_cast<int32_t>(std::lround(v * 1e4f)); };
    const Vec3& n = mesh.normal(leaf);
    return {static_cast<int32_t>(mesh.vertices(leaf)[k]), front ? 0 : 1, quantized(n.x),
            quantized(n.y), quantized(n.z)};
}

// Casts n rays from x on the side `front` and calls onHit(hit, sampler) for each that meets the
// mesh, the sampler at that ray's sample for the dimensions after its direction's.
// Returns the harmonic mean of the rays' lengths, escaped rays counting as infinitely long: how
// far from x the light it gathers holds (the validity radius of Ward, Rubinstein and Clear 1988,
// "A Ray Tracing Solution for Diffuse Interreflection"); infinity when no ray meets anything.
// Adds the rays it traces to `rays`.
template <typename OnHit>
float castCornerRays(const Scene& scene, const RadiosityMesh& mesh, const ElementSample& x,
                     bool front, uint32_t seed, IVec2 key, uint32_t n, uint64_t& rays,
                     const OnHit& onHit) {
    const Frame frame = Frame::fromNormal(front ? x.n : -x.n);
    Sampler sampler(seed);
    double inverseDistances = 0.0;
    for (uint32_t j = 0; j < n; ++j) {
        sampler.startPixelSample(key, j);
        const Vec3 w = frame.toWorld(sampleCosineHemisphere(sampler.get2D()));
        const std::optional<MeshedHit> y =
            firstMeshedHit(scene, mesh, Ray{offsetRayOrigin(x.p, x.pError, x.n, w), w}, rays);
        if (!y)
            continue;
        onHit(*y, sampler);
        inverseDistances += 1.0 / std::max(double(glm::length(y->hit.p - x.p)), 1e-6);
    }
    return inverseDistances > 0.0 ? static_cast<float>(n / inverseDistances)
                                  : std::numeric_limits<float>::infinity();
}

}  // namespace penumbra
