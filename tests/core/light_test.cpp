// Light sources: the area light's pdf integrates to one and matches its sampling (chi-square),
// emitted power against closed forms and quadrature, the KHR_lights_punctual spot cone and range
// window, power-proportional light selection, and photometric units end to end. Every
// statistical test has a fixed seed, and states why its tolerance is right.
#include "core/light_sampler.h"
#include "core/punctual_lights.h"
#include "core/sampling.h"
#include "core/triangle_light.h"
#include "tests/support/chi2.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <iterator>
#include <memory>
#include <numbers>
#include <optional>
#include <ostream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace penumbra {
namespace {

constexpr double kPiD = std::numbers::pi;

double relativeError(double a, double b) {
    return std::abs(a - b) / std::max(std::abs(b), 1e-30);
}

// An emissive triangle with the mesh, material and textures it refers to. TriangleLight keeps
// references to them, so an Emitter is built in place and never moved.
struct Emitter {
    Mesh mesh;
    Material material;
    std::vector<Texture> textures;
    std::optional<TriangleLight> light;

    Emitter(const Emitter&) = delete;
    Emitter& operator=(const Emitter&) = delete;
    Emitter() = default;

    const Vec3& vertex(int i) const { return mesh.positions[mesh.triangles[0][i]]; }
    Vec3 normal() const {
        return glm::normalize(glm::cross(vertex(1) - vertex(0), vertex(2) - vertex(0)));
    }
};

// A scalene triangle in the plane z = 0, counter-clockwise seen from +z (its front side),
// area 0.4 m².
std::unique_ptr<Emitter> makeEmitter(bool doubleSided, Color Le = Color(2.0f, 1.0f, 0.5f)) {
    auto e = std::make_unique<Emitter>();
    e->mesh.name = "emitter";
    e->mesh.positions = {Vec3(0.0f), Vec3(1.0f, 0.0f, 0.0f), Vec3(0.3f, 0.8f, 0.0f)};
    e->mesh.triangles = {glm::uvec3(0, 1, 2)};
    e->material.emissive = Le;
    e->material.doubleSided = doubleSided;
    e->light.emplace(e->mesh, 0, e->material, e->textures);
    return e;
}

// Moller and Trumbore 1997, "Fast, Minimum Storage Ray-Triangle Intersection", in double
// precision, with the hit built as Scene::intersect builds it (p from the barycentrics, ng the
// unit front-side normal). `slack` widens the barycentric bounds, to accept points sampled on
// the triangle that rounding put a hair outside it.
std::optional<SurfaceHit> intersect(const Emitter& e, const Vec3& origin, const Vec3& direction,
                                    double slack = 0.0) {
    const glm::dvec3 p0(e.vertex(0)), p1(e.vertex(1)), p2(e.vertex(2));
    const glm::dvec3 o(origin), d(direction);
    const glm::dvec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::dvec3 pvec = glm::cross(d, e2);
    const double det = glm::dot(e1, pvec);
    if (std::abs(det) < 1e-300)
        return std::nullopt;
    const double invDet = 1.0 / det;
    const glm::dvec3 tvec = o - p0;
    const double u = glm::dot(tvec, pvec) * invDet;
    if (u < -slack || u > 1.0 + slack)
        return std::nullopt;
    const glm::dvec3 qvec = glm::cross(tvec, e1);
    const double v = glm::dot(d, qvec) * invDet;
    if (v < -slack || u + v > 1.0 + slack)
        return std::nullopt;
    const double t = glm::dot(e2, qvec) * invDet;
    if (!(t > 0.0))
        return std::nullopt;
    SurfaceHit hit;
    hit.barycentric = Vec3(float(1.0 - u - v), float(u), float(v));
    const Vec3& b = hit.barycentric;
    hit.p = b.x * e.vertex(0) + b.y * e.vertex(1) + b.z * e.vertex(2);
    hit.ng = e.normal();
    hit.ns = hit.ng;
    hit.t = float(t);
    return hit;
}

// A box in (cos theta, phi) about the normal of the triangle's plane on the receiver's side,
// which holds every direction from p to the triangle: cos theta = h / |x - p| for a point x of the
// triangle at height h below p, so it runs from h over the farthest vertex's distance to h over
// the distance of the triangle's nearest point; phi spans the vertices' azimuths when the foot
// of p lies outside the triangle (a convex set not holding the origin spans less than pi), and
// everything otherwise. Widened by 1e-4 against rounding.
struct DirectionBox {
    Frame frame;
    double cosLo, cosHi, phiLo, phiHi;
};

double segmentDistance(const glm::dvec2& a, const glm::dvec2& b) {  // from the origin
    const glm::dvec2 ab = b - a;
    const double t = std::clamp(-glm::dot(a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(a + t * ab);
}

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

DirectionBox boundingBox(const Emitter& e, const Vec3& p) {
    const float side = glm::dot(p - e.vertex(0), e.normal()) > 0.0f ? -1.0f : 1.0f;
    DirectionBox box{Frame::fromNormal(side * e.normal()), 0.0, 0.0, 0.0, 2.0 * kPiD};
    glm::dvec3 v[3];
    double farthest = 0.0;
    for (int i = 0; i < 3; ++i) {
        v[i] = glm::dvec3(box.frame.toLocal(e.vertex(i) - p));
        farthest = std::max(farthest, glm::length(v[i]));
    }
    const double h = (v[0].z + v[1].z + v[2].z) / 3.0;
    const glm::dvec2 a(v[0]), b(v[1]), c(v[2]);
    const double s0 = cross2(a, b), s1 = cross2(b, c), s2 = cross2(c, a);
    const bool footInside = (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
    double planar = 0.0;
    if (!footInside) {
        planar = std::min({segmentDistance(a, b), segmentDistance(b, c), segmentDistance(c, a)});
        const glm::dvec2 centroid = (a + b + c) / 3.0;
        const double phiCentroid = std::atan2(centroid.y, centroid.x);
        double lo = 0.0, hi = 0.0;
        for (const glm::dvec2& q : {a, b, c}) {
            const double phi = std::remainder(std::atan2(q.y, q.x) - phiCentroid, 2.0 * kPiD);
            lo = std::min(lo, phi);
            hi = std::max(hi, phi);
        }
        box.phiLo = phiCentroid + lo - 1e-4;
        box.phiHi = phiCentroid + hi + 1e-4;
    }
    box.cosLo = h / farthest * (1.0 - 1e-4);
    box.cosHi = std::min(1.0, h / std::sqrt(h * h + planar * planar) * (1.0 + 1e-4));
    return box;
}

// Receivers around the triangle of makeEmitter(), in front of it unless named "Behind".
struct Receiver {
    const char* name;
    Vec3 p;
};

const Receiver kReceivers[] = {
    {"Above", {0.4f, 0.3f, 1.0f}},
    {"ObliqueFar", {3.0f, -2.0f, 1.5f}},
    {"Grazing", {2.5f, 0.4f, 0.05f}},  // 1 to 2 degrees above the plane
    {"VeryClose", {0.4f, 0.3f, 0.01f}},
    {"CloseToEdge", {0.5f, -0.02f, 0.005f}},  // just outside edge p0-p1
    {"Behind", {0.4f, 0.3f, -1.0f}},
    {"BehindGrazing", {2.5f, 0.4f, -0.05f}},
};

void PrintTo(const Receiver& r, std::ostream* os) {
    *os << r.name;
}

bool inFront(const Receiver& r) {
    return r.p.z > 0.0f;
}

using LightCase = std::tuple<Receiver, bool>;  // receiver, doubleSided

std::string lightCaseName(const testing::TestParamInfo<LightCase>& info) {
    return std::string(std::get<0>(info.param).name) +
           (std::get<1>(info.param) ? "_DoubleSided" : "_OneSided");
}

// 1. The area light's pdf ----------------------------------------------------------------------

struct Estimate {
    double mean = 0.0;
    double standardError = 0.0;
};

// Integral of pdfLi over the sphere of directions by stratified uniform sampling of solid angle:
// one uniform direction in each cell of a grid over the box that holds the triangle (the sphere
// restricted to where the integrand can be non-zero), times the cell's solid angle
// d(cos theta) d(phi). The cells are geometric in cos theta so that each holds a similar share
// of the density, which grows as the directions approach the plane, where very close and
// grazing receivers see most of the triangle. kReplicates independent estimates give the
// standard error honestly (stratification makes the per-sample variance formula wrong).
Estimate integratePdfLi(const Emitter& e, const Vec3& p, uint32_t seed) {
    constexpr int kReplicates = 32, kCos = 128, kPhi = 128;
    const DirectionBox box = boundingBox(e, p);
    const double ratio = std::pow(box.cosHi / box.cosLo, 1.0 / kCos);
    const double dPhi = (box.phiHi - box.phiLo) / kPhi;
    const LightSampleContext ctx{p};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<double> replicates;
    for (int r = 0; r < kReplicates; ++r) {
        double sum = 0.0;
        for (int i = 0; i < kCos; ++i) {
            const double c0 = box.cosLo * std::pow(ratio, i);
            const double c1 = i + 1 == kCos ? box.cosHi : c0 * ratio;
            for (int j = 0; j < kPhi; ++j) {
                const double cosTheta = c0 + (c1 - c0) * uniform(rng);
                const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
                const double phi = box.phiLo + dPhi * (j + uniform(rng));
                const Vec3 w = glm::normalize(
                    box.frame.toWorld(Vec3(float(sinTheta * std::cos(phi)),
                                           float(sinTheta * std::sin(phi)), float(cosTheta))));
                if (const std::optional<SurfaceHit> hit = intersect(e, p, w))
                    sum += e.light->pdfLi(ctx, w, *hit) * (c1 - c0) * dPhi;
            }
        }
        replicates.push_back(sum);
    }
    Estimate estimate;
    for (double x : replicates)
        estimate.mean += x / kReplicates;
    double variance = 0.0;
    for (double x : replicates)
        variance += (x - estimate.mean) * (x - estimate.mean) / (kReplicates - 1);
    estimate.standardError = std::sqrt(variance / kReplicates);
    return estimate;
}

class TriangleLightPdf : public testing::TestWithParam<LightCase> {};

TEST_P(TriangleLightPdf, IntegratesToOneOverTheSphere) {
    const auto& [receiver, doubleSided] = GetParam();
    const auto e = makeEmitter(doubleSided);
    const Estimate estimate = integratePdfLi(*e, receiver.p, 17);
    std::printf("[ measured ] integral of pdfLi = %.6f +- %.6f\n", estimate.mean,
                estimate.standardError);
    if (!doubleSided && !inFront(receiver)) {
        // A one-sided light seen from behind: no direction is sampled, every pdf is exactly 0.
        EXPECT_EQ(estimate.mean, 0.0);
        return;
    }
    // 4 standard errors: with 32 replicates the t statistic has 31 degrees of freedom and
    // exceeds 4 with probability 4e-4, so a correct pdf passes; the standard errors measured are
    // 0.02 % to 0.07 %, so a wrong Jacobian factor (cos theta, d, a factor 2) cannot pass. The
    // 1e-5 floor covers float rounding of pdfLi, ~1e-7 relative per sample.
    EXPECT_NEAR(estimate.mean, 1.0, 4.0 * estimate.standardError + 1e-5);
    // The bound above is only meaningful if the estimate is precise.
    EXPECT_LT(estimate.standardError, 2e-3);
}

TEST_P(TriangleLightPdf, SampleLiPdfEqualsPdfLi) {
    const auto& [receiver, doubleSided] = GetParam();
    const auto e = makeEmitter(doubleSided);
    const LightSampleContext ctx{receiver.p};
    std::mt19937 rng(29);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    int samples = 0, misses = 0;
    double worstPdf = 0.0, worstPoint = 0.0;
    for (int i = 0; i < 100000; ++i) {
        const std::optional<LightLiSample> s =
            e->light->sampleLi(ctx, Vec2(uniform(rng), uniform(rng)));
        if (!s)
            continue;
        ++samples;
        EXPECT_EQ(s->L, e->material.emissive);
        // The sampled point lies on the triangle up to rounding: accept barycentrics 1e-5
        // outside it rather than count a miss.
        const std::optional<SurfaceHit> hit = intersect(*e, receiver.p, s->wi, 1e-5);
        if (!hit) {
            ++misses;
            continue;
        }
        worstPdf = std::max(worstPdf, relativeError(e->light->pdfLi(ctx, s->wi, *hit), s->pdf));
        worstPoint = std::max(worstPoint, double(glm::length(hit->p - s->pLight)));
    }
    std::printf("[ measured ] %d samples, worst relative pdf difference %.3g, point %.3g m\n",
                samples, worstPdf, worstPoint);
    if (!doubleSided && !inFront(receiver)) {
        EXPECT_EQ(samples, 0);
        return;
    }
    EXPECT_EQ(samples, 100000);
    EXPECT_EQ(misses, 0);
    // Both are d² / (|cos theta_light| A) for the same direction; they differ only through the
    // hit point, which the test recomputes from the float direction: at the most grazing
    // sample (cos theta_light = 0.006, CloseToEdge) a 6e-8 rad direction error moves d by 1e-5
    // relative at most; measured at most 2e-6. 2e-5 leaves room for that and catches any formula
    // difference, which would be of order 1.
    EXPECT_LT(worstPdf, 2e-5);
    EXPECT_LT(worstPoint, 1e-5);
}

INSTANTIATE_TEST_SUITE_P(Receivers, TriangleLightPdf,
                         testing::Combine(testing::ValuesIn(kReceivers), testing::Bool()),
                         lightCaseName);

// 2. Chi-square test of sampleLi() against pdfLi() ---------------------------------------------

// chi2Test() bins the whole sphere in (cos theta, phi), where the triangle's image is a small
// region cut by its edges, which the per-bin integration cannot resolve. The directions are
// therefore carried by an exact change of variables onto the whole sphere: a direction wi hits
// the triangle at barycentrics (b1, b2), Duffy's map s = b1 + b2, t = b2 / s takes the triangle
// to the unit square (d b1 d b2 = s ds dt), and cos' = 1 - 2 s, phi' = 2 pi t takes the square
// to the sphere (d omega' = 4 pi ds dt). The density of wi' follows from pdfLi through the
// Jacobians: solid angle to area |cos theta_light| / d², area to barycentrics 2 A, then
// s / (4 pi). Every chi-square cell is the image of a region of directions, and the warped
// density is smooth, so its cell integrals are exact.
class TriangleLightChi2 : public testing::TestWithParam<Receiver> {};

const Receiver kChi2Receivers[] = {
    {"Above", {0.4f, 0.3f, 1.0f}},           {"ObliqueFar", {3.0f, -2.0f, 1.5f}},
    {"Grazing", {2.5f, 0.4f, 0.05f}},        {"VeryClose", {0.4f, 0.3f, 0.01f}},
    {"CloseToEdge", {0.5f, -0.02f, 0.005f}}, {"BehindDoubleSided", {0.4f, 0.3f, -1.0f}},
};

TEST_P(TriangleLightChi2, SampleLiFollowsPdfLi) {
    const Receiver& receiver = GetParam();
    const auto e = makeEmitter(true);
    const LightSampleContext ctx{receiver.p};
    const glm::dvec3 p0(e->vertex(0)), p1(e->vertex(1)), p2(e->vertex(2));
    const double area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));

    const auto sample = [&](const Vec3& u) -> std::optional<Vec3> {
        const std::optional<LightLiSample> s = e->light->sampleLi(ctx, Vec2(u.x, u.y));
        if (!s)
            return std::nullopt;
        const std::optional<SurfaceHit> hit = intersect(*e, receiver.p, s->wi, 1e-5);
        if (!hit)
            return std::nullopt;  // counted as a sample outside the density: fails the test
        const double sum =
            std::clamp(double(hit->barycentric.y) + double(hit->barycentric.z), 0.0, 1.0);
        const double t = sum > 0.0 ? std::clamp(hit->barycentric.z / sum, 0.0, 1.0) : 0.0;
        const double cosTheta = 1.0 - 2.0 * sum, phi = 2.0 * kPiD * t;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        return Vec3(float(sinTheta * std::cos(phi)), float(sinTheta * std::sin(phi)),
                    float(cosTheta));
    };
    const auto pdf = [&](const Vec3& warped) -> float {
        const double sum = 0.5 * (1.0 - double(warped.z));
        double phi = std::atan2(double(warped.y), double(warped.x));
        if (phi < 0.0)
            phi += 2.0 * kPiD;
        const double t = phi / (2.0 * kPiD);
        SurfaceHit hit;
        hit.barycentric = Vec3(float(1.0 - sum), float(sum * (1.0 - t)), float(sum * t));
        const glm::dvec3 x = (1.0 - sum) * p0 + sum * (1.0 - t) * p1 + sum * t * p2;
        hit.p = Vec3(x);
        hit.ng = e->normal();
        hit.ns = hit.ng;
        const glm::dvec3 toLight = x - glm::dvec3(receiver.p);
        const double d2 = glm::dot(toLight, toLight);
        const glm::dvec3 w = toLight / std::sqrt(d2);
        const double cosLight = std::abs(glm::dot(w, glm::dvec3(hit.ng)));
        const double pdfOmega = e->light->pdfLi(ctx, Vec3(w), hit);
        return float(pdfOmega * cosLight / d2 * 2.0 * area * sum / (4.0 * kPiD));
    };

    Chi2Options options;
    // A seed per receiver, so that the tests of the family are independent.
    const auto index =
        std::find_if(std::begin(kChi2Receivers), std::end(kChi2Receivers),
                     [&](const Receiver& r) { return std::string(r.name) == receiver.name; }) -
        std::begin(kChi2Receivers);
    options.seed = 41 + uint32_t(index);
    // The family: every receiver (Sidak correction of the 1 % level).
    options.testCount = int(std::size(kChi2Receivers));
    const Chi2Result result = chi2Test(sample, pdf, options);
    std::printf("[ measured ] chi-square %.1f, %d dof, p = %.3f\n", result.statistic, result.dof,
                result.pValue);
    EXPECT_TRUE(result.passed) << result.report;
    // All 200 cells expect well over 5 samples, so none is pooled.
    EXPECT_GE(result.dof, 150);
}

INSTANTIATE_TEST_SUITE_P(Receivers, TriangleLightChi2, testing::ValuesIn(kChi2Receivers),
                         [](const testing::TestParamInfo<Receiver>& info) {
                             return std::string(info.param.name);
                         });

// 3. Emitted power -----------------------------------------------------------------------------

// The closed forms below are single float products, so 1e-6 relative is rounding only.
constexpr float kProductTolerance = 1e-6f;

void expectColorNear(const Color& actual, const Color& expected, double tolerance) {
    for (int i = 0; i < 3; ++i)
        EXPECT_LE(relativeError(actual[i], expected[i]), tolerance)
            << "channel " << i << ": " << actual[i] << " vs " << expected[i];
}

PunctualLightDesc punctual(PunctualType type, float intensity, Color color = Color(1.0f)) {
    PunctualLightDesc desc;
    desc.name = "test";
    desc.type = type;
    desc.intensity = intensity;
    desc.color = color;
    desc.position = Vec3(0.5f, -1.0f, 2.0f);
    desc.direction = glm::normalize(Vec3(1.0f, 2.0f, -2.0f));
    return desc;
}

TEST(LightPower, PointLightIsFourPiI) {
    const PointLight light(punctual(PunctualType::Point, 120.0f, Color(1.0f, 0.5f, 0.25f)));
    expectColorNear(light.power(), 4.0f * kPi * 120.0f * Color(1.0f, 0.5f, 0.25f),
                    kProductTolerance);
}

struct SpotCone {
    const char* name;
    float inner, outer;  // radians
};

class SpotPower : public testing::TestWithParam<SpotCone> {};

// Flux = integral of the intensity over the sphere, the intensity measured through sampleLi()
// from receivers at distance r (Li r² = I(w) for range 0), integrated in coordinates around the
// spot axis: x = cos theta by composite 3-point Gauss-Legendre, split where the falloff has a
// kink (the two cones, and the end of the spec's ramp when the cones are closer than 0.001 in
// cos), and phi by the midpoint rule.
TEST_P(SpotPower, MatchesTheIntegralOfItsIntensity) {
    const SpotCone& cone = GetParam();
    PunctualLightDesc desc = punctual(PunctualType::Spot, 80.0f, Color(1.0f, 0.6f, 0.2f));
    desc.innerConeAngle = cone.inner;
    desc.outerConeAngle = cone.outer;
    const SpotLight light(desc);

    const double cosOuter = std::cos(double(cone.outer)), cosInner = std::cos(double(cone.inner));
    std::vector<double> breaks = {-1.0, 1.0, cosOuter, cosInner, cosOuter + 0.001};
    std::erase_if(breaks, [](double x) { return x < -1.0 || x > 1.0; });
    std::sort(breaks.begin(), breaks.end());

    static const double kNodes[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    static const double kWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    constexpr int kPanels = 200, kPhi = 32;
    constexpr double kRadius = 2.0;
    const Frame frame = Frame::fromNormal(desc.direction);
    glm::dvec3 flux(0.0);
    for (size_t k = 0; k + 1 < breaks.size(); ++k) {
        const double h = (breaks[k + 1] - breaks[k]) / kPanels;
        for (int panel = 0; panel < kPanels; ++panel) {
            for (int node = 0; node < 3; ++node) {
                const double x = breaks[k] + h * (panel + 0.5 + 0.5 * kNodes[node]);
                const double sinTheta = std::sqrt(std::max(0.0, 1.0 - x * x));
                for (int j = 0; j < kPhi; ++j) {
                    const double phi = 2.0 * kPiD * (j + 0.5) / kPhi;
                    const Vec3 w = frame.toWorld(Vec3(float(sinTheta * std::cos(phi)),
                                                      float(sinTheta * std::sin(phi)), float(x)));
                    const LightSampleContext ctx{desc.position + float(kRadius) * w};
                    const std::optional<LightLiSample> s = light.sampleLi(ctx, Vec2(0.5f));
                    if (s) {
                        flux += glm::dvec3(s->L) * (kRadius * kRadius) * (0.5 * h) *
                                kWeights[node] * (2.0 * kPiD / kPhi);
                    }
                }
            }
        }
    }
    std::printf("[ measured ] power %.7g, quadrature %.7g (luminance), relative difference %.2g\n",
                luminance(light.power()), luminance(Color(flux)),
                relativeError(luminance(light.power()), luminance(Color(flux))));
    // The quadrature is exact for the piecewise-quadratic falloff in x; what is left is float
    // rounding of cos theta in intensity(), ~6e-8 against a ramp 1 / max(0.001, delta) wide:
    // measured <= 1e-6 relative for the wider cones (1e-5 allowed), 1.3e-3 for the 1-degree
    // cone, whose whole cap is 1.5e-4 wide in cos (3e-3 allowed).
    const double tolerance = (1.0 - cosOuter) < 0.01 ? 3e-3 : 1e-5;
    expectColorNear(light.power(), Color(flux), tolerance);
}

INSTANTIATE_TEST_SUITE_P(Cones, SpotPower,
                         testing::Values(SpotCone{"Default", 0.0f, kPi / 4.0f},
                                         SpotCone{"Soft", 0.3f, 0.5f}, SpotCone{"Wide", 0.2f, 1.5f},
                                         // cones closer than the spec's 0.001 in cos
                                         SpotCone{"NearlyHard", 0.5f, 0.5005f},
                                         // the whole cone inside 0.001 in cos
                                         SpotCone{"Narrow", 0.0f, 0.0175f}),
                         [](const testing::TestParamInfo<SpotCone>& info) {
                             return std::string(info.param.name);
                         });

TEST(LightPower, DirectionalLightIsEPiR2) {
    const DirectionalLight light(punctual(PunctualType::Directional, 3.0f, Color(1.0f, 0.9f, 0.8f)),
                                 Vec3(1.0f), 2.5f);
    expectColorNear(light.power(), 3.0f * kPi * 2.5f * 2.5f * Color(1.0f, 0.9f, 0.8f),
                    kProductTolerance);
}

TEST(LightPower, TriangleLightIsPiALe) {
    const Color Le(2.0f, 1.0f, 0.5f);
    EXPECT_NEAR(makeEmitter(false)->light->area(), 0.4f, 1e-7f);
    expectColorNear(makeEmitter(false)->light->power(), kPi * 0.4f * Le, kProductTolerance);
    expectColorNear(makeEmitter(true)->light->power(), 2.0f * kPi * 0.4f * Le, kProductTolerance);
}

// Gives the emitter a 2x2 emission texture of mean (0.4, 0.25, 0.6).
void addEmissionTexture(Emitter& e) {
    e.textures.emplace_back(
        "emission", 2, 2,
        std::vector<Vec4>{Vec4(0.1f, 0.0f, 1.0f, 1.0f), Vec4(0.7f, 0.5f, 0.2f, 1.0f),
                          Vec4(0.3f, 0.5f, 0.6f, 1.0f), Vec4(0.5f, 0.0f, 0.6f, 1.0f)},
        WrapMode::Repeat, WrapMode::Repeat);
    e.material.emissiveTexture.texture = 0;
}

TEST(LightPower, TexturedTriangleLightUsesTheTextureAverage) {
    const auto e = makeEmitter(false);
    addEmissionTexture(*e);
    e->light.emplace(e->mesh, 0, e->material, e->textures);
    expectColorNear(e->light->power(),
                    kPi * 0.4f * Color(2.0f, 1.0f, 0.5f) * Color(0.4f, 0.25f, 0.6f),
                    kProductTolerance);
}

// Power against the flux that sampleLi() delivers through a sphere around the triangle:
// Phi = integral over the sphere of the irradiance on its inner side, E(x) = integral of
// L cos theta_x, estimated with one light sample per uniformly chosen receiver. This checks
// the L and pdf of sampleLi() against power() end to end.
TEST(LightPower, TriangleLightFluxThroughAnEnclosingSphere) {
    for (bool doubleSided : {false, true}) {
        const auto e = makeEmitter(doubleSided);
        const Vec3 center = (e->vertex(0) + e->vertex(1) + e->vertex(2)) / 3.0f;
        constexpr double kRadius = 3.0;
        constexpr int kSamples = 1000000;
        std::mt19937 rng(doubleSided ? 53 : 59);
        std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
        glm::dvec3 sum(0.0), sum2(0.0);
        for (int i = 0; i < kSamples; ++i) {
            const Vec3 outward = sampleUniformSphere(Vec2(uniform(rng), uniform(rng)));
            const LightSampleContext ctx{center + float(kRadius) * outward, Vec3(0.0f), -outward};
            const std::optional<LightLiSample> s =
                e->light->sampleLi(ctx, Vec2(uniform(rng), uniform(rng)));
            if (!s)
                continue;
            const glm::dvec3 x = glm::dvec3(s->L) * double(glm::dot(s->wi, -outward)) /
                                 double(s->pdf) * (4.0 * kPiD * kRadius * kRadius);
            sum += x;
            sum2 += x * x;
        }
        const glm::dvec3 mean = sum / double(kSamples);
        const glm::dvec3 standardError =
            glm::sqrt((sum2 / double(kSamples) - mean * mean) / double(kSamples - 1));
        const Color power = e->light->power();
        std::printf("[ measured ] %s: power %.5f, flux %.5f +- %.5f (red)\n",
                    doubleSided ? "double-sided" : "one-sided", power.r, mean.r, standardError.r);
        // 4 standard errors of a mean of 1e6 samples (normal to high accuracy), measured at
        // 0.1 % of the flux.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(mean[c], power[c], 4.0 * standardError[c]) << "channel " << c;
    }
}

// 4. KHR_lights_punctual spot cone and range window --------------------------------------------

// The spec's falloff, written out from the extension's README ("Inner and Outer Cone Angles"):
// scale = 1 / max(0.001, cos inner - cos outer), offset = -cos outer * scale,
// attenuation = saturate(cos theta * scale + offset)².
double specSpotFalloff(double theta, double inner, double outer) {
    const double scale = 1.0 / std::max(0.001, std::cos(inner) - std::cos(outer));
    const double offset = -std::cos(outer) * scale;
    const double t = std::clamp(std::cos(theta) * scale + offset, 0.0, 1.0);
    return t * t;
}

// Radiance-like value (intensity / d²) that a spot at the origin delivers at distance d and
// angle theta from its axis, 0 when sampleLi() returns nothing.
Color spotAt(const SpotLight& light, const PunctualLightDesc& desc, double theta, float d) {
    const Frame frame = Frame::fromNormal(desc.direction);
    const Vec3 w = frame.toWorld(Vec3(float(std::sin(theta)), 0.0f, float(std::cos(theta))));
    const std::optional<LightLiSample> s =
        light.sampleLi(LightSampleContext{desc.position + d * w}, Vec2(0.5f));
    return s ? s->L : Color(0.0f);
}

TEST(SpotFalloff, FollowsTheSpecBetweenTheCones) {
    PunctualLightDesc desc = punctual(PunctualType::Spot, 40.0f, Color(1.0f, 0.5f, 0.25f));
    desc.innerConeAngle = 0.3f;
    desc.outerConeAngle = 0.6f;
    const SpotLight light(desc);
    const double inner = desc.innerConeAngle, outer = desc.outerConeAngle;
    const Color full = desc.color * desc.intensity;
    // Full intensity inside the inner cone, none outside the outer one; angles 1e-3 rad from the
    // cone edges, well above the 1e-7 rad float error of the direction.
    for (double theta : {0.0, 0.1, inner - 1e-3})
        expectColorNear(spotAt(light, desc, theta, 1.0f), full, 1e-5);
    for (double theta : {outer + 1e-3, 1.0, kPiD / 2.0, 2.5, kPiD})
        EXPECT_EQ(spotAt(light, desc, theta, 1.0f), Color(0.0f)) << theta;
    // Between the cones, against the spec's curve: the value moves by at most
    // 2 sin(theta) / (cos inner - cos outer) = 7 per radian, times 1e-7 rad of direction error,
    // plus float rounding of cos: 1e-5 absolute on a falloff in [0, 1].
    for (double theta : {inner + 1e-3, 0.35, 0.45, 0.5, 0.55, outer - 1e-3}) {
        const double expected = specSpotFalloff(theta, inner, outer);
        const Color got = spotAt(light, desc, theta, 1.0f);
        EXPECT_NEAR(got.r / full.r, expected, 1e-5) << theta;
        EXPECT_NEAR(got.b / full.b, expected, 1e-5) << theta;
    }
    // The curve's shape in the middle: halfway in cos theta gives a quarter.
    const double halfway = std::acos(0.5 * (std::cos(inner) + std::cos(outer)));
    EXPECT_NEAR(spotAt(light, desc, halfway, 1.0f).r / full.r, 0.25, 1e-5);
}

// The range window of the extension's README ("Range Property").
double specAttenuation(double d, double range) {
    if (range <= 0.0)
        return 1.0 / (d * d);
    return std::clamp(1.0 - std::pow(d / range, 4.0), 0.0, 1.0) / (d * d);
}

TEST(RangeWindow, MatchesTheSpec) {
    // Float evaluation of a few operations: 1e-6 relative; absolute 1e-7 near the range, where
    // the window goes to zero through cancellation.
    for (float range : {0.0f, 0.5f, 3.0f, 100.0f}) {
        for (float d : {0.01f, 0.3f, 0.499f, 0.5f, 1.0f, 2.0f, 2.9f, 2.999f, 3.0f, 10.0f, 250.0f}) {
            const double expected = specAttenuation(d, range);
            EXPECT_NEAR(punctualAttenuation(d, range), expected, 1e-6 * expected + 1e-7)
                << "d " << d << ", range " << range;
        }
    }
    EXPECT_EQ(punctualAttenuation(3.0f, 3.0f), 0.0f);
    EXPECT_EQ(punctualAttenuation(4.0f, 3.0f), 0.0f);
}

TEST(RangeWindow, ReceiversBeyondTheRangeGetNothing) {
    for (PunctualType type : {PunctualType::Point, PunctualType::Spot}) {
        PunctualLightDesc desc = punctual(type, 50.0f);
        desc.range = 4.0f;
        std::unique_ptr<Light> light;
        if (type == PunctualType::Point)
            light = std::make_unique<PointLight>(desc);
        else
            light = std::make_unique<SpotLight>(desc);
        // Along the spot's axis, so that only the range decides.
        for (float d : {4.0f, 4.5f, 100.0f}) {
            const LightSampleContext ctx{desc.position + d * desc.direction};
            const std::optional<LightLiSample> s = light->sampleLi(ctx, Vec2(0.5f));
            EXPECT_TRUE(!s || maxComponent(s->L) == 0.0f) << d;
        }
        // Inside the range the window applies: d = 2 is half the range, window 15/16.
        const std::optional<LightLiSample> s =
            light->sampleLi(LightSampleContext{desc.position + 2.0f * desc.direction}, Vec2(0.5f));
        ASSERT_TRUE(s);
        EXPECT_NEAR(s->L.g, 50.0 * specAttenuation(2.0, 4.0), 1e-5);
    }
}

// 5. Power-proportional light selection --------------------------------------------------------

// Eight lights (a power of two, so that u * 8 is exact in the sweep below), two without power.
struct LightSet {
    std::unique_ptr<Emitter> emitter = makeEmitter(true);
    std::vector<std::unique_ptr<Light>> lights;

    LightSet() {
        lights.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 0.0f)));
        lights.push_back(std::make_unique<PointLight>(
            punctual(PunctualType::Point, 10.0f, Color(1.0f, 0.5f, 0.2f))));
        lights.push_back(std::make_unique<SpotLight>(punctual(PunctualType::Spot, 50.0f)));
        lights.push_back(std::make_unique<DirectionalLight>(
            punctual(PunctualType::Directional, 3.0f, Color(0.2f, 0.3f, 1.0f)), Vec3(0.0f), 2.0f));
        lights.push_back(std::make_unique<TriangleLight>(emitter->mesh, 0, emitter->material,
                                                         emitter->textures));
        lights.push_back(std::make_unique<PointLight>(
            punctual(PunctualType::Point, 1.0f, Color(0.0f))));  // black: no power
        lights.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 0.02f)));
        lights.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 200.0f)));
    }

    std::vector<double> expectedPmf() const {
        std::vector<double> pmf;
        double total = 0.0;
        for (const auto& light : lights) {
            pmf.push_back(luminance(light->power()));
            total += pmf.back();
        }
        for (double& p : pmf)
            p /= total;
        return pmf;
    }
};

