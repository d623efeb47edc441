// The path tracer and the distribution ray tracer in-process on a Lambertian floor under a point
// light, against the closed form of direct lighting: a camera ray that meets the floor at
// horizontal distance r from the light's foot sees L = rho / pi * I cos(theta) / d^2, with
// d^2 = h^2 + r^2 and cos(theta) = h / d. A lone plane reflects nothing onto itself, so that is
// the whole radiance, all of it direct light; and next-event estimation of a delta light has no
// randomness (one light, one point on it, no occluder), so every sample must equal it.
#include "core/path_components.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "raytrace/distribution_tracer.h"
#include "raytrace/path_tracer.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>

namespace penumbra::test {
namespace {

using Estimator = std::function<PathRadiance(const Ray&, Sampler&, FirstHit*, PathCounters&)>;

// Float rounding in the tracer (the shading frame, the direction to the light, the product of a
// few factors) stays within a few ulps; 1e-5 relative is a hundred of them and ten thousand times
// smaller than the errors the test is for (a missing cos(theta) is 29 % at r = h, a lost 1 / pi a
// factor of 3).
constexpr double kRelativeTolerance = 1e-5;

struct LitFloor {
    PointLightOverFloor floor{.rho = 0.6f, .intensity = 25.0f, .height = 2.0f, .half = 20.0f};
    std::unique_ptr<Scene> scene;

    LitFloor() {
        GltfBuilder builder;
        floor.build(builder);
        scene = loadBuiltScene(builder, "raytrace-point-light");
    }

    // The closed form: the inverse-square cosine law gives the illuminance E = I cos(theta) / d^2
    // at the point, and a Lambertian surface of reflectance rho reflects L = rho E / pi in every
    // direction (its BRDF is rho / pi; Lambert 1760, pbrt-v4 section 9.2).
    double exact(double r) const {
        const double h = floor.height, d2 = h * h + r * r;
        const double cosTheta = h / std::sqrt(d2);
        return floor.rho / kPi * floor.intensity * cosTheta / d2;
    }

    // A camera ray from above and to the side (the radiance of a Lambertian surface does not
    // depend on the direction it is seen from) to the floor point at distance r from the light's
    // foot, along a diagonal, in the loaded scene's coordinates (rebased on the geometry's centre).
    Ray rayTo(double r) const {
        const Vec3 origin(scene->description().origin);
        const float s = static_cast<float>(r / std::sqrt(2.0));
        const Vec3 target = Vec3(s, 0.0f, s) - origin;
        const Vec3 eye = target + Vec3(0.5f, 1.5f, -0.8f);
        return Ray{eye, glm::normalize(target - eye)};
    }
};

// Checks every one of a few samples of the estimator at points r = 0 (under the light), h / 2,
// h and 2h against the closed form, all of it filed as direct light, and the first hit's AOVs.
void expectClosedForm(const LitFloor& lit, const Estimator& Li) {
    Sampler sampler(3);
    PathCounters counters;
    const double h = lit.floor.height;
    for (const double r : {0.0, 0.5 * h, h, 2.0 * h}) {
        const double exact = lit.exact(r);
        const Ray ray = lit.rayTo(r);
        for (uint32_t i = 0; i < 8; ++i) {
            sampler.startPixelSample(IVec2(0, 0), i);
            FirstHit firstHit;
            const PathRadiance L = Li(ray, sampler, &firstHit, counters);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(L.total()[c], exact, kRelativeTolerance * exact)
                    << "r = " << r << ", sample " << i << ", channel " << c;
                EXPECT_EQ(L[PathComponent::Direct][c], L.total()[c]) << "r = " << r;
            }
            // The first hit is the floor, at the end of the camera ray.
            ASSERT_TRUE(firstHit.valid);
            EXPECT_NEAR(firstHit.albedo.g, lit.floor.rho, 1e-6);
            EXPECT_NEAR(firstHit.normal.y, 1.0f, 1e-6);
            EXPECT_NEAR(firstHit.depth, glm::length(Vec3(0.5f, 1.5f, -0.8f)), 1e-5);
        }
    }
}

TEST(PointLightFloor, PathTracerMatchesClosedForm) {
    const LitFloor lit;
    const PathTracer tracer(*lit.scene, PathTracerSettings{});
    expectClosedForm(lit, [&](const Ray& ray, Sampler& sampler, FirstHit* hit, PathCounters& c) {
        return tracer.Li(ray, sampler, hit, c);
    });
}

TEST(PointLightFloor, DistributionTracerWithoutAmbientMatchesClosedForm) {
    const LitFloor lit;
    // No radiosity solution and no constant ambient term: direct light only, which is all there
    // is on a lone plane.
    const DistributionTracer tracer(*lit.scene, DistributionSettings{}, nullptr);
    expectClosedForm(lit, [&](const Ray& ray, Sampler& sampler, FirstHit* hit, PathCounters& c) {
        return tracer.Li(ray, sampler, hit, c);
    });
}

}  // namespace
}  // namespace penumbra::test
