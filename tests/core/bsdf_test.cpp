// The glTF BSDF: its sampling against its pdf (chi-square), energy (white furnace), reciprocity,
// delta lobes, and robustness to extreme inputs. Every statistical test has a fixed seed.
#include "core/bsdf.h"
#include "core/fresnel.h"
#include "core/sampling.h"
#include "tests/support/chi2.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <ostream>
#include <random>
#include <string>
#include <vector>

namespace penumbra {
namespace {

// Materials -------------------------------------------------------------------------------

ShadingParams dielectric(float roughness, Color base) {
    ShadingParams p;
    p.baseColor = base;
    p.metallic = 0.0f;
    p.roughness = roughness;
    return p;
}

ShadingParams lambertian(Color base) {
    ShadingParams p = dielectric(1.0f, base);
    p.specular = 0.0f;
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

// Every strategy at once: diffuse, GGX reflection and the glass term.
ShadingParams halfGlass(Color base) {
    ShadingParams p = glass(0.3f, false, base);
    p.metallic = 0.2f;
    p.transmission = 0.5f;
    return p;
}

// A material and the side of the surface wo is on.
struct Case {
    std::string name;
    ShadingParams params;
    bool back = false;
};

void PrintTo(const Case& c, std::ostream* os) {
    *os << c.name;
}

// Every non-delta configuration of the model.
std::vector<Case> roughCases(Color base) {
    return {
        {"Lambertian", lambertian(base)},         {"Dielectric02", dielectric(0.2f, base)},
        {"Dielectric05", dielectric(0.5f, base)}, {"Dielectric10", dielectric(1.0f, base)},
        {"Metal01", metal(0.1f, base)},           {"Metal05", metal(0.5f, base)},
        {"GlassFront", glass(0.3f, false, base)}, {"GlassBack", glass(0.3f, false, base), true},
        {"ThinGlass", glass(0.3f, true, base)},   {"Mixed", mixed(base)},
        {"HalfGlassFront", halfGlass(base)},      {"HalfGlassBack", halfGlass(base), true},
    };
}

// The delta configurations.
std::vector<Case> smoothCases(Color base) {
    ShadingParams smoothHalfGlass = halfGlass(base);
    smoothHalfGlass.roughness = 0.0f;
    return {
        {"SmoothDielectric", dielectric(0.0f, base)},
        {"SmoothMetal", metal(0.0f, base)},
        {"SmoothGlassFront", glass(0.0f, false, base)},
        {"SmoothGlassBack", glass(0.0f, false, base), true},
        {"SmoothThinGlass", glass(0.0f, true, base)},
        {"SmoothHalfGlass", smoothHalfGlass},
    };
}

// The surface is the z = 0 plane with its front towards +z; shading frame = world frame.
Bsdf makeBsdf(const ShadingParams& params) {
    return Bsdf(params, Frame{}, Vec3(0, 0, 1));
}

// wo at polar angle thetaDegrees from the normal of the side it is on, in the xz-plane.
Vec3 outgoing(float thetaDegrees, bool back) {
    const float theta = glm::radians(thetaDegrees);
    return Vec3(std::sin(theta), 0.0f, back ? -std::cos(theta) : std::cos(theta));
}

bool isValid(const Color& c) {
    return isFinite(c) && glm::all(glm::greaterThanEqual(c, Color(0)));
}

float relativeError(float a, float b) {
    const float scale = glm::max(std::abs(a), std::abs(b));
    return scale > 0.0f ? std::abs(a - b) / scale : 0.0f;
}

// Albedo estimators ------------------------------------------------------------------------

struct Estimate {
    Color mean{0.0f};
    Color sigma{0.0f};  // standard error of the mean
};

// Importance-sampled albedo: mean of f |cos| / pdf over sample(), delta lobes included and
// rejected samples counted as 0.
Estimate sampledAlbedo(const Bsdf& bsdf, const Vec3& wo, int n, uint32_t seed, TransportMode mode) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int i = 0; i < n; ++i) {
        const float uLobe = uniform(rng);
        const Vec2 u(uniform(rng), uniform(rng));
        const std::optional<BsdfSample> s = bsdf.sample(wo, uLobe, u, mode);
        if (!s)
            continue;
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
        if (!s || s->isDelta())
            return std::nullopt;
        const float pdf = bsdf.pdf(wo, s->wi);
        const Color weight = s->f * std::abs(s->wi.z) / s->pdf;
        const Color expected = bsdf.f(wo, s->wi) * std::abs(s->wi.z) / pdf;
        bool ok = relativeError(pdf, s->pdf) <= 1e-3f;
        for (int i = 0; i < 3; ++i)
            ok = ok && relativeError(weight[i], expected[i]) <= 1e-3f;
        if (!ok && mismatches++ == 0) {
            firstMismatch = "pdf " + std::to_string(s->pdf) + " vs " + std::to_string(pdf) +
                            ", weight.r " + std::to_string(weight.r) + " vs " +
                            std::to_string(expected.r);
        }
        return s->wi;
    };
    const auto pdf = [&](const Vec3& wi) { return bsdf.pdf(wo, wi); };