TEST(PowerLightSampler, PmfIsProportionalToLuminanceOfPower) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const std::vector<double> expected = set.expectedPmf();
    double sum = 0.0;
    for (uint32_t i = 0; i < set.lights.size(); ++i) {
        // The pmf is computed in double and stored as float: 1e-6 relative.
        EXPECT_NEAR(sampler.pmf(i), expected[i], 1e-6 * expected[i]) << i;
        sum += sampler.pmf(i);
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    EXPECT_EQ(sampler.pmf(0), 0.0f);
    EXPECT_EQ(sampler.pmf(5), 0.0f);
}

TEST(PowerLightSampler, StratifiedSweepReproducesThePmf) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const size_t n = set.lights.size();
    // u = (k + 1/2) / (n K): every alias-table bin receives exactly K evenly spaced values, so
    // each bin's split between its own light and its alias is exact to 1/K of the bin, and a
    // light, touched by at most n bins of weight 1/n, is off by at most 1/K. The float
    // thresholds add 1e-7.
    constexpr int kPerBin = 1 << 17;
    const int count = int(n) * kPerBin;
    std::vector<double> frequency(n, 0.0);
    for (int k = 0; k < count; ++k) {
        const std::optional<PowerLightSampler::Choice> choice =
            sampler.sample((float(k) + 0.5f) / float(count));
        ASSERT_TRUE(choice);
        EXPECT_EQ(choice->pmf, sampler.pmf(choice->light));
        frequency[choice->light] += 1.0 / count;
    }
    for (uint32_t i = 0; i < n; ++i)
        EXPECT_NEAR(frequency[i], sampler.pmf(i), 1.0 / kPerBin + 1e-6) << i;
    EXPECT_EQ(frequency[0], 0.0);
    EXPECT_EQ(frequency[5], 0.0);
}

