// The low-discrepancy sampler: the (0,2)-sequence formed by the first two Sobol dimensions,
// Owen-scrambled and shuffled with hashes, padded to any number of dimensions, as in
// Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4).
#pragma once

#include "core/math.h"

#include <cstdint>

namespace penumbra {

// One sampler per thread; it holds no shared state. Every value depends only on
// (seed, pixel, sampleIndex, position of the call since startPixelSample), so a render is the
// same whatever the thread count or the order in which pixels are visited.
//
// Each get1D/get2D call is a new "dimension": its own shuffled, Owen-scrambled Sobol sequence
// seeded by hashing (seed, pixel, dimension) (Burley 2020, "padding"). Within one
// dimension the first 2^k sample indices of a pixel form a (0,k,2)-net: every elementary
// interval of area 2^-k holds exactly one point.
class Sampler {
  public:
    explicit Sampler(uint32_t seed) : seed_(seed) {}

    // Start sample `sampleIndex` of `pixel`; resets the dimension counter.
    void startPixelSample(IVec2 pixel, uint32_t sampleIndex);

    // Uniform values in [0, 1): never 1.0f.
    float get1D();
    Vec2 get2D();
    // The position of the camera sample within its pixel's filter footprint. It has a reserved
    // dimension of its own, so it stays the same sequence whether or not get1D/get2D were called
    // first.
    Vec2 getPixel2D();

  private:
    uint32_t seed_;
    IVec2 pixel_{0, 0};
    uint32_t sampleIndex_ = 0;
    // Dimension 0 is reserved for getPixel2D.
    uint32_t dimension_ = 1;
};

// One 2D dimension of one pixel as a sequence over the sample index: element k is what the
// Sampler of that seed gives for that dimension in sample k of the pixel, where get2D's (or
// get1D's) n-th call after startPixelSample reads dimension n, counted from 1 (0 is getPixel2D's).
// The dimension's seeds are hashed once, for callers that draw many samples of one dimension in
// a loop (a radiosity link's shadow rays).
class SampleSequence2D {
  public:
    SampleSequence2D(uint32_t seed, IVec2 pixel, uint32_t dimension);
    Vec2 operator[](uint32_t sampleIndex) const;

  private:
    uint32_t indexSeed_, xSeed_, ySeed_;
};

}  // namespace penumbra