    Chi2Options options;
    options.seed = 1234 + uint32_t(angle);
    // The family: every material at every angle (Sidak correction of the 1% level).
    options.testCount = int(roughCases(Color(1)).size() * std::size(kChi2Angles));
    const Chi2Result result = chi2Test(sample, pdf, options);
    EXPECT_TRUE(result.passed) << result.report;
    EXPECT_EQ(mismatches, 0) << firstMismatch;
}

INSTANTIATE_TEST_SUITE_P(Materials, BsdfChi2,
                         testing::Combine(testing::ValuesIn(roughCases(Color(0.8f, 0.5f, 0.3f))),
                                          testing::ValuesIn(kChi2Angles)),
                         [](const testing::TestParamInfo<BsdfChi2::ParamType>& info) {
                             return std::get<0>(info.param).name + "_" +
                                    std::to_string(int(std::get<1>(info.param))) + "deg";
                         });

TEST(Chi2, IncompleteGammaMatchesClosedForms) {
    // Q(1, x) = exp(-x) and Q(1/2, x) = erfc(sqrt(x)); both branches of the evaluation, which
    // iterate to 1e-15 in double precision, hence 1e-12.
    for (double x : {0.1, 0.5, 1.9, 2.5, 10.0, 40.0}) {
        EXPECT_NEAR(regularizedGammaQ(1.0, x), std::exp(-x), 1e-12) << x;
        EXPECT_NEAR(regularizedGammaQ(0.5, x), std::erfc(std::sqrt(x)), 1e-12) << x;
    }
    // Chi-square with 10 degrees of freedom: P(X > 23.209) = 0.01 (standard tables).
    EXPECT_NEAR(regularizedGammaQ(5.0, 23.209 / 2.0), 0.01, 1e-5);
}

TEST(Chi2, RejectsAWrongDensity) {
    // Cosine-weighted samples tested against a uniform-hemisphere density must fail.
    const auto sample = [](const Vec3& u) -> std::optional<Vec3> {
        return sampleCosineHemisphere(Vec2(u.x, u.y));
    };
    const auto pdf = [](const Vec3& w) { return w.z > 0.0f ? kInv2Pi : 0.0f; };
    Chi2Options options;
    options.sampleCount = 20000;
    EXPECT_FALSE(chi2Test(sample, pdf, options).passed);
}

// 2. White furnace ---------------------------------------------------------------------------

// Albedo = mean of f |cos| / pdf in Importance mode, whose integral over wi is the energy
// scattered from light arriving along -wo (Veach 1997, section 3.7.6: in Radiance mode
// refraction carries the 1/eta^2 radiance scaling, so its albedo is not bounded by 1). For
// thin-walled glass the straight transmittance is added.
constexpr float kFurnaceAngles[] = {0, 15, 30, 45, 60, 75, 80, 85, 89};

// The Kelemen coupling is exact up to the albedo table's interpolation error (E_table vs E_true
// shifts the total by their difference): at most 6e-4 for roughness >= 0.2 and 3e-3 overall
// (measured against a 200x200-point quadrature), so the bound is 1 + 3 sigma + 1e-3.
constexpr float kTableTolerance = 1e-3f;

TEST(BsdfFurnace, AlbedoIsAtMostOne) {
    std::vector<Case> all = roughCases(Color(1.0f));
    for (const Case& c : smoothCases(Color(1.0f)))
        all.push_back(c);
    for (const Case& c : all) {
        const Bsdf bsdf = makeBsdf(c.params);
        float lowest = 2.0f, highest = 0.0f;
        for (float angle : kFurnaceAngles) {
            const Vec3 wo = outgoing(angle, c.back);
            const Estimate e = sampledAlbedo(bsdf, wo, 50000, 99, TransportMode::Importance);
            const Color albedo = e.mean + bsdf.straightTransmittance(wo);
            for (int i = 0; i < 3; ++i) {
                EXPECT_LE(albedo[i], 1.0f + 3.0f * e.sigma[i] + kTableTolerance)
                    << c.name << " at " << angle << " degrees, channel " << i;
            }
            lowest = glm::min(lowest, albedo.g);
            highest = glm::max(highest, albedo.g);
        }
        std::printf("furnace %-16s albedo in [%.4f, %.4f] over 0-89 degrees\n", c.name.c_str(),
                    lowest, highest);
    }
}

TEST(BsdfFurnace, SpecularZeroIsExactlyLambertian) {
    const Color base(0.9f, 0.6f, 0.3f);
    const Bsdf bsdf = makeBsdf(lambertian(base));
    EXPECT_EQ(bsdf.lobes(), kLobeReflection | kLobeDiffuse);
    EXPECT_EQ(bsdf.diffuseGlossyReflectance(), base);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < 1000; ++i) {
        const Vec3 wo = sampleCosineHemisphere({uniform(rng), uniform(rng)});
        const Vec3 wi = sampleCosineHemisphere({uniform(rng), uniform(rng)});
        // f = baseColor / pi and pdf = cos / pi up to float rounding (1e-6 relative).
        const Color f = bsdf.f(wo, wi);
        for (int k = 0; k < 3; ++k)
            ASSERT_LE(relativeError(f[k], base[k] * kInvPi), 1e-6f);
        ASSERT_LE(relativeError(bsdf.pdf(wo, wi), wi.z * kInvPi), 1e-6f);
        // Each sample's weight is baseColor itself: cosine sampling of a Lambertian is exact.
        const std::optional<BsdfSample> s = bsdf.sample(wo, uniform(rng), {uniform(rng), 0.3f});
        ASSERT_TRUE(s);
        const Color weight = s->f * s->wi.z / s->pdf;
        for (int k = 0; k < 3; ++k)
            ASSERT_LE(relativeError(weight[k], base[k]), 1e-5f);
    }
}

