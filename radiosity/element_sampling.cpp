#include "radiosity/element_sampling.h"

#include "core/light.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"

#include <cassert>
#include <cmath>
#include <optional>

namespace penumbra {

ElementSample sampleElement(const Scene& scene, const RadiosityMesh& mesh, int element, Vec2 u) {
    const Vec3 w = sampleUniformTriangle(u);
    const auto& corners = mesh.barycentrics(element);
    const SurfaceHit hit = scene.surfaceAt(mesh.sceneMesh(element), mesh.sceneTriangle(element),
                                           w.x * corners[0] + w.y * corners[1] + w.z * corners[2]);
    return {hit.p, hit.pError, mesh.normal(element)};
}

void stratifiedElementSamples(const Scene& scene, const RadiosityMesh& mesh, int element,
                              uint32_t seed, IVec2 key, std::span<ElementSample> out) {
    Sampler sampler(seed);
    for (size_t k = 0; k < out.size(); ++k) {
        sampler.startPixelSample(key, static_cast<uint32_t>(k));
        out[k] = sampleElement(scene, mesh, element, sampler.get2D());
    }
}

Color meanTransmittance(const Scene& scene, std::span<const ElementSample> a,
                        std::span<const ElementSample> b) {
    assert(!a.empty() && a.size() == b.size());
    Color sum(0.0f);
    for (size_t k = 0; k < a.size(); ++k)
        sum += scene.transmittance(a[k].p, a[k].pError, a[k].n, b[k].p, b[k].pError, b[k].n);
    return sum / static_cast<float>(a.size());
}

std::vector<const Light*> punctualLights(const Scene& scene) {
    std::vector<const Light*> lights;
    for (const auto& light : scene.lights()) {
        if (light->isDelta())
            lights.push_back(light.get());
    }
    return lights;
}

PunctualDirect punctualDirect(const Scene& scene, const RadiosityMesh& mesh, int element,
                              std::span<const Light* const> lights, int samples, uint32_t seed) {
    PunctualDirect result;
    if (lights.empty())
        return result;
    Sampler sampler(seed);
    std::array<Color, 2> sum{Color(0.0f), Color(0.0f)};
    std::array<float, 2> lo{INFINITY, INFINITY}, hi{0.0f, 0.0f};
    for (int k = 0; k < samples; ++k) {
        sampler.startPixelSample(IVec2(element, 0), static_cast<uint32_t>(k));
        const ElementSample x = sampleElement(scene, mesh, element, sampler.get2D());
        std::array<Color, 2> E{Color(0.0f), Color(0.0f)};
        for (const Light* light : lights) {
            const LightSampleContext ctx{x.p, x.pError, x.n};
            // A delta light has one direction: the sample point is irrelevant.
            const std::optional<LightLiSample> ls = light->sampleLi(ctx, Vec2(0.5f));
            if (!ls)
                continue;
            const float cosTheta = glm::dot(ls->wi, x.n);
            if (cosTheta == 0.0f)
                continue;
            const Color T =
                scene.transmittance(x.p, x.pError, x.n, ls->pLight, ls->pLightError, ls->nLight);
            E[cosTheta > 0.0f ? 0 : 1] += ls->L * std::abs(cosTheta) * T;
        }
        for (int side = 0; side < 2; ++side) {
            sum[side] += E[side];
            lo[side] = glm::min(lo[side], maxComponent(E[side]));
            hi[side] = glm::max(hi[side], maxComponent(E[side]));
        }
    }
    for (int side = 0; side < 2; ++side) {
        result.D[side] = sum[side] * (kInvPi / static_cast<float>(samples));
        result.spread[side] = (hi[side] - lo[side]) * kInvPi;
    }
    return result;
}

}  // namespace penumbra
