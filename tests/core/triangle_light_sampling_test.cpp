// The area light's sampling from receivers around it (in front, behind, grazing, very close, just
// outside an edge): its pdfLi integrates to one over the sphere of directions (stratified
// quadrature) and equals the pdf sampleLi() reports for the same direction, and sampleLi() follows
// pdfLi (chi-square). Every statistical test has a fixed seed, and states why its tolerance is
// right.
#include "core/sampling.h"
#include "core/triangle_light.h"
#include "tests/support/chi2.h"
#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <optional>
#include <ostream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace penumbra::test {
namespace {

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

}  // namespace
}  // namespace penumbra::test
