#include "radiosity/environment_direct.h"

#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"

namespace penumbra {

namespace {

// The sequences' dimensions: one for each strategy.
constexpr uint32_t kLightDimension = 1;
constexpr uint32_t kCosineDimension = 2;

}  // namespace

Color environmentD(const Scene& scene, const ElementSample& x, const Vec3& n, uint32_t seed,
                   IVec2 key, uint32_t first, uint32_t count, uint64_t& rays) {
    const EnvironmentLight* environment = scene.environment();
    if (!environment || count == 0)
        return Color(0.0f);
    const Bounds3& bounds = scene.bounds();
    // A target beyond the scene's bounding sphere in every direction, as the light's own.
    const float reach =
        bounds.empty() ? 1.0f : glm::length(x.p - bounds.center()) + 2.0f * bounds.boundingRadius();
    const float n1 = static_cast<float>(count);
    // f / (n p_env + n p_cos) of one direction, f = L T cos(theta).
    const auto contribution = [&](const Vec3& wi, float cosTheta) {
        const Color L = environment->radiance(wi);
        if (!(cosTheta > 0.0f) || !(maxComponent(L) > 0.0f))
            return Color(0.0f);
        const float density =
            n1 * (environment->pdfDirection(x.p, wi) + cosineHemispherePdf(cosTheta));
        ++rays;
        const Color T =
            scene.transmittance(x.p, x.pError, n, x.p + wi * reach, Vec3(0.0f), Vec3(0.0f));
        return L * T * (cosTheta / density);
    };
    const SampleSequence2D fromLight(seed, key, kLightDimension);
    const SampleSequence2D fromCosine(seed, key, kCosineDimension);
    const Frame frame = Frame::fromNormal(n);
    const LightSampleContext ctx{x.p, x.pError, n};
    Color E(0.0f);
    for (uint32_t i = first; i < first + count; ++i) {
        if (const std::optional<LightLiSample> ls = environment->sampleLi(ctx, fromLight[i]))
            E += contribution(ls->wi, glm::dot(ls->wi, n));
        const Vec3 local = sampleCosineHemisphere(fromCosine[i]);
        E += contribution(frame.toWorld(local), local.z);
    }
    return E * kInvPi;
}

}  // namespace penumbra