TEST(PowerLightSampler, RandomSamplesPassChiSquare) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const size_t n = set.lights.size();
    constexpr int kSamples = 1000000;
    std::mt19937 rng(71);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<double> observed(n, 0.0);
    for (int i = 0; i < kSamples; ++i)
        observed[sampler.sample(uniform(rng))->light] += 1.0;
    // Pearson's statistic over the lights with power (all expect >= 5 samples); the others
    // must never be chosen. 1 % level, a single test.
    double statistic = 0.0;
    int dof = -1;
    for (uint32_t i = 0; i < n; ++i) {
        const double expected = kSamples * double(sampler.pmf(i));
        if (expected == 0.0) {
            EXPECT_EQ(observed[i], 0.0) << i;
            continue;
        }
        ASSERT_GE(expected, 5.0);
        statistic += (observed[i] - expected) * (observed[i] - expected) / expected;
        ++dof;
    }
    const double pValue = regularizedGammaQ(0.5 * dof, 0.5 * statistic);
    std::printf("[ measured ] chi-square %.2f, %d dof, p = %.3f\n", statistic, dof, pValue);
    EXPECT_GE(pValue, 0.01);
}

TEST(PowerLightSampler, ZeroPowerLightsAreNeverChosenEvenAtBinEdges) {
    const LightSet set;
    const PowerLightSampler sampler(set.lights);
    const float n = float(set.lights.size());
    std::vector<float> us = {0.0f, 0.99999994f, std::nextafter(1.0f, 0.0f)};
    for (int k = 1; k < int(n); ++k) {
        us.push_back(float(k) / n);
        us.push_back(std::nextafter(float(k) / n, 0.0f));
        us.push_back(std::nextafter(float(k) / n, 1.0f));
    }
    for (float u : us) {
        const std::optional<PowerLightSampler::Choice> choice = sampler.sample(u);
        ASSERT_TRUE(choice);
        EXPECT_GT(choice->pmf, 0.0f) << u;
    }
}

