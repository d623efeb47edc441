#include "passes/path_pass.h"

#include "caustics/caustic_map.h"
#include "passes/products.h"
#include "radiosity/radiosity_solution.h"

namespace penumbra {

std::set<std::string> PathPass::needs() const {
    std::set<std::string> needs;
    if (settings_.reuseRadiosity)
        needs.insert(products::kRadiositySolution);
    if (settings_.causticsAtReuse)
        needs.insert(products::kCausticMap);
    return needs;
}

void PathPass::adapt(const PipelineShape& shape) {
    settings_.excludeCaustics = caustics_ == Caustics::Exclude ||
                                (caustics_ == Caustics::Auto && shape.causticPathsCounted);
    // A caustic map made before this pass also lights the second diffuse vertex.
    settings_.causticsAtReuse =
        settings_.reuseRadiosity && shape.madeBefore.count(products::kCausticMap);
    // ... unless the solution took the map's photons, which then lights it through the solution.
    settings_.causticsInRadiosity = settings_.causticsAtReuse && shape.causticsInRadiosity;
}

PassStats PathPass::parameters() const {
    return {{"max_depth", std::to_string(settings_.maxDepth)},
            {"radiosity", settings_.reuseRadiosity ? "true" : "false"},
            {"caustics", caustics_ == Caustics::Auto      ? "auto"
                         : caustics_ == Caustics::Include ? "include"
                                                          : "exclude"}};
}

RadianceEstimator PathPass::makeEstimator(PassContext& context) {
    radiosity_ = context.product<RadiositySolution>(products::kRadiositySolution);
    causticMap_ = context.product<CausticMap>(products::kCausticMap);
    PathTracerSettings settings = settings_;
    // The ray from a reuse vertex to the specular surfaces it sees would find none (the
    // planner's analysis, which also skips the caustic pass then).
    settings.specularAtReuse = context.contents.specular;
    tracer_ =
        std::make_unique<PathTracer>(context.scene, settings, radiosity_.get(), causticMap_.get());
    return [tracer = tracer_.get()](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                    PathCounters& counters) {
        return tracer->Li(ray, sampler, firstHit, counters);
    };
}

}  // namespace penumbra
