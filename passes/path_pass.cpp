#include "passes/path_pass.h"

#include "caustics/caustic_map.h"
#include "passes/products.h"

namespace penumbra {

namespace {

const NamedValues<PathPass::Caustics> kCausticsModes = {{"auto", PathPass::Caustics::Auto},
                                                        {"include", PathPass::Caustics::Include},
                                                        {"exclude", PathPass::Caustics::Exclude}};

// The script keys of the path pass, in the order the plan prints them.
template <typename Settings, typename Mode, typename Sigma, typename Keys>
void pathKeys(Settings& s, Mode& caustics, Sigma& correctionSigma, Keys& keys) {
    keys("max_depth", s.maxDepth, -1, kMaxDepthLimit);
    keys("radiosity", s.reuseRadiosity);
    keys("correction", s.correctionProbability, 0.0f, 1.0f);
    keys("correction_sigma", correctionSigma, 0.0f, 64.0f);
    keys.choice("caustics", caustics, kCausticsModes);
}

}  // namespace

std::unique_ptr<Pass> PathPass::fromScript(const ScriptTable& table,
                                           const PassOverrides& overrides) {
    ParameterReader keys(table);
    PathTracerSettings settings;
    Caustics caustics = Caustics::Auto;
    float correctionSigma = kDefaultCorrectionSigma;
    pathKeys(settings, caustics, correctionSigma, keys);
    settings.maxDepth = overrides.maxDepth.value_or(settings.maxDepth);
    return std::make_unique<PathPass>(settings, caustics, correctionSigma);
}

std::set<std::string> PathPass::needs() const {
    std::set<std::string> needs;
    if (settings_.reuseRadiosity)
        needs.insert(products::kRadiositySolution);
    if (settings_.causticsAtReuse && !settings_.causticsInRadiosity)
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
    // ... and, with them, the light through specular surfaces, when it carried it.
    settings_.specularInRadiosity =
        settings_.causticsInRadiosity && shape.specularTransferInRadiosity;
}

PassStats PathPass::parameters() const {
    ParameterPrinter print;
    pathKeys(settings_, caustics_, correctionSigma_, print);
    return print.stats();
}

float PathPass::correctionSigma() const {
    const bool corrects = reuses_ && settings_.correctionProbability > 0.0f;
    return corrects ? correctionSigma_ : 0.0f;
}

std::vector<std::string> PathPass::lightGroups() const {
    std::vector<std::string> names;
    if (lightGroupSplit_) {
        for (const LightGroup& group : lightGroupSplit_->groups())
            names.push_back(group.name);
    }
    return names;
}

RadianceEstimator PathPass::makeEstimator(PassContext& context) {
    radiosity_ = context.product<RadiositySolution>(products::kRadiositySolution);
    causticMap_ = context.product<CausticMap>(products::kCausticMap);
    PathTracerSettings settings = settings_;
    // No solution: the radiosity pass was skipped (no diffuse surface, so there is nothing to
    // reuse) or abandoned at the time limit (PathPass::transportFlags); every path is traced on.
    reuses_ = settings.reuseRadiosity && radiosity_;
    if (!reuses_) {
        const bool excludeCaustics = settings.excludeCaustics;
        settings = PathTracerSettings{settings.maxDepth};
        settings.excludeCaustics = excludeCaustics;
    }
    // The ray from a reuse vertex to the specular surfaces it sees would find none (the
    // planner's analysis, which also skips the caustic pass then).
    settings.specularAtReuse = context.contents.specular;
    if (radiosity_)
        reusedSolution_.emplace(*radiosity_);
    if (causticMap_)
        reusedCaustics_.emplace(*causticMap_);
    if (context.settings.lightGroups && splitsLightGroups())
        lightGroupSplit_.emplace(context.scene);
    tracer_ = std::make_unique<PathTracer>(context.scene, settings,
                                           reusedSolution_ ? &*reusedSolution_ : nullptr,
                                           reusedCaustics_ ? &*reusedCaustics_ : nullptr,
                                           lightGroupSplit_ ? &*lightGroupSplit_ : nullptr);
    return [tracer = tracer_.get()](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                    PathCounters& counters) {
        return tracer->Li(ray, sampler, firstHit, counters);
    };
}

}  // namespace penumbra
