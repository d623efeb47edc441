// Warps from the unit square to directions and shapes, discrete sampling, and MIS weights.
// Every function states the measure of the pdf it returns.
#pragma once

#include "core/math.h"

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace penumbra {

// Cosine-weighted hemisphere around +z, Malley's method with Shirley and Chiu's concentric
// disk mapping (Shirley and Chiu 1997, "A Low Distortion Map Between Disk and Square").
// pdf (solid angle) = cos(theta) / pi.
Vec3 sampleCosineHemisphere(Vec2 u);
inline float cosineHemispherePdf(float cosTheta) {
    return glm::max(cosTheta, 0.0f) * kInvPi;
}

Vec2 sampleConcentricDisk(Vec2 u);

// Uniform direction on the unit sphere; pdf (solid angle) = 1 / (4 pi).
Vec3 sampleUniformSphere(Vec2 u);

// Uniform direction in the cone around +z with cos(half angle) = cosMax;
// pdf (solid angle) = 1 / (2 pi (1 - cosMax)).
Vec3 sampleUniformCone(Vec2 u, float cosMax);

// Uniform barycentrics (b0, b1, b2) on a triangle, area-preserving square-to-triangle map of
// Heitz 2019, "A Low-Distortion Map Between Triangle and Square" (Eq. 3); pdf (area) = 1 / A.
Vec3 sampleUniformTriangle(Vec2 u);

// Equiangular sampling of a distance t in [a, b] along a ray (o, unit d) towards a point y
// (Kulla and Fajardo 2012, "Importance Sampling Techniques for Path Tracing in Participating
// Media", section 4.1): t is drawn uniformly in the angle under which y sees the ray, so its
// density, D / ((thetaB - thetaA) (D^2 + (t - delta)^2)) per unit length, follows the inverse
// square falloff of a point light at y. delta is where the foot of the perpendicular from y
// lies along the ray, D the distance from y to the ray's line, thetaA and thetaB the angles of a
// and b seen from y. Nothing when y lies on the ray's line (D = 0) or the span is empty.
struct Equiangular {
    float delta, D, thetaA, thetaB;

    float sample(float u) const;
    float pdf(float t) const;
};
std::optional<Equiangular> equiangularTowards(const Vec3& o, const Vec3& d, float a, float b,
                                              const Vec3& y);

// Power heuristic with beta = 2 for one sample of each strategy
// (Veach and Guibas 1995, "Optimally Combining Sampling Techniques", Eq. 9).
inline float powerHeuristic(float pdfA, float pdfB) {
    const float a = pdfA * pdfA;
    const float b = pdfB * pdfB;
    if (std::isinf(a))
        return 1.0f;
    return a + b > 0.0f ? a / (a + b) : 0.0f;
}

// A discrete distribution over n entries by its cumulative distribution (pbrt-v3's
// Distribution1D, Pharr, Jakob and Humphreys, 3rd ed., section 13.3.1), for sampling by binary
// search where a sample's place within its entry matters (piecewise-constant densities over
// cells: an environment map's pixels, a candela table's cells).
//
// fillCdf() writes cdf[0] = 0, cdf[i + 1] = (w_0 + ... + w_i) / total (n + 1 entries) for weights
// w >= 0, uniform when the total is zero (the caller gives such a distribution no probability),
// and returns the total, summed in double.
double fillCdf(std::span<const float> weights, std::span<float> cdf);
double fillCdf(std::span<const double> weights, std::span<double> cdf);

// The entry i with cdf[i] <= u < cdf[i + 1], found by binary search, and where u falls between
// the two, in [0, 1] (0.5 in an entry of zero width): a fresh uniform number for the position
// within the entry.
struct CdfEntry {
    size_t index;
    double remainder;
};
CdfEntry invertCdf(std::span<const float> cdf, double u);
CdfEntry invertCdf(std::span<const double> cdf, double u);

// Walker's alias method (Walker 1977; Vose 1991 construction) for O(1) sampling of a discrete
// distribution proportional to non-negative weights. Zero weights are never chosen.
class AliasTable {
  public:
    AliasTable() = default;
    explicit AliasTable(std::span<const float> weights);

    // Index drawn with probability pmf(index), from one uniform number in [0, 1).
    uint32_t sample(float u) const;
    float pmf(uint32_t index) const { return pmf_[index]; }
    size_t size() const { return pmf_.size(); }
    bool empty() const { return pmf_.empty(); }

  private:
    struct Bin {
        float threshold;  // probability of keeping this bin's own index
        uint32_t alias;
    };
    std::vector<Bin> bins_;
    std::vector<float> pmf_;
};

}  // namespace penumbra
