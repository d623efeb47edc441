// The glTF BSDF: its sampling against its pdf (chi-square), energy (white furnace), reciprocity,
// delta lobes, and robustness to extreme inputs. Every statistical test has a fixed seed.
#include "core/bsdf.h"
#include "tests/chi2.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace penumbra {
namespace {

// Materials -------------------------------------------------------------------------------

ShadingParams lambertian(Color base) {
    ShadingParams p;
    p.baseColor = base;
    p.metallic = 0.0f;
    p.specular = 0.0f;
    return p;
}

ShadingParams dielectric(float roughness, Color base) {
    ShadingParams p;
    p.baseColor = base;
    p.metallic = 0.0f;
    p.roughness = roughness;
    return p;
}

ShadingParams metal(float roughness, Color base) {
    ShadingParams p = dielectric(roughness, base);
    p.metallic = 1.0f;
    return p;
}

ShadingParams glass(float roughness, bool thinWalled, Color base) {
    ShadingParams p = dielectric(roughness, base);
    p.transmission = 1.0f;
    p.thinWalled = thinWalled;
    return p;
}

ShadingParams mixed(Color base) {
    ShadingParams p = dielectric(0.4f, base);
    p.metallic = 0.5f;
    return p;
}

// A material and the side of the surface wo is on.
struct Case {
    std::string name;
    ShadingParams params;
    bool back = false;
};

// Every non-delta configuration of the model; base colour given by the caller.
std::vector<Case> cases(Color base) {
    return {
        {"Lambertian", lambertian(base)},
        {"Dielectric02", dielectric(0.2f, base)},
        {"Dielectric05", dielectric(0.5f, base)},
        {"Dielectric10", dielectric(1.0f, base)},
        {"Metal01", metal(0.1f, base)},
        {"Metal05", metal(0.5f, base)},
        {"GlassFront", glass(0.3f, false, base)},
        {"GlassBack", glass(0.3f, false, base), true},
        {"ThinGlass", glass(0.3f, true, base)},
        {"Mixed", mixed(base)},
    };
}

// The surface is the z = 0 plane with its front towards +z; shading frame = world frame.
Bsdf makeBsdf(const ShadingParams& params) { return Bsdf(params, Frame{}, Vec3(0, 0, 1)); }

// wo at polar angle thetaDegrees from the normal of the side it is on, in the xz-plane.
Vec3 outgoing(float thetaDegrees, bool back) {
    const float theta = glm::radians(thetaDegrees);
    return Vec3(std::sin(theta), 0.0f, back ? -std::cos(theta) : std::cos(theta));
}

bool isValid(const Color& c) { return isFinite(c) && glm::all(glm::greaterThanEqual(c, Color(0))); }

// Albedo estimators ------------------------------------------------------------------------

struct Estimate {
    Color mean{0.0f};
    Color sigma{0.0f};  // standard error of the mean
};

// Importance-sampled albedo: mean of f |cos| / pdf over sample(), delta lobes included and
// rejected samples counted as 0.
Estimate sampledAlbedo(const Bsdf& bsdf, const Vec3& wo, int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int i = 0; i < n; ++i) {
        const float uLobe = uniform(rng);
        const Vec2 u(uniform(rng), uniform(rng));
        const std::optional<BsdfSample> s = bsdf.sample(wo, uLobe, u);
        if (!s) continue;
        const glm::dvec3 w = glm::dvec3(s->f) * double(std::abs(s->wi.z)) / double(s->pdf);
        sum += w;
        sum2 += w * w;
    }
    const glm::dvec3 mean = sum / double(n);
    const glm::dvec3 var = glm::max(sum2 / double(n) - mean * mean, 0.0);
    return {Color(mean), Color(glm::sqrt(var / double(n)))};
}

// Independent albedo: stratified uniform sampling of the sphere (jittered strata in cos theta
// and phi), f |cos| 4 pi per sample; its standard error comes from independent replicates.
Estimate uniformAlbedo(const Bsdf& bsdf, const Vec3& wo, int strata, int replicates,
                       uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int r = 0; r < replicates; ++r) {
        glm::dvec3 replicate(0.0);
        for (int i = 0; i < strata; ++i) {
            for (int j = 0; j < 2 * strata; ++j) {
                const float z = -1.0f + 2.0f * (i + uniform(rng)) / strata;
                const float phi = 2.0f * kPi * (j + uniform(rng)) / (2 * strata);
                const float sinTheta = safeSqrt(1.0f - z * z);
                const Vec3 wi(sinTheta * std::cos(phi), sinTheta * std::sin(phi), z);
                replicate += glm::dvec3(bsdf.f(wo, wi)) * double(std::abs(z));
            }
        }
        replicate *= 4.0 * kPi / (2.0 * strata * strata);
        sum += replicate;
        sum2 += replicate * replicate;
    }
    const glm::dvec3 mean = sum / double(replicates);
    const glm::dvec3 var = glm::max(sum2 / double(replicates) - mean * mean, 0.0) *
                           (double(replicates) / (replicates - 1));
    return {Color(mean), Color(glm::sqrt(var / double(replicates)))};
}