TEST(BsdfFurnace, ImportanceSampledAlbedoMatchesUniformSampling) {
    // Catches a sampler that never reaches part of f (the chi-square test cannot: it compares
    // sample() with pdf(), not with f). Metal01's lobe is 1 degree wide: uniform sampling would
    // need ~1e8 samples to resolve it, so it is left out. The uniform estimate's error comes
    // from 8 replicates, a t-distribution with 7 degrees of freedom: 5 sigma keeps the chance
    // of a false alarm over these 66 comparisons below 0.1.
    for (const Case& c : roughCases(Color(0.9f, 0.6f, 0.3f))) {
        if (c.name == "Metal01")
            continue;
        const Bsdf bsdf = makeBsdf(c.params);
        for (float angle : {20.0f, 70.0f}) {
            const Vec3 wo = outgoing(angle, c.back);
            const Estimate sampled = sampledAlbedo(bsdf, wo, 100000, 3, TransportMode::Radiance);
            const Estimate uniform = uniformAlbedo(bsdf, wo, 256, 8, 4);
            for (int i = 0; i < 3; ++i) {
                const float sigma = std::hypot(sampled.sigma[i], uniform.sigma[i]);
                EXPECT_NEAR(sampled.mean[i], uniform.mean[i], 5.0f * sigma)
                    << c.name << " at " << angle << " degrees, channel " << i;
            }
        }
    }
}

// The directional albedo of a lobe f(wo, wi) at wo, by a midpoint rule over stratified
// directions wi (cos(theta_i) and phi); accurate to about 1e-3 for a lobe as smooth as the matte
// one.
glm::dvec3 directionalAlbedo(const std::function<Color(const Vec3&, const Vec3&)>& lobe,
                             const Vec3& wo) {
    constexpr int kTheta = 32, kPhi = 64;
    glm::dvec3 albedo(0.0);
    for (int i = 0; i < kTheta; ++i) {
        for (int j = 0; j < kPhi; ++j) {
            const float z = (i + 0.5f) / kTheta;
            const float phi = 2.0f * kPi * (j + 0.5f) / kPhi;
            const Vec3 wi(safeSqrt(1.0f - z * z) * std::cos(phi),
                          safeSqrt(1.0f - z * z) * std::sin(phi), z);
            albedo += glm::dvec3(lobe(wo, wi)) * double(z);
        }
    }
    return albedo * (2.0 * kPi / (kTheta * kPhi));
}

// The hemispherical-hemispherical albedo of a lobe: its directional albedo averaged by a
// midpoint rule over cos(theta_o) (isotropy), cosine-weighted.
glm::dvec3 averageAlbedo(const std::function<Color(const Vec3&, const Vec3&)>& lobe) {
    constexpr int kMu = 32;
    glm::dvec3 rho(0.0);
    for (int a = 0; a < kMu; ++a) {
        const float muO = (a + 0.5f) / kMu;
        const Vec3 wo(safeSqrt(1.0f - muO * muO), 0.0f, muO);
        rho += directionalAlbedo(lobe, wo) * (2.0 * muO / kMu);
    }
    return rho;
}

