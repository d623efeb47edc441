#include "core/sampling.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace penumbra {

Vec2 sampleConcentricDisk(Vec2 u) {
    const Vec2 offset = 2.0f * u - Vec2(1.0f);
    if (offset.x == 0.0f && offset.y == 0.0f)
        return Vec2(0.0f);
    float r, theta;
    if (std::abs(offset.x) > std::abs(offset.y)) {
        r = offset.x;
        theta = (kPi / 4.0f) * (offset.y / offset.x);
    } else {
        r = offset.y;
        theta = kPi / 2.0f - (kPi / 4.0f) * (offset.x / offset.y);
    }
    return r * Vec2(std::cos(theta), std::sin(theta));
}

Vec3 sampleCosineHemisphere(Vec2 u) {
    const Vec2 d = sampleConcentricDisk(u);
    const float z = safeSqrt(1.0f - d.x * d.x - d.y * d.y);
    return Vec3(d.x, d.y, z);
}

Vec3 sampleUniformSphere(Vec2 u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = safeSqrt(1.0f - z * z);
    const float phi = 2.0f * kPi * u.y;
    return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}

std::optional<Equiangular> equiangularTowards(const Vec3& o, const Vec3& d, float a, float b,
                                              const Vec3& y) {
    const float delta = glm::dot(y - o, d);
    const float D = glm::length(y - (o + delta * d));
    if (!(D > 0.0f) || !(b > a))
        return std::nullopt;
    const Equiangular e{delta, D, std::atan2(a - delta, D), std::atan2(b - delta, D)};
    if (!(e.thetaB > e.thetaA))
        return std::nullopt;
    return e;
}

float Equiangular::sample(float u) const {
    return delta + D * std::tan(thetaA + u * (thetaB - thetaA));
}

float Equiangular::pdf(float t) const {
    const float x = t - delta;
    return D / ((thetaB - thetaA) * (D * D + x * x));
}

Vec3 sampleUniformCone(Vec2 u, float cosMax) {
    const float cosTheta = (1.0f - u.x) + u.x * cosMax;
    const float sinTheta = safeSqrt(1.0f - cosTheta * cosTheta);
    const float phi = 2.0f * kPi * u.y;
    return Vec3(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
}

Vec3 sampleUniformTriangle(Vec2 u) {
    // Heitz's two cases (u.x < u.y: b0 = u.x / 2, b1 = u.y - b0; else b1 = u.y / 2, b0 = u.x - b1)
    // are both b = u - min(u.x, u.y) / 2, exactly (x - x/2 = x/2 in floating point for every u a
    // sampler gives): no branch, which random u would mispredict half the time.
    const float half = glm::min(u.x, u.y) / 2.0f;
    const float b0 = u.x - half, b1 = u.y - half;
    return Vec3(b0, b1, 1.0f - b0 - b1);
}

AliasTable::AliasTable(std::span<const float> weights) {
    const size_t n = weights.size();
    if (n == 0)
        return;
    const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
    pmf_.resize(n);
    bins_.resize(n);
    if (!(total > 0.0)) {
        pmf_.clear();
        bins_.clear();
        return;
    }
    // Vose's construction: scaled probabilities n p_i split into small (< 1) and large work lists.
    std::vector<double> scaled(n);
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < n; ++i) {
        pmf_[i] = static_cast<float>(weights[i] / total);
        scaled[i] = weights[i] / total * static_cast<double>(n);
        (scaled[i] < 1.0 ? small : large).push_back(static_cast<uint32_t>(i));
    }
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back();
        small.pop_back();
        const uint32_t l = large.back();
        bins_[s] = {static_cast<float>(scaled[s]), l};
        scaled[l] -= 1.0 - scaled[s];
        if (scaled[l] < 1.0) {
            large.pop_back();
            small.push_back(l);
        }
    }
    // Leftovers are 1 up to rounding.
    for (uint32_t i : large)
        bins_[i] = {1.0f, i};
    for (uint32_t i : small)
        bins_[i] = {1.0f, i};
}

uint32_t AliasTable::sample(float u) const {
    const size_t n = bins_.size();
    const float scaled = u * static_cast<float>(n);
    const uint32_t index = std::min(static_cast<uint32_t>(scaled), static_cast<uint32_t>(n - 1));
    const float up = std::min(scaled - static_cast<float>(index), 0.99999994f);
    return up < bins_[index].threshold ? index : bins_[index].alias;
}

namespace {

template <typename T>
double fillCdfOf(std::span<const T> weights, std::span<T> cdf) {
    const size_t n = weights.size();
    double total = 0.0;
    for (T w : weights)
        total += double(w);
    double running = 0.0;
    cdf[0] = T(0);
    for (size_t i = 0; i < n; ++i) {
        running += double(weights[i]);
        cdf[i + 1] = T(total > 0.0 ? running / total : double(i + 1) / double(n));
    }
    return total;
}

template <typename T>
CdfEntry invertCdfOf(std::span<const T> cdf, double u) {
    const size_t upper = size_t(std::upper_bound(cdf.begin(), cdf.end(), T(u)) - cdf.begin());
    const size_t i = std::clamp<size_t>(upper, 1, cdf.size() - 1) - 1;
    const double width = double(cdf[i + 1]) - double(cdf[i]);
    return {i, width > 0.0 ? std::clamp((u - double(cdf[i])) / width, 0.0, 1.0) : 0.5};
}

}  // namespace

double fillCdf(std::span<const float> weights, std::span<float> cdf) {
    return fillCdfOf(weights, cdf);
}
double fillCdf(std::span<const double> weights, std::span<double> cdf) {
    return fillCdfOf(weights, cdf);
}
CdfEntry invertCdf(std::span<const float> cdf, double u) {
    return invertCdfOf(cdf, u);
}
CdfEntry invertCdf(std::span<const double> cdf, double u) {
    return invertCdfOf(cdf, u);
}

}  // namespace penumbra