TEST(PowerLightSampler, NoLightsOrNoPowerGivesNothing) {
    const std::vector<std::unique_ptr<Light>> none;
    const PowerLightSampler empty(none);
    EXPECT_FALSE(empty.sample(0.5f));

    std::vector<std::unique_ptr<Light>> dark;
    dark.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 0.0f)));
    dark.push_back(std::make_unique<PointLight>(punctual(PunctualType::Point, 5.0f, Color(0.0f))));
    const PowerLightSampler sampler(dark);
    EXPECT_FALSE(sampler.sample(0.0f));
    EXPECT_FALSE(sampler.sample(0.7f));
    EXPECT_EQ(sampler.pmf(0), 0.0f);
}

// 6. Photometric units end to end --------------------------------------------------------------

// A point light of I cd at distance d gives an illuminance I / d² lx at normal incidence, which
// sampleLi() reports as L; the receiver's own cosine is the integrator's, so a tilted receiver
// gets the same L. Float rounding only: 1e-6.
TEST(PhotometricUnits, PointLightGivesIOverDSquared) {
    // At the origin, so that the receiver's position carries no cancellation error into d.
    PunctualLightDesc desc = punctual(PunctualType::Point, 250.0f, Color(1.0f, 0.8f, 0.5f));
    desc.position = Vec3(0.0f);
    const PointLight light(desc);
    const Vec3 away = glm::normalize(Vec3(0.3f, -0.4f, 0.866f));
    for (float d : {0.1f, 0.5f, 2.0f, 7.0f, 300.0f}) {
        for (const Vec3& n : {-away, glm::normalize(-away + Vec3(0.5f, 0.0f, 0.0f))}) {
            const LightSampleContext ctx{desc.position + d * away, Vec3(0.0f), n};
            const std::optional<LightLiSample> s = light.sampleLi(ctx, Vec2(0.3f, 0.8f));
            ASSERT_TRUE(s);
            expectColorNear(s->L, desc.color * (250.0f / (d * d)), 1e-6);
            EXPECT_NEAR(glm::dot(s->wi, -away), 1.0f, 1e-6f);
            EXPECT_EQ(s->pdf, 1.0f);
        }
    }
}