TEST(BsdfFurnace, SmoothDielectricReflectanceIsTheMatteLobesAverageAlbedo) {
    // A smooth dielectric's reflection is a delta (an S vertex), so diffuseGlossyReflectance()
    // holds the matte lobe alone, which is f(baseColor 1) - f(baseColor 0) (the specular terms
    // cancel exactly); the matte lobe is smooth, so 2e-3 covers the quadrature error.
    ShadingParams p = dielectric(0.0f, Color(1.0f));
    p.specularColor = Color(1.0f, 3.0f, 8.0f);  // a coloured E_avg
    const Bsdf white = makeBsdf(p);
    p.baseColor = Color(0.0f);
    const Bsdf black = makeBsdf(p);
    const glm::dvec3 rho = averageAlbedo(
        [&](const Vec3& wo, const Vec3& wi) { return white.f(wo, wi) - black.f(wo, wi); });
    const Color expected = white.diffuseGlossyReflectance();
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(rho[i], expected[i], 2e-3) << "channel " << i;
    EXPECT_EQ(expected, white.matteReflectance());
    EXPECT_LT(expected.b, expected.r);  // more specular, less matte
}

TEST(BsdfFurnace, FLessFGlossyIsTheMatteLobe) {
    // fGlossy() leaves out exactly the matte lobe: f - fGlossy averages to matteReflectance(),
    // and a metal (no matte lobe) has fGlossy = f everywhere.
    ShadingParams p = dielectric(0.3f, Color(0.9f, 0.6f, 0.3f));
    p.specularColor = Color(1.0f, 3.0f, 8.0f);
    const Bsdf plastic = makeBsdf(p);
    const glm::dvec3 rho = averageAlbedo([&](const Vec3& wo, const Vec3& wi) {
        return plastic.f(wo, wi) - plastic.fGlossy(wo, wi);
    });
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(rho[i], plastic.matteReflectance()[i], 2e-3) << "channel " << i;
    const Bsdf gold = makeBsdf(metal(0.4f, Color(1.0f, 0.766f, 0.336f)));
    EXPECT_EQ(gold.matteReflectance(), Color(0.0f));
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (int i = 0; i < 100; ++i) {
        const Vec3 wo = sampleCosineHemisphere({uniform(rng), uniform(rng)});
        const Vec3 wi = sampleCosineHemisphere({uniform(rng), uniform(rng)});
        ASSERT_EQ(gold.fGlossy(wo, wi), gold.f(wo, wi));
    }
}

TEST(BsdfFurnace, MatteAlbedoIsTheMatteLobesDirectionalAlbedo) {
    // matteAlbedo(wo) is what f - fGlossy (the matte lobe alone) reflects towards wo of uniform
    // light, at every angle; seen at grazing angles a polished coat takes much of it, which the
    // hemispherical average matteReflectance() does not say.
    ShadingParams p = dielectric(0.1f, Color(0.9f, 0.6f, 0.3f));
    p.specularColor = Color(1.0f, 3.0f, 8.0f);
    const Bsdf polished = makeBsdf(p);
    const auto matte = [&](const Vec3& wo, const Vec3& wi) {
        return polished.f(wo, wi) - polished.fGlossy(wo, wi);
    };
    for (const float mu : {1.0f, 0.5f, 0.1f, 0.03f}) {
        const Vec3 wo(safeSqrt(1.0f - mu * mu), 0.0f, mu);
        const glm::dvec3 albedo = directionalAlbedo(matte, wo);
        const Color expected = polished.matteAlbedo(wo);
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(albedo[i], expected[i], 2e-3) << "mu " << mu << ", channel " << i;
    }
    const Vec3 grazing(safeSqrt(1.0f - 0.03f * 0.03f), 0.0f, 0.03f);
    EXPECT_LT(polished.matteAlbedo(grazing).g, 0.8f * polished.matteReflectance().g);
    const Bsdf gold = makeBsdf(metal(0.4f, Color(1.0f, 0.766f, 0.336f)));
    EXPECT_EQ(gold.matteAlbedo(Vec3(0.0f, 0.0f, 1.0f)), Color(0.0f));
}

