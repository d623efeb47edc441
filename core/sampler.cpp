#include "core/sampler.h"

#include <array>

namespace penumbra {
namespace {

constexpr uint32_t reverseBits(uint32_t v) {
    v = ((v & 0x55555555u) << 1) | ((v >> 1) & 0x55555555u);
    v = ((v & 0x33333333u) << 2) | ((v >> 2) & 0x33333333u);
    v = ((v & 0x0f0f0f0fu) << 4) | ((v >> 4) & 0x0f0f0f0fu);
    v = ((v & 0x00ff00ffu) << 8) | ((v >> 8) & 0x00ff00ffu);
    return (v << 16) | (v >> 16);
}

// MurmurHash3's 64-bit finalizer fmix64 (Appleby 2011, MurmurHash3.cpp): a bijection with full
// avalanche, used to turn (seed, pixel, dimension) into independent-looking scrambling seeds.
uint64_t mixBits(uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ull;
    k ^= k >> 33;
    return k;
}

// Owen scrambling in base 2 of a bit-reversed value: bit i of the result is bit i of the input
// flipped by a hash of the bits below it (each step only carries information upwards, and each
// is a bijection). This is the Laine-Karras construction (Laine and Karras 2011, "Stratified
// Sampling for Stochastic Transparency") that Burley 2020 uses for Owen scrambling. Burley's paper
// keeps Laine and Karras' multipliers; these improved ones, with the seed also used as a
// multiplier, are Vegdahl's ("Building a Better LK Hash", psychopath.io, 2021, final version of
// 2021-05-08), which avalanche much better (pbrt-v4's FastOwenScrambler uses the same).
uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

// Owen's nested uniform scramble of a 32-bit fraction (most significant bit first): each digit is
// flipped by a random function of the digits above it (Burley 2020, "nested_uniform_scramble").
uint32_t nestedUniformScramble(uint32_t x, uint32_t seed) {
    return reverseBits(laineKarrasPermutation(reverseBits(x), seed));
}

// Generator matrix of Sobol's second dimension as 32 columns: column i is the direction number v_i,
// the image of index bit i. Its primitive polynomial is x + 1 (degree 1, no inner coefficients,
// m_1 = 1), so Sobol's recurrence v_i = v_{i-1} XOR (v_{i-1} >> s) with s = 1 holds from
// v_0 = 1/2 (Bratley and Fox 1988, "Algorithm 659: Implementing Sobol's Quasirandom Sequence
// Generator", ACM TOMS 14(1); Joe and Kuo 2008, "Constructing Sobol Sequences with Better
// Two-Dimensional Projections", list this as their dimension 2: s = 1, a = 0, m_1 = 1).
constexpr std::array<uint32_t, 32> kSobolDimension1 = [] {
    std::array<uint32_t, 32> v{};
    v[0] = 1u << 31;
    for (size_t i = 1; i < v.size(); ++i) {
        v[i] = v[i - 1] ^ (v[i - 1] >> 1);
    }
    return v;
}();

// The generator matrix is linear over GF(2), so the point is the XOR of the images of the
// index's four bytes: four table lookups instead of a loop over 32 bits (the shuffled index
// has random high bits, so the loop would always run its full length).
constexpr std::array<std::array<uint32_t, 256>, 4> kSobolDimension1ByByte = [] {
    std::array<std::array<uint32_t, 256>, 4> tables{};
    for (size_t byte = 0; byte < 4; ++byte) {
        for (uint32_t value = 0; value < 256; ++value) {
            uint32_t x = 0;
            for (size_t bit = 0; bit < 8; ++bit) {
                if (value & (1u << bit))
                    x ^= kSobolDimension1[8 * byte + bit];
            }
            tables[byte][value] = x;
        }
    }
    return tables;
}();

// The same tables with every entry bit-reversed (reversal is linear over GF(2) too): the
// scramble works on reversed values, so the point is looked up reversed.
constexpr std::array<std::array<uint32_t, 256>, 4> kReversedSobolDimension1ByByte = [] {
    std::array<std::array<uint32_t, 256>, 4> tables{};
    for (size_t byte = 0; byte < 4; ++byte) {
        for (size_t value = 0; value < 256; ++value)
            tables[byte][value] = reverseBits(kSobolDimension1ByByte[byte][value]);
    }
    return tables;
}();

// reverseBits(point of Sobol's second dimension at index).
uint32_t reversedSobolDimension1(uint32_t index) {
    return kReversedSobolDimension1ByByte[0][index & 0xffu] ^
           kReversedSobolDimension1ByByte[1][(index >> 8) & 0xffu] ^
           kReversedSobolDimension1ByByte[2][(index >> 16) & 0xffu] ^
           kReversedSobolDimension1ByByte[3][index >> 24];
}

float toUnitFloat(uint32_t bits) {
    return static_cast<float>(bits >> 8) * 0x1p-24f;
}

// The per-dimension seeds: one to shuffle the sample index, one per output coordinate. Hash
// (pixel) and (seed, dimension) as two 64-bit words; mixBits is a bijection, so two pixels (or
// two dimensions) of one render never share a hash.
struct DimensionSeeds {
    uint32_t index, x, y;
};
DimensionSeeds dimensionSeeds(uint32_t seed, IVec2 pixel, uint32_t dimension) {
    const uint64_t pixelWord = (uint64_t(uint32_t(pixel.x)) << 32) | uint64_t(uint32_t(pixel.y));
    const uint64_t streamWord = (uint64_t(seed) << 32) | dimension;
    const uint64_t h = mixBits(pixelWord ^ mixBits(streamWord));
    return {uint32_t(h), uint32_t(h >> 32), uint32_t(mixBits(h))};
}

// Shuffle the sample order by Owen-scrambling the index (Burley 2020, "shuffling"). The scramble
// maps each aligned block of 2^k indices onto another aligned block, so the first 2^k samples
// stay a (0,k,2)-net.
uint32_t shuffledIndex(uint32_t sampleIndex, uint32_t indexSeed) {
    return nestedUniformScramble(sampleIndex, indexSeed);
}

// Sobol dimension 0 is the van der Corput sequence: the bit-reversed index. The scramble reverses
// its input first (nestedUniformScramble(v) = reverseBits(LK(reverseBits(v)))), so the point is
// handed over reversed: the index itself.
float scrambledDimension0(uint32_t index, uint32_t seed) {
    return toUnitFloat(reverseBits(laineKarrasPermutation(index, seed)));
}

// Sobol dimension 1, likewise handed over reversed, from reversed tables.
float scrambledDimension1(uint32_t index, uint32_t seed) {
    return toUnitFloat(reverseBits(laineKarrasPermutation(reversedSobolDimension1(index), seed)));
}

}  // namespace

SampleSequence2D::SampleSequence2D(uint32_t seed, IVec2 pixel, uint32_t dimension) {
    const DimensionSeeds seeds = dimensionSeeds(seed, pixel, dimension);
    indexSeed_ = seeds.index;
    xSeed_ = seeds.x;
    ySeed_ = seeds.y;
}

Vec2 SampleSequence2D::operator[](uint32_t sampleIndex) const {
    const uint32_t index = shuffledIndex(sampleIndex, indexSeed_);
    return {scrambledDimension0(index, xSeed_), scrambledDimension1(index, ySeed_)};
}

void Sampler::startPixelSample(IVec2 pixel, uint32_t sampleIndex) {
    pixel_ = pixel;
    sampleIndex_ = sampleIndex;
    dimension_ = 1;
}

float Sampler::get1D() {
    const DimensionSeeds seeds = dimensionSeeds(seed_, pixel_, dimension_++);
    return scrambledDimension0(shuffledIndex(sampleIndex_, seeds.index), seeds.x);
}

Vec2 Sampler::get2D() {
    return SampleSequence2D(seed_, pixel_, dimension_++)[sampleIndex_];
}

Vec2 Sampler::getPixel2D() {
    return SampleSequence2D(seed_, pixel_, 0)[sampleIndex_];
}

}  // namespace penumbra
