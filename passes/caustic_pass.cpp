#include "passes/caustic_pass.h"

#include "core/progress.h"
#include "core/stats.h"
#include "raytrace/specular_chain.h"

namespace penumbra {

CausticPass::CausticPass(CausticSettings settings, int maxSpecularDepth, int viewSpp)
    : settings_(settings), maxSpecularDepth_(maxSpecularDepth), viewSpp_(viewSpp) {
    validateCausticSettings(settings_);
}

PassStats CausticPass::parameters() const {
    return {{"photons", std::to_string(settings_.photons)},
            {"k", std::to_string(settings_.k)},
            {"max_radius", settings_.maxRadius > 0.0f ? formatStat(settings_.maxRadius) : "auto"},
            {"kernel", kernelName(settings_.kernel)},
            {"max_specular_depth", std::to_string(maxSpecularDepth_)},
            {"view_spp", std::to_string(viewSpp_)}};
}

RadianceEstimator CausticPass::makeEstimator(PassContext& context) {
    {
        Progress progress("caustic photons", static_cast<uint64_t>(settings_.photons),
                          context.settings.quiet);
        CausticSettings seeded = settings_;
        seeded.seed += context.settings.seed;  // a render's seed changes its photons too
        map_ =
            std::make_shared<const CausticMap>(CausticMap::build(context.scene, seeded, &progress));
        progress.finish();
    }
    context.publish<CausticMap>(products::kCausticMap, map_);
    const SpecularChainSettings chain{maxSpecularDepth_, false};
    return [map = map_.get(), &scene = context.scene, chain](
               const Ray& ray, Sampler& sampler, FirstHit* firstHit, PathCounters& counters) {
        return traceSpecularChain(scene, ray, sampler, firstHit, counters, chain,
                                  [map](const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                                        Sampler&, PathCounters&) {
                                      // L S+ D seen at the first vertex: light that scattered
                                      // before, so indirect.
                                      PathRadiance caustic;
                                      caustic[PathComponent::Indirect] =
                                          map->radiance(hit, bsdf, wo);
                                      return caustic;
                                  });
    };
}

PassStats CausticPass::stats() const {
    PassStats stats = SamplingPass::stats();
    for (const auto& [key, value] : map_->stats())
        stats.push_back({"map " + key, value});
    return stats;
}

}  // namespace penumbra