TEST(BsdfFurnace, RoughReflectanceIsTheWholeLobesAverageAlbedo) {
    // With rough reflection every lobe of an opaque surface is non-delta (a D vertex), so
    // diffuseGlossyReflectance() is the hemispherical-hemispherical albedo of the whole BSDF:
    // 2 integral E(mu) mu dmu, E(mu) estimated by importance sampling at the midpoints of 32
    // bins of mu. The closed form reads the tabulated GGX albedo (core/specular_albedo.h),
    // whose bilinear interpolation is within 2e-3 of the exact lobe (measured: within 3e-4 on
    // these cases); the estimate's own standard error is below 5e-4 (checked at 4 sigma on top
    // of that).
    for (const Case& c : roughCases(Color(0.9f, 0.6f, 0.3f))) {
        if (c.params.transmission > 0.0f || c.name == "Metal01")
            continue;  // transmission is not reflectance; Metal01 is sampled below the rest
        const Bsdf bsdf = makeBsdf(c.params);
        constexpr int kMu = 32;
        glm::dvec3 rho(0.0), variance(0.0);
        for (int a = 0; a < kMu; ++a) {
            const float muO = (a + 0.5f) / kMu;
            const Vec3 wo(safeSqrt(1.0f - muO * muO), 0.0f, muO);
            const Estimate e = sampledAlbedo(bsdf, wo, 20000, 11 + a, TransportMode::Radiance);
            const double weight = 2.0 * muO / kMu;
            rho += glm::dvec3(e.mean) * weight;
            variance += glm::dvec3(e.sigma * e.sigma) * (weight * weight);
        }
        const Color expected = bsdf.diffuseGlossyReflectance();
        std::printf("reflectance %-14s estimate %.4f %.4f %.4f, closed form %.4f %.4f %.4f\n",
                    c.name.c_str(), rho[0], rho[1], rho[2], expected[0], expected[1], expected[2]);
        for (int i = 0; i < 3; ++i) {
            EXPECT_NEAR(rho[i], expected[i], 2e-3 + 4.0 * std::sqrt(variance[i]))
                << c.name << " channel " << i;
        }
    }
}

// 3. Reciprocity ----------------------------------------------------------------------------

// A uniformly distributed direction on the side of the surface given by `back`.
Vec3 randomDirection(std::mt19937& rng, bool back) {
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    Vec3 w = sampleUniformSphere({uniform(rng), uniform(rng)});
    w.z = std::abs(w.z) * (back ? -1.0f : 1.0f);
    return w;
}

TEST(BsdfReciprocity, ReflectionIsSymmetric) {
    // f(wo, wi) and f(wi, wo) evaluate the same float expressions with the arguments swapped:
    // 1e-4 relative allows for the different rounding of sums such as 1 + Lambda_o + Lambda_i.
    std::vector<Case> all = roughCases(Color(0.9f, 0.6f, 0.3f));
    for (const Case& c : smoothCases(Color(0.9f, 0.6f, 0.3f)))
        all.push_back(c);
    std::mt19937 rng(17);
    for (const Case& c : all) {
        const Bsdf bsdf = makeBsdf(c.params);
        for (bool back : {false, true}) {
            for (int i = 0; i < 2000; ++i) {
                const Vec3 wo = randomDirection(rng, back), wi = randomDirection(rng, back);
                const Color a = bsdf.f(wo, wi), b = bsdf.f(wi, wo);
                for (int k = 0; k < 3; ++k) {
                    ASSERT_LE(relativeError(a[k], b[k]), 1e-4f)
                        << c.name << (back ? " back" : " front") << " channel " << k;
                }
            }
        }
    }
}

TEST(BsdfReciprocity, RefractionIsReciprocalUpToEtaSquared) {
    // Veach 1997, Eq. 5.14 (section 5.2): in Radiance mode f(wo, wi) / eta(wo)^2 =
    // f(wi, wo) / eta(wi)^2, eta(w) being the IOR of the medium w is in (1 outside, ior
    // inside); and the Importance-mode BSDF is the adjoint, f*(wo, wi) = f(wi, wo). The
    // generalised half vector is computed by different float expressions from the two sides
    // and the peaked D amplifies its rounding, hence 1e-3 relative; pairs far in the tails
    // (f < 1e-6, where nearly grazing microfacets leave few significant digits in wi.h) are
    // held to 1e-9 absolute.
    std::mt19937 rng(23);
    for (float ior : {1.33f, 1.5f, 2.4f}) {
        ShadingParams p = glass(0.3f, false, Color(0.9f, 0.6f, 0.3f));
        p.ior = ior;
        const Bsdf bsdf = makeBsdf(p);
        int nonZero = 0;
        for (int i = 0; i < 20000; ++i) {
            const Vec3 wo = randomDirection(rng, false), wi = randomDirection(rng, true);
            const Color outIn = bsdf.f(wo, wi), inOut = bsdf.f(wi, wo);
            const Color adjoint = bsdf.f(wi, wo, TransportMode::Importance);
            if (maxComponent(outIn) > 0.0f)
                ++nonZero;
            for (int k = 0; k < 3; ++k) {
                const float expected = inOut[k] / (ior * ior);
                ASSERT_NEAR(outIn[k], expected, 1e-3f * expected + 1e-9f) << ior;
                ASSERT_NEAR(adjoint[k], outIn[k], 1e-3f * outIn[k] + 1e-9f) << ior;
            }
        }
        EXPECT_GT(nonZero, 1000) << "too few refraction pairs tested at ior " << ior;
    }
}

