#include "passes/distribution_pass.h"

#include "core/stats.h"
#include "radiosity/radiosity_solution.h"

namespace penumbra {

PassStats DistributionPass::parameters() const {
    if (ambient_ == Ambient::Constant) {
        return {{"max_specular_depth", std::to_string(settings_.maxSpecularDepth)},
                {"ambient", formatStat(settings_.ambient)}};
    }
    return {{"max_specular_depth", std::to_string(settings_.maxSpecularDepth)}};
}

RadianceEstimator DistributionPass::makeEstimator(PassContext& context) {
    radiosity_ = context.product<RadiositySolution>("radiosity");
    tracer_ = std::make_unique<DistributionTracer>(context.scene, settings_, radiosity_.get());
    return [tracer = tracer_.get()](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                    PathCounters& counters) {
        return tracer->Li(ray, sampler, firstHit, counters);
    };
}

}  // namespace penumbra