TEST(PhotometricUnits, DirectionalLightGivesE) {
    const PunctualLightDesc desc =
        punctual(PunctualType::Directional, 1.0e5f, Color(1.0f, 0.95f, 0.9f));  // sunlight, lux
    const DirectionalLight light(desc, Vec3(0.0f), 10.0f);
    for (const Vec3& p : {Vec3(0.0f), Vec3(3.0f, -7.0f, 1.0f), Vec3(-40.0f, 2.0f, 9.0f)}) {
        const std::optional<LightLiSample> s =
            light.sampleLi(LightSampleContext{p, Vec3(0.0f), -desc.direction}, Vec2(0.5f));
        ASSERT_TRUE(s);
        expectColorNear(s->L, desc.color * 1.0e5f, 1e-6);
        EXPECT_NEAR(glm::dot(s->wi, -desc.direction), 1.0f, 1e-6f);
        // The shadow-ray target lies outside the scene's bounding sphere.
        EXPECT_GT(glm::length(s->pLight), 10.0f);
    }
}

TEST(PhotometricUnits, AreaLightRadianceIsLe) {
    // An emissive surface of Le cd/m² delivers radiance Le along every ray that reaches it.
    const auto e = makeEmitter(false);
    const std::optional<LightLiSample> s =
        e->light->sampleLi(LightSampleContext{Vec3(0.4f, 0.3f, 2.0f)}, Vec2(0.2f, 0.7f));
    ASSERT_TRUE(s);
    EXPECT_EQ(s->L, e->material.emissive);
}