// 1. Chi-square test of sample() against pdf() -----------------------------------------------

constexpr float kChi2Angles[] = {10.0f, 45.0f, 80.0f};

class BsdfChi2 : public testing::TestWithParam<std::tuple<Case, float>> {};

TEST_P(BsdfChi2, SamplesFollowPdf) {
    const auto& [c, angle] = GetParam();
    const Bsdf bsdf = makeBsdf(c.params);
    const Vec3 wo = outgoing(angle, c.back);

    // Consistency of each sample with f() and pdf(): both are computed the same way, so only
    // float rounding separates them; 1e-3 relative leaves room for it and nothing else.
    int mismatches = 0;
    std::string firstMismatch;
    const auto sample = [&](const Vec3& u) -> std::optional<Vec3> {
        const std::optional<BsdfSample> s = bsdf.sample(wo, u.x, Vec2(u.y, u.z));
        if (!s || s->isDelta()) return std::nullopt;
        const float pdf = bsdf.pdf(wo, s->wi);
        const Color weight = s->f * std::abs(s->wi.z) / s->pdf;
        const Color expected = bsdf.f(wo, s->wi) * std::abs(s->wi.z) / pdf;
        const bool pdfOk = std::abs(pdf - s->pdf) <= 1e-3f * pdf;
        const bool weightOk = glm::all(glm::lessThanEqual(glm::abs(weight - expected),
                                                          1e-3f * glm::abs(expected)));
        if (!pdfOk || !weightOk) {
            if (mismatches++ == 0) {
                firstMismatch = "pdf " + std::to_string(s->pdf) + " vs " + std::to_string(pdf) +
                                ", weight.r " + std::to_string(weight.r) + " vs " +
                                std::to_string(expected.r);
            }
        }
        return s->wi;
    };
    const auto pdf = [&](const Vec3& wi) { return bsdf.pdf(wo, wi); };

    Chi2Options options;
    options.seed = 1234 + uint32_t(angle);
    // The family: every material at every angle (Sidak correction of the 1% level).
    options.testCount = int(cases(Color(1)).size() * std::size(kChi2Angles));
    const Chi2Result result = chi2Test(sample, pdf, options);
    EXPECT_TRUE(result.passed) << result.report;
    EXPECT_EQ(mismatches, 0) << firstMismatch;
}

INSTANTIATE_TEST_SUITE_P(
    Materials, BsdfChi2,
    testing::Combine(testing::ValuesIn(cases(Color(0.8f, 0.5f, 0.3f))),
                     testing::ValuesIn(kChi2Angles)),
    [](const testing::TestParamInfo<BsdfChi2::ParamType>& info) {
        return std::get<0>(info.param).name + "_" +
               std::to_string(int(std::get<1>(info.param))) + "deg";
    });

TEST(Chi2, IncompleteGammaMatchesClosedForms) {
    // Q(1, x) = exp(-x) and Q(1/2, x) = erfc(sqrt(x)); both branches of the evaluation.
    for (double x : {0.1, 0.5, 1.9, 2.5, 10.0, 40.0}) {
        EXPECT_NEAR(regularizedGammaQ(1.0, x), std::exp(-x), 1e-12) << x;
        EXPECT_NEAR(regularizedGammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-12) << x;
    }
    // Chi-square with 10 degrees of freedom: P(X > 23.209) = 0.01 (standard tables).
    EXPECT_NEAR(regularizedGammaQ(5.0, 23.209 / 2.0), 0.01, 1e-5);
}

}  // namespace
}  // namespace penumbra
namespace penumbra { namespace {
TEST(Explore, Furnace) {
    double worst = 0;
    for (const Case& c : cases(Color(1.0f))) {
        if (c.name == "Metal01") continue;
        const Bsdf bsdf = makeBsdf(c.params);
        for (float angle : {20.0f, 70.0f}) {
            const Vec3 wo = outgoing(angle, c.back);
            Estimate e = sampledAlbedo(bsdf, wo, 100000, 7);
            for (uint32_t seed : {1u, 2u, 3u}) {
            Estimate u = uniformAlbedo(bsdf, wo, 256, 8, seed);
            double z = (e.mean.g - u.mean.g) / std::sqrt(sqr(e.sigma.g) + sqr(u.sigma.g));
            worst = std::max(worst, std::abs(z));
            printf("%-14s %4.0f  IS %.5f +- %.5f  US %.5f +- %.5f  diff/sig %.2f\n", c.name.c_str(), angle,
                   e.mean.g, e.sigma.g, u.mean.g, u.sigma.g, z);
            }
        }
    }
    printf("worst %.2f\n", worst);
}
}}
