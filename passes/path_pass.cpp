#include "passes/path_pass.h"

#include "radiosity/radiosity_solution.h"

namespace penumbra {

std::set<std::string> PathPass::needs() const {
    if (settings_.reuseRadiosity)
        return {"radiosity"};
    return {};
}

void PathPass::adapt(const PipelineShape& shape) {
    settings_.excludeCaustics = caustics_ == Caustics::Exclude ||
                                (caustics_ == Caustics::Auto && shape.products.count("caustics"));
}

PassStats PathPass::parameters() const {
    return {{"max_depth", std::to_string(settings_.maxDepth)},
            {"radiosity", settings_.reuseRadiosity ? "true" : "false"},
            {"caustics", caustics_ == Caustics::Auto      ? "auto"
                         : caustics_ == Caustics::Include ? "include"
                                                          : "exclude"}};
}

RadianceEstimator PathPass::makeEstimator(PassContext& context) {
    radiosity_ = context.product<RadiositySolution>("radiosity");
    tracer_ = std::make_unique<PathTracer>(context.scene, settings_, radiosity_.get());
    return [tracer = tracer_.get()](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                    PathCounters& counters) {
        return tracer->Li(ray, sampler, firstHit, counters);
    };
}

}  // namespace penumbra