// Photon emission (Light::sampleLe): the mean of the samples' flux() is the light's power(); the
// directions follow the density each light claims (chi-square); emittedLe() agrees with the
// sample's L. Exact per sample where the emitted flux is the same for every sample (point,
// directional, untextured area light: L |cos| / (pdfPos pdfDir) is a constant), statistical with
// a fixed seed otherwise.
Color meanLeFlux(const Light& light, int count, uint32_t seed, double* relativeStandardError) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 0.99999994f);
    glm::dvec3 sum(0.0);
    double sumLum = 0.0, sumLum2 = 0.0;
    for (int i = 0; i < count; ++i) {
        const Vec2 uPosition(uniform(rng), uniform(rng));
        const Vec2 uDirection(uniform(rng), uniform(rng));
        const std::optional<LightLeSample> s = light.sampleLe(uPosition, uDirection);
        const Color flux = s ? s->flux() : Color(0.0f);
        if (s) {
            // The sample's own direction gives back its emission.
            EXPECT_EQ(light.emittedLe(*s, s->w), s->L);
            EXPECT_NEAR(glm::length(s->w), 1.0f, 1e-5f);
        }
        sum += glm::dvec3(flux);
        sumLum += luminance(flux);
        sumLum2 += sqr(luminance(flux));
    }
    const double mean = sumLum / count;
    const double variance = std::max(0.0, sumLum2 / count - mean * mean);
    *relativeStandardError = mean > 0.0 ? std::sqrt(variance / count) / mean : 0.0;
    return Color(sum / double(count));
}

