#include "raytrace/distribution_tracer.h"

#include "core/sampler.h"
#include "radiosity/radiosity_solution.h"
#include "raytrace/direct_light.h"
#include "raytrace/specular_chain.h"

namespace penumbra {

std::string distributionLightPaths() {
    return "L S* E | L D S* E | L D D+ S* E";
}

DistributionTracer::DistributionTracer(const Scene& scene, const DistributionSettings& settings,
                                       const RadiositySolution* indirect)
    : scene_(scene), settings_(settings), indirect_(indirect) {}

PathRadiance DistributionTracer::Li(Ray ray, Sampler& sampler, FirstHit* firstHit,
                                    PathCounters& counters) const {
    const SpecularChainSettings chain{settings_.maxSpecularDepth, true};
    return traceSpecularChain(
        scene_, ray, sampler, firstHit, counters, chain,
        [this](const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo, Sampler& vertexSampler,
               PathCounters& vertexCounters) {
            PathRadiance L;
            L[PathComponent::Direct] =
                estimateDirectLight(scene_, hit, bsdf, wo, vertexSampler, vertexCounters);
            if (indirect_) {
                L[PathComponent::Indirect] += indirect_->indirectRadiance(
                    hit.mesh, hit.triangle, hit.barycentric, glm::dot(wo, hit.ng) > 0.0f);
            }
            if (maxComponent(settings_.ambient) > 0.0f)
                L[PathComponent::Indirect] += bsdf.diffuseGlossyReflectance() * settings_.ambient;
            return L;
        });
}

}  // namespace penumbra
