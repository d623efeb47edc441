#include "passes/caustic_pass.h"

#include "core/progress.h"
#include "core/stats.h"
#include "passes/progressive_caustic_pass.h"
#include "raytrace/specular_chain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace penumbra {

namespace {

const NamedValues<std::string> kMethods = {{"photon_map", "photon_map"},
                                           {"progressive", "progressive"}};
const NamedValues<CausticKernel> kKernels = {
    {kernelName(CausticKernel::Cone), CausticKernel::Cone},
    {kernelName(CausticKernel::Epanechnikov), CausticKernel::Epanechnikov},
    {kernelName(CausticKernel::Gaussian), CausticKernel::Gaussian}};

// The script keys of the photon-map pass (CausticSettings' table at the top of
// caustics/caustic_map.cpp, and the view's), in the order the plan prints them.
template <typename Settings, typename Count, typename Keys>
void photonMapKeys(Settings& s, Count& maxSpecularDepth, Count& viewSpp, Keys& keys) {
    keys.orAuto("photons", s.photons, CausticPass::kAutoPhotons, int64_t{1},
                int64_t{std::numeric_limits<uint32_t>::max()});
    keys.orAuto("k", s.k, CausticPass::kAutoK, 2, 10000);
    keys.orAuto("max_radius", s.maxRadius, 0.0f);
    keys.choice("kernel", s.kernel, kKernels, "kernel");
    keys("seed", s.seed);
    keys("max_specular_depth", maxSpecularDepth, 0, kMaxDepthLimit);
    keys("view_spp", viewSpp, 1, std::numeric_limits<int>::max());
}

}  // namespace

std::unique_ptr<Pass> CausticPass::fromScript(const ScriptTable& table,
                                              const PassOverrides& overrides) {
    ParameterReader keys(table);
    std::string method = "photon_map";
    keys.choice("method", method, kMethods, "method");
    if (method == "progressive")
        return ProgressiveCausticPass::fromScript(table, overrides);
    CausticSettings settings = defaultSettings();
    int maxSpecularDepth = kDefaultMaxSpecularDepth, viewSpp = kDefaultViewSpp;
    photonMapKeys(settings, maxSpecularDepth, viewSpp, keys);
    return keys.construct("caustics.", [&] {
        return std::make_unique<CausticPass>(settings, maxSpecularDepth, viewSpp);
    });
}

// Above this solid angle of the lights seen from the specular meshes
// (SceneContents::lightSolidAngleAtSpecular) a yielding caustic pass steps aside: the path
// tracer finds those caustics often enough. Measured: the modern hall's lights, seen through its
// glass balustrade, 1.8 sr, where the corrected hybrid without the map is 0.49 x the path
// tracer at 64 s against 0.58 x with it; the caustic spheres' 8 cm light, 0.027 sr, where the
// map takes the hybrid's error at 16 s from 0.033 to 0.0077; the glossy spheres' 0.15 sr. The
// threshold sits between the two measured scenes, about their geometric mean.
constexpr float kLargeLightSolidAngle = 0.25f;

std::string CausticPass::skipReason(const SceneContents& contents) const {
    const std::string none = causticPassSkipReason(contents);
    if (!none.empty() || !yields_ || !causticsTracedLater_)
        return none;
    // As in the reference, a point light's caustics are then missing: no path from the eye
    // finds them.
    if (contents.medium)
        return "the scene has a medium, which the photons do not cross: the path pass traces the "
               "caustics (a point light's are missing, as in the reference)";
    // A punctual light's caustics cannot be found by tracing from the eye: the map stays.
    if (contents.punctualLights > 0 || contents.lightSolidAngleAtSpecular < kLargeLightSolidAngle)
        return "";
    std::ostringstream reason;
    reason.precision(2);
    reason << "the lights look large from the specular surfaces ("
           << contents.lightSolidAngleAtSpecular << " sr, above " << kLargeLightSolidAngle
           << "): the path pass traces their caustics";
    return reason.str();
}

CausticPass::CausticPass(CausticSettings settings, int maxSpecularDepth, int viewSpp)
    : settings_(settings), maxSpecularDepth_(maxSpecularDepth), viewSpp_(viewSpp) {
    CausticSettings resolved = settings_;
    if (resolved.photons == kAutoPhotons)
        resolved.photons = kBasePhotons;
    if (resolved.k == kAutoK)
        resolved.k = kBaseK;
    validateCausticSettings(resolved);
}

int CausticPass::automaticK(int64_t photons) {
    // Consistent k-nearest density estimation wants k to grow and k / N to vanish (Loftsgaarden
    // and Quesenberry 1965, whose example is k = sqrt(N)). The squared bias (~(r_k²)² ~ (k / N)²
    // for a smooth density in the plane) against the variance (~1 / k) would grow k faster, as
    // N^(2/3) (Silverman 1986, chapter 5); sqrt(N) keeps each estimate cheaper and the blur of a
    // caustic's sharp edges, where the density is not smooth, smaller.
    const double k = kBaseK * std::sqrt(static_cast<double>(photons) / kBasePhotons);
    return static_cast<int>(std::clamp(std::round(k), double(kBaseK), double(kMaxAutoK)));
}

std::shared_ptr<const CausticMap> CausticPass::buildMap(PassContext& context,
                                                        const CausticSettings& seeded) const {
    const RenderSettings& render = context.settings;
    const auto build = [&](int64_t photons) {
        CausticSettings settings = seeded;
        settings.photons = photons;
        if (settings.k == kAutoK)
            settings.k = automaticK(photons);
        Progress progress("caustic photons", static_cast<uint64_t>(photons), render.quiet);
        auto map = std::make_shared<const CausticMap>(
            CausticMap::build(context.scene, settings, &progress));
        progress.finish();
        return map;
    };
    if (seeded.photons != kAutoPhotons)
        return build(seeded.photons);
    // The k-nearest estimate's bias falls with the photons' density (its radius r_k² ~ k / N, k
    // fixed) and its noise, averaged over a pixel's footprint, with their number: photons in
    // proportion to the budget make the map consistent as the image's samples are.
    const double maxPhotons = static_cast<double>(std::numeric_limits<uint32_t>::max());
    const double bySamples =
        static_cast<double>(kBasePhotons) * std::max(1.0, double(render.spp) / kBaseSpp);
    std::shared_ptr<const CausticMap> first = build(kBasePhotons);
    double photons = bySamples;
    if (render.timeLimit > 0.0) {
        // What the first photons' rate fits in the time share.
        const double rate = static_cast<double>(kBasePhotons) / std::max(first->seconds(), 1e-3);
        photons = std::min(photons, rate * render.timeLimit * kTimeShare);
    }
    const double storedFraction = static_cast<double>(first->photons().size()) / kBasePhotons;
    if (storedFraction > 0.0)
        photons = std::min(photons, kMaxStoredPhotons / storedFraction);
    photons = std::min(photons, maxPhotons);
    if (photons < 2.0 * kBasePhotons)
        return first;  // more would not pay for shooting the first ones again
    first.reset();
    return build(static_cast<int64_t>(photons));
}

PassStats CausticPass::parameters() const {
    ParameterPrinter print;
    print("method", std::string("photon_map"));
    photonMapKeys(settings_, maxSpecularDepth_, viewSpp_, print);
    return print.stats();
}

RadianceEstimator CausticPass::makeEstimator(PassContext& context) {
    CausticSettings seeded = settings_;
    seeded.seed += context.settings.seed;  // a render's seed changes its photons too
    map_ = buildMap(context, seeded);
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