TEST(SampleLe, PointLightFluxIsItsPower) {
    const PointLight light(punctual(PunctualType::Point, 120.0f, Color(1.0f, 0.5f, 0.25f)));
    double se = 0.0;
    expectColorNear(meanLeFlux(light, 4096, 1, &se), light.power(), 1e-5);
    EXPECT_LT(se, 1e-5);  // every sample carries 4 pi I, up to float rounding
}

TEST(SampleLe, SpotLightFluxIsItsPower) {
    PunctualLightDesc desc = punctual(PunctualType::Spot, 80.0f, Color(1.0f, 0.6f, 0.2f));
    desc.innerConeAngle = 0.2f;
    desc.outerConeAngle = 0.7f;
    const SpotLight light(desc);
    double se = 0.0;
    const Color flux = meanLeFlux(light, 200000, 2, &se);
    std::printf("[ measured ] spot sampleLe flux %.6g, power %.6g, relative standard error %.2g\n",
                luminance(flux), luminance(light.power()), se);
    // The flux varies only with the falloff between the cones: 4.5 standard errors (about 0.3 %
    // here) is a false-alarm rate below 1e-5; a missing 1 / pdfDir or a wrong cone would be off
    // by tens of percent.
    EXPECT_GT(se, 0.0);
    expectColorNear(flux, light.power(), 4.5 * se + 1e-6);
    // Every photon leaves inside the outer cone.
    for (int i = 0; i < 64; ++i) {
        const auto s = light.sampleLe(Vec2(0.5f), Vec2((i + 0.5f) / 64.0f, 0.37f));
        ASSERT_TRUE(s);
        EXPECT_GE(glm::dot(s->w, desc.direction), std::cos(0.7f) - 1e-6f);
        EXPECT_EQ(s->p, desc.position);
    }
}