// 4. Energy of the coupled dielectric ------------------------------------------------------

TEST(BsdfEnergy, CoupledDielectricKeepsItsEnergy) {
    // metallic 0, roughness 0.5, specular 1, ior 1.5, white: specular + coupled matte albedo is
    // 1 up to the albedo table's error (kTableTolerance) and MC noise (3 sigma).
    const Bsdf bsdf = makeBsdf(dielectric(0.5f, Color(1.0f)));
    std::string figures;
    for (float angle : kFurnaceAngles) {
        const Estimate e =
            sampledAlbedo(bsdf, outgoing(angle, false), 50000, 31, TransportMode::Radiance);
        EXPECT_GE(e.mean.g, 0.97f) << angle;
        EXPECT_NEAR(e.mean.g, 1.0f, 3.0f * e.sigma.g + kTableTolerance) << angle;
        char buffer[48];
        std::snprintf(buffer, sizeof(buffer), " %.0f: %.4f", angle, e.mean.g);
        figures += buffer;
    }
    std::printf("coupled dielectric albedo by angle:%s\n", figures.c_str());
}

// Delta lobes ------------------------------------------------------------------------------

// Samples of one BSDF for one wo with a fixed seed.
std::vector<BsdfSample> drawSamples(const Bsdf& bsdf, const Vec3& wo, int n,
                                    TransportMode mode = TransportMode::Radiance) {
    std::mt19937 rng(41);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<BsdfSample> samples;
    for (int i = 0; i < n; ++i) {
        const float uLobe = uniform(rng);
        const Vec2 u(uniform(rng), uniform(rng));
        if (const std::optional<BsdfSample> s = bsdf.sample(wo, uLobe, u, mode)) {
            samples.push_back(*s);
        }
    }
    return samples;
}

TEST(BsdfDelta, MirrorDirectionIsExactAndNotInFOrPdf) {
    // Black base colour: the mirror is the only lobe.
    for (const ShadingParams& p :
         {dielectric(0.0f, Color(0.0f)), metal(0.0f, Color(0.9f)), metal(1e-6f, Color(0.9f))}) {
        const Bsdf bsdf = makeBsdf(p);
        EXPECT_EQ(bsdf.lobes(), kLobeReflection | kLobeSpecular);
        for (float angle : {0.0f, 30.0f, 60.0f, 89.0f}) {
            const Vec3 wo = outgoing(angle, false);
            const Vec3 mirror(-wo.x, -wo.y, wo.z);
            int mirrors = 0;
            for (const BsdfSample& s : drawSamples(bsdf, wo, 2000)) {
                if (!s.isDelta())
                    continue;
                ++mirrors;
                EXPECT_EQ(s.lobe, kLobeReflection | kLobeSpecular);
                // Exact up to the float rounding of the frame transforms (a few ulps).
                EXPECT_LE(glm::length(s.wi - mirror), 1e-6f);
            }
            EXPECT_EQ(mirrors, 2000);
            EXPECT_EQ(bsdf.f(wo, mirror), Color(0.0f));
            EXPECT_EQ(bsdf.pdf(wo, mirror), 0.0f);
        }
    }
}

TEST(BsdfDelta, RefractionObeysSnell) {
    const float ior = 1.5f;
    const Bsdf bsdf = makeBsdf(glass(0.0f, false, Color(1.0f)));
    // From the front at any angle; from the back below the critical angle asin(1/1.5) = 41.8.
    for (const auto& [angle, back] : std::vector<std::pair<float, bool>>{
             {0, false}, {30, false}, {60, false}, {89, false}, {10, true}, {40, true}}) {
        const Vec3 wo = outgoing(angle, back);
        const float etaO = back ? ior : 1.0f, etaI = back ? 1.0f : ior;
        int refractions = 0;
        for (const BsdfSample& s : drawSamples(bsdf, wo, 2000)) {
            if (!(s.lobe & kLobeTransmission))
                continue;
            ++refractions;
            EXPECT_TRUE(s.isDelta());
            EXPECT_FLOAT_EQ(s.eta, etaI / etaO);
            EXPECT_LT(s.wi.z * wo.z, 0.0f);  // crosses the surface
            // Snell: eta_o sin(theta_o) = eta_i sin(theta_i), in the plane of incidence and on
            // the other side of the normal; 1e-5 is float rounding of refract()'s few operations.
            EXPECT_NEAR(etaO * wo.x, -etaI * s.wi.x, 1e-5f);
            EXPECT_NEAR(s.wi.y, 0.0f, 1e-6f);
            EXPECT_NEAR(glm::length(s.wi), 1.0f, 1e-5f);
        }
        EXPECT_GT(refractions, 100) << angle;
    }
}

