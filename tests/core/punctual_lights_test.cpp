// The KHR_lights_punctual lights against the extension's README: the spot cone's falloff and the
// range window; and photometric units end to end (a point light's I / d², a directional light's
// E, an area light's Le, as sampleLi() reports them). Closed forms, float rounding only.
#include "core/punctual_lights.h"
#include "core/triangle_light.h"
#include "tests/support/test_lights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

namespace penumbra::test {
namespace {

// 1. KHR_lights_punctual spot cone and range window --------------------------------------------

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

// 2. Photometric units end to end --------------------------------------------------------------

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

}  // namespace
}  // namespace penumbra::test