TEST(SampleLe, DirectionalLightFluxIsItsPowerFromADiscBehindTheScene) {
    const PunctualLightDesc desc =
        punctual(PunctualType::Directional, 3.0f, Color(1.0f, 0.9f, 0.8f));
    const Vec3 center(1.0f, -2.0f, 0.5f);
    const float radius = 2.5f;
    const DirectionalLight light(desc, center, radius);
    double se = 0.0;
    expectColorNear(meanLeFlux(light, 4096, 3, &se), light.power(), 1e-5);
    for (int i = 0; i < 64; ++i) {
        const auto s = light.sampleLe(Vec2((i + 0.5f) / 64.0f, 0.99f), Vec2(0.5f));
        ASSERT_TRUE(s);
        EXPECT_EQ(s->w, desc.direction);
        // On the disc of radius R, perpendicular to the light, one radius behind the centre.
        EXPECT_NEAR(glm::dot(s->p - center, desc.direction), -radius, 1e-5f);
        EXPECT_LE(glm::length(s->p - center + desc.direction * radius), radius * (1.0f + 1e-5f));
    }
}

TEST(SampleLe, TriangleLightFluxIsItsPowerOnEachSide) {
    for (const bool doubleSided : {false, true}) {
        const auto e = makeEmitter(doubleSided);
        double se = 0.0;
        expectColorNear(meanLeFlux(*e->light, 4096, 4, &se), e->light->power(), 1e-5);
        int back = 0;
        constexpr int kCount = 4096;
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> uniform(0.0f, 0.99999994f);
        for (int i = 0; i < kCount; ++i) {
            const auto s = e->light->sampleLe(Vec2(uniform(rng), uniform(rng)),
                                              Vec2(uniform(rng), uniform(rng)));
            ASSERT_TRUE(s);
            EXPECT_GT(glm::dot(s->w, s->n), 0.0f);
            back += glm::dot(s->n, e->normal()) < 0.0f ? 1 : 0;
            // The origin lies in the triangle's plane.
            EXPECT_NEAR(glm::dot(s->p - e->vertex(0), e->normal()), 0.0f, 1e-6f);
            // Behind a one-sided emitter nothing is emitted.
            EXPECT_EQ(maxComponent(e->light->emittedLe(*s, -e->normal())) > 0.0f, doubleSided);
        }
        if (doubleSided) {
            // Binomial(4096, 1/2): 5 standard deviations is 160.
            EXPECT_NEAR(back, kCount / 2, 160);
        } else {
            EXPECT_EQ(back, 0);
        }
    }
}

TEST(SampleLe, TexturedTriangleLightFluxIsItsPower) {
    const auto e = makeEmitter(false);
    addEmissionTexture(*e);
    e->mesh.uvs[0] = {Vec2(0.0f), Vec2(4.0f, 0.0f), Vec2(0.0f, 4.0f)};  // two repeats each way
    e->light.emplace(e->mesh, 0, e->material, e->textures);
    double se = 0.0;
    const Color flux = meanLeFlux(*e->light, 200000, 6, &se);
    std::printf("[ measured ] textured sampleLe flux %.6g, power %.6g, relative SE %.2g\n",
                luminance(flux), luminance(e->light->power()), se);
    // power() uses the texture's average, which the triangle covers in whole repeats up to its
    // slanted edge: the mean over the triangle differs from the texture's average (measured
    // 1.4 % below it, standard error 0.05 %); 5 % plus 4.5 standard errors allowed, while a
    // sample evaluated at the wrong texture coordinates or without the texture is 15 % or more
    // away.
    expectColorNear(flux, e->light->power(), 0.05 + 4.5 * se);
}

// The emitted directions follow the density each light reports (pdfDir), which equals the closed
// form: 1 / (4 pi) for a point light, uniform in the outer cone for a spot, cos / pi over the
// front for an area light, |cos| / (2 pi) on both sides for a doubleSided one.
TEST(SampleLe, DirectionsFollowTheirPdf) {
    const PointLight point(punctual(PunctualType::Point, 1.0f));
    PunctualLightDesc spotDesc = punctual(PunctualType::Spot, 1.0f);
    spotDesc.outerConeAngle = 1.0f;
    const SpotLight spot(spotDesc);
    const auto oneSided = makeEmitter(false);
    const auto twoSided = makeEmitter(true);
    const float cosOuter = std::cos(1.0f);
    const Vec3 n = oneSided->normal();

    struct Case {
        const char* name;
        const Light& light;
        std::function<float(const Vec3&)> pdf;
    };
    const std::vector<Case> cases = {
        {"point", point, [](const Vec3&) { return kInv4Pi; }},
        {"spot", spot,
         [&](const Vec3& w) {
             return glm::dot(w, spotDesc.direction) >= cosOuter
                        ? 1.0f / (2.0f * kPi * (1.0f - cosOuter))
                        : 0.0f;
         }},
        {"one-sided area", *oneSided->light,
         [&](const Vec3& w) { return glm::max(glm::dot(w, n), 0.0f) * kInvPi; }},
        {"double-sided area", *twoSided->light,
         [&](const Vec3& w) { return std::abs(glm::dot(w, n)) * 0.5f * kInvPi; }},
    };
    for (const Case& c : cases) {
        Chi2Options options;
        options.testCount = static_cast<int>(cases.size());
        options.seed = 7;
        const Chi2Result result = chi2Test(
            [&](const Vec3& u) -> std::optional<Vec3> {
                const auto s = c.light.sampleLe(Vec2(0.3f, 0.6f), Vec2(u.x, u.y));
                if (!s)
                    return std::nullopt;
                EXPECT_NEAR(s->pdfDir, c.pdf(s->w), 1e-3f * c.pdf(s->w) + 1e-6f) << c.name;
                return s->w;
            },
            c.pdf, options);
        EXPECT_TRUE(result.passed) << c.name << ": " << result.report;
    }
}

}  // namespace
}  // namespace penumbra