TEST(BsdfDelta, TotalInternalReflectionBeyondTheCriticalAngle) {
    // Inside smooth glass (ior 1.5) beyond 41.8 degrees everything reflects: no refraction
    // sample, and the mean weight is 1 (F = 1, specular 1) within 3 sigma.
    const Bsdf bsdf = makeBsdf(glass(0.0f, false, Color(1.0f)));
    for (float angle : {42.5f, 50.0f, 70.0f, 89.0f}) {
        const Vec3 wo = outgoing(angle, true);
        const int n = 20000;
        double sum = 0.0, sum2 = 0.0;
        for (const BsdfSample& s : drawSamples(bsdf, wo, n)) {
            ASSERT_FALSE(s.lobe & kLobeTransmission) << angle;
            const double w = s.f.g * std::abs(s.wi.z) / s.pdf;
            sum += w;
            sum2 += w * w;
        }
        const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, 1.0, 3.0 * sigma + 1e-6) << angle;
    }
}

// Lobes, thin walls ------------------------------------------------------------------------

TEST(BsdfLobes, OnlyLobesWithWeightArePresent) {
    const Color c(0.5f);
    EXPECT_EQ(makeBsdf(lambertian(c)).lobes(), kLobeReflection | kLobeDiffuse);
    EXPECT_EQ(makeBsdf(dielectric(0.5f, c)).lobes(), kLobeReflection | kLobeDiffuse | kLobeGlossy);
    EXPECT_EQ(makeBsdf(metal(0.5f, c)).lobes(), kLobeReflection | kLobeGlossy);
    EXPECT_EQ(makeBsdf(metal(0.0f, c)).lobes(), kLobeReflection | kLobeSpecular);
    EXPECT_EQ(makeBsdf(glass(0.3f, false, c)).lobes(),
              kLobeReflection | kLobeTransmission | kLobeGlossy);
    EXPECT_EQ(makeBsdf(glass(0.0f, false, c)).lobes(),
              kLobeReflection | kLobeTransmission | kLobeSpecular);
    // A thin wall's transmission is straightTransmittance(), not a lobe.
    EXPECT_EQ(makeBsdf(glass(0.3f, true, c)).lobes(), kLobeReflection | kLobeGlossy);
    // Index-matched rough glass: rough reflection, refraction straight through.
    ShadingParams matched = glass(0.3f, false, c);
    matched.ior = 1.0f;
    EXPECT_EQ(makeBsdf(matched).lobes(),
              kLobeReflection | kLobeTransmission | kLobeGlossy | kLobeSpecular);
    EXPECT_FALSE(makeBsdf(glass(0.0f, false, c)).hasNonDeltaLobe());
}

TEST(BsdfLobes, SharpGlossyLobesAreTheNarrowRoughOnes) {
    // alpha = roughness^2: 0.22 gives 0.0484, within kSharpGlossyAlpha (0.05); 0.23 gives
    // 0.0529, outside; roughness 0 is a delta, not a glossy lobe.
    const Color c(0.5f);
    EXPECT_TRUE(makeBsdf(dielectric(0.1f, c)).hasSharpGlossyLobe());
    EXPECT_TRUE(makeBsdf(metal(0.22f, c)).hasSharpGlossyLobe());
    EXPECT_TRUE(makeBsdf(glass(0.1f, false, c)).hasSharpGlossyLobe());
    EXPECT_FALSE(makeBsdf(metal(0.23f, c)).hasSharpGlossyLobe());
    EXPECT_FALSE(makeBsdf(dielectric(0.0f, c)).hasSharpGlossyLobe());
    EXPECT_FALSE(makeBsdf(lambertian(c)).hasSharpGlossyLobe());
    // Left out of the reflectance, a sharp coat leaves the Lambertian layer, a sharp metal
    // nothing; a rough coat stays.
    const Bsdf polished = makeBsdf(dielectric(0.1f, c));
    EXPECT_EQ(polished.diffuseGlossyReflectance(false), polished.matteReflectance());
    EXPECT_GT(polished.diffuseGlossyReflectance().g, polished.matteReflectance().g);
    EXPECT_EQ(makeBsdf(metal(0.1f, c)).diffuseGlossyReflectance(false), Color(0.0f));
    const Bsdf rough = makeBsdf(dielectric(0.5f, c));
    EXPECT_EQ(rough.diffuseGlossyReflectance(false), rough.diffuseGlossyReflectance());
}

TEST(BsdfThinWall, StraightTransmittanceIsWhatReflectionLeaves) {
    const Color base(0.9f, 0.6f, 0.3f);
    const Bsdf smooth = makeBsdf(glass(0.0f, true, base));
    for (float angle : {0.0f, 45.0f, 80.0f}) {
        for (bool back : {false, true}) {
            const Vec3 wo = outgoing(angle, back);
            // A smooth wall: the glTF spec's base * (1 - specular * F(cos)), F at ior 1.5, up to
            // float rounding.
            const Color expected = base * (Color(1.0f) - fresnelSchlick(Color(0.04f), wo.z));
            const Color straight = smooth.straightTransmittance(wo);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(straight[k], expected[k], 1e-6f);
        }
    }
    EXPECT_EQ(makeBsdf(glass(0.0f, false, base)).straightTransmittance(outgoing(30, false)),
              Color(0.0f));
    EXPECT_EQ(makeBsdf(dielectric(0.3f, base)).straightTransmittance(outgoing(30, false)),
              Color(0.0f));
}

// 5. Robustness ----------------------------------------------------------------------------

TEST(BsdfRobustness, NoNanInfOrNegativeValuesForExtremeInputs) {
    std::vector<ShadingParams> materials;
    for (float roughness : {0.0f, 1e-6f, 0.0316f, 0.5f, 1.0f}) {
        for (float ior : {1.0f, 1.0005f, 1.5f, 3.0f}) {
            for (float metallic : {0.0f, 1.0f}) {
                for (float transmission : {0.0f, 1.0f}) {
                    for (bool thin : {false, true}) {
                        for (float specular : {0.0f, 1.0f}) {
                            ShadingParams p = dielectric(roughness, Color(1.0f, 0.5f, 0.0f));
                            p.ior = ior;
                            p.metallic = metallic;
                            p.transmission = transmission;
                            p.thinWalled = thin;
                            p.specular = specular;
                            p.specularColor = Color(1.0f, 5.0f, 0.0f);
                            materials.push_back(p);
                        }
                    }
                }
            }
        }
    }
    const float grazing = 1e-6f;
    const float sinGrazing = std::sqrt(1.0f - grazing * grazing);
    const std::vector<Vec3> wos = {
        Vec3(sinGrazing, 0.0f, grazing),   // grazing, front
        Vec3(sinGrazing, 0.0f, -grazing),  // grazing, back
        Vec3(0.0f, 0.0f, 1.0f),            // normal incidence
        Vec3(0.0f, 0.0f, -1.0f),           // below the geometric horizon
        Vec3(1.0f, 0.0f, 0.0f),            // on the geometric plane
        outgoing(60.0f, true),
    };
    // Shading normals: the geometric one, and one tilted by 60 degrees.
    const std::vector<Frame> frames = {
        Frame{}, Frame::fromNormal(glm::normalize(Vec3(std::sqrt(3.0f), 0.0f, 1.0f)))};
    std::mt19937 rng(53);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (const ShadingParams& p : materials) {
        for (const Frame& frame : frames) {
            const Bsdf bsdf(p, frame, Vec3(0, 0, 1));
            ASSERT_TRUE(isValid(bsdf.diffuseGlossyReflectance()));
            for (const Vec3& wo : wos) {
                ASSERT_TRUE(isValid(bsdf.straightTransmittance(wo)));
                for (int i = 0; i < 32; ++i) {
                    const Vec3 wi = sampleUniformSphere({uniform(rng), uniform(rng)});
                    for (TransportMode mode :
                         {TransportMode::Radiance, TransportMode::Importance}) {
                        ASSERT_TRUE(isValid(bsdf.f(wo, wi, mode)));
                        ASSERT_TRUE(isValid(bsdf.f(wo, wos[i % wos.size()], mode)));
                    }
                    const float pdf = bsdf.pdf(wo, wi);
                    ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0.0f);
                    const std::optional<BsdfSample> s =
                        bsdf.sample(wo, uniform(rng), {uniform(rng), uniform(rng)});
                    if (!s)
                        continue;
                    ASSERT_TRUE(isValid(s->f));
                    ASSERT_TRUE(std::isfinite(s->pdf) && s->pdf > 0.0f);
                    ASSERT_NEAR(glm::length(s->wi), 1.0f, 1e-4f);
                    ASSERT_TRUE(std::isfinite(s->eta) && s->eta > 0.0f);
                }
            }
        }
    }
}

}  // namespace
}  // namespace penumbra
