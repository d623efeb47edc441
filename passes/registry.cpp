// The registries of passes: built-in pipelines (name -> the passes it runs) and pass types of
// scripts (name -> the constructor from a [[pass]] table). Adding a preset or a pass type touches
// this file, the pass's own files and a test.
#include "core/errors.h"
#include "passes/caustic_pass.h"
#include "passes/composite.h"
#include "passes/distribution_pass.h"
#include "passes/path_pass.h"
#include "passes/pipeline.h"
#include "passes/planner.h"
#include "passes/progressive_caustic_pass.h"
#include "passes/radiosity_pass.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <utility>

namespace penumbra {

namespace {

using PresetFactory = std::function<std::vector<std::unique_ptr<Pass>>(const RenderSettings&)>;

const std::vector<std::pair<std::string, PresetFactory>>& presets() {
    static const std::vector<std::pair<std::string, PresetFactory>> table = {
        {"reference",
         [](const RenderSettings& settings) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<PathPass>(PathTracerSettings{settings.maxDepth}));
             return passes;
         }},
        {"radiosity",
         [](const RenderSettings&) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<RadiosityPass>(RadiositySettings{}));
             return passes;
         }},
        // Whitted's ray tracing (the seed's Eq. 2): direct light, mirror and refraction
        // recursion, no ambient term unless a script sets one. The crudest preview.
        {"whitted",
         [](const RenderSettings&) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<DistributionPass>(
                 DistributionSettings{}, DistributionPass::Ambient::Constant));
             return passes;
         }},
        // The seed's two-pass method: an indirect-only radiosity solution as the ambient term
        // of distribution ray tracing.
        {"distribution",
         [](const RenderSettings&) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<RadiosityPass>(RadiositySettings{}));
             passes.push_back(std::make_unique<DistributionPass>(DistributionSettings{}));
             return passes;
         }},
        // The seed's three-pass method: the caustic photon map, radiosity that takes the
        // photons' flux as well, then path tracing that takes the solution at the second
        // diffuse vertex (docs/light-paths.md); the planner skips the caustic pass for a scene
        // without specular surfaces.
        {"hybrid",
         [](const RenderSettings& settings) {
             std::vector<std::unique_ptr<Pass>> passes;
             passes.push_back(std::make_unique<CausticPass>(CausticSettings{}));
             passes.push_back(std::make_unique<RadiosityPass>(RadiositySettings{}));
             PathTracerSettings path{settings.maxDepth};
             path.reuseRadiosity = true;
             passes.push_back(std::make_unique<PathPass>(path));
             return passes;
         }},
    };
    return table;
}

// Largest max_depth accepted, as --max-depth.
constexpr int kMaxDepthLimit = 1 << 20;

// A settings check's UsageError "PREFIXkey: what" moved to the key's place in the script (or the
// table's, for a key the script does not give).
ScriptError atKey(const ScriptTable& table, const std::string& prefix, const UsageError& e) {
    const std::string message = e.what();
    const size_t colon = message.find(": ");
    if (message.rfind(prefix, 0) != 0 || colon == std::string::npos)
        return table.error("", message);
    return table.error(message.substr(prefix.size(), colon - prefix.size()),
                       message.substr(colon + 2));
}

// The radiosity pass. `solver` picks the method and so the keys that are valid: those of
// RadiositySettings for "hierarchical" (the table at the top of radiosity/radiosity_solver.cpp),
// those of ProgressiveSettings for "progressive" (radiosity/progressive_solver.cpp); each set is
// checked by its validate function, the same rules as for any other caller, and a key of the other
// solver is refused as unknown.
std::unique_ptr<Pass> hierarchicalRadiosityPass(const ScriptTable& p) {
    RadiositySettings s;
    s.epsilon = p.get("epsilon", s.epsilon);
    s.patchEdgeLength = p.get("patch_edge_length", s.patchEdgeLength);
    s.minElementArea = p.get("min_element_area", s.minElementArea);
    s.convergence = p.get("convergence", s.convergence);
    s.visibilitySamples = p.get("visibility_samples", s.visibilitySamples);
    s.maxIterations = p.get("max_iterations", s.maxIterations);
    s.maxRefinements = p.get("max_refinements", s.maxRefinements);
    s.clusterMinPatches = p.get("cluster_min_patches", s.clusterMinPatches);
    s.subdivisionThreshold = p.get("subdivision_threshold", s.subdivisionThreshold);
    // An integer, or "auto" (the default): the solver decides (RadiositySettings::finalGatherRays).
    if (p.holdsString("final_gather")) {
        const std::string gather = p.get<std::string>("final_gather", "");
        if (gather != "auto")
            throw p.error("final_gather",
                          "unknown value '" + gather + "'; valid: an integer in [0, 65536], auto");
    } else {
        s.finalGatherRays =
            p.get("final_gather", s.finalGatherRays, 0, RadiositySettings::kMaxFinalGatherRays);
    }
    const std::string iteration = p.get<std::string>("iteration", "gauss-seidel");
    if (iteration == "jacobi") {
        s.iteration = RadiositySettings::Iteration::Jacobi;
    } else if (iteration != "gauss-seidel") {
        throw p.error("iteration",
                      "unknown iteration '" + iteration + "'; valid: gauss-seidel, jacobi");
    }
    // Whether the solution takes the photons of a caustic pass before it.
    const std::string caustics = p.get<std::string>("caustics", "auto");
    if (caustics != "auto" && caustics != "exclude")
        throw p.error("caustics", "unknown value '" + caustics + "'; valid: auto, exclude");
    try {
        validateRadiositySettings(s);
    } catch (const UsageError& e) {
        throw atKey(p, "radiosity.", e);
    }
    return std::make_unique<RadiosityPass>(
        s, caustics == "auto" ? RadiosityPass::Caustics::Auto : RadiosityPass::Caustics::Exclude);
}

std::unique_ptr<Pass> progressiveRadiosityPass(const ScriptTable& p) {
    ProgressiveSettings s;
    s.patchEdgeLength = p.get("patch_edge_length", s.patchEdgeLength);
    s.elementArea = p.get("element_area", s.elementArea);
    s.threshold = p.get("threshold", s.threshold);
    s.maxShots = p.get("max_shots", s.maxShots);
    s.visibilitySamples = p.get("visibility_samples", s.visibilitySamples);
    s.adaptiveVisibility = p.get("adaptive_visibility", s.adaptiveVisibility);
    s.ambient = p.get("ambient", s.ambient);
    try {
        validateProgressiveSettings(s);
    } catch (const UsageError& e) {
        throw atKey(p, "radiosity.", e);
    }
    return std::make_unique<RadiosityPass>(s);
}

std::unique_ptr<Pass> radiosityPass(const ScriptTable& p, const PassOverrides&) {
    const std::string solver = p.get<std::string>("solver", "hierarchical");
    if (solver == "hierarchical")
        return hierarchicalRadiosityPass(p);
    if (solver == "progressive")
        return progressiveRadiosityPass(p);
    throw p.error("solver", "unknown solver '" + solver + "'; valid: hierarchical, progressive");
}

// The path-tracing pass (the `reference` pipeline's; the `hybrid` one's with radiosity = true).
std::unique_ptr<Pass> pathPass(const ScriptTable& p, const PassOverrides& overrides) {
    PathTracerSettings settings;
    settings.maxDepth =
        overrides.maxDepth.value_or(p.get("max_depth", settings.maxDepth, -1, kMaxDepthLimit));
    settings.reuseRadiosity = p.get("radiosity", false);
    const std::string caustics = p.get<std::string>("caustics", "auto");
    const std::vector<std::pair<std::string, PathPass::Caustics>> modes = {
        {"auto", PathPass::Caustics::Auto},
        {"include", PathPass::Caustics::Include},
        {"exclude", PathPass::Caustics::Exclude}};
    for (const auto& [name, mode] : modes) {
        if (name == caustics)
            return std::make_unique<PathPass>(settings, mode);
    }
    throw p.error("caustics", "unknown value '" + caustics + "'; valid: auto, include, exclude");
}

// Whitted's ray tracing: the distribution tracer with a constant ambient term, a number or
// "radiosity" (the mean of an earlier radiosity pass's solution).
std::unique_ptr<Pass> whittedPass(const ScriptTable& p, const PassOverrides&) {
    DistributionSettings settings;
    settings.maxSpecularDepth =
        p.get("max_specular_depth", settings.maxSpecularDepth, 0, kMaxDepthLimit);
    if (p.holdsString("ambient")) {
        const std::string source = p.get<std::string>("ambient", "");
        if (source != "radiosity")
            throw p.error("ambient", "unknown value '" + source + "'; valid: a number, radiosity");
        return std::make_unique<DistributionPass>(settings,
                                                  DistributionPass::Ambient::RadiosityMean);
    }
    settings.ambient = Color(p.get("ambient", 0.0f, 0.0f, std::numeric_limits<float>::max()));
    return std::make_unique<DistributionPass>(settings, DistributionPass::Ambient::Constant);
}

// The distribution ray-tracing pass (the `distribution` pipeline's).
std::unique_ptr<Pass> distributionPass(const ScriptTable& p, const PassOverrides&) {
    DistributionSettings settings;
    settings.maxSpecularDepth =
        p.get("max_specular_depth", settings.maxSpecularDepth, 0, kMaxDepthLimit);
    return std::make_unique<DistributionPass>(settings);
}

// The caustic pass. `method` picks the reconstruction and so the keys that are valid: a photon
// map (CausticSettings' keys, the table at the top of caustics/caustic_map.cpp, and view_spp) or
// stochastic progressive photon mapping (ProgressiveCausticSettings' keys and iterations); both
// take max_specular_depth for their camera rays. Each set is checked by its validate function.
std::unique_ptr<Pass> causticPass(const ScriptTable& p, const PassOverrides&) {
    const std::string method = p.get<std::string>("method", "photon_map");
    const int maxSpecularDepth = p.get("max_specular_depth", 16, 0, kMaxDepthLimit);
    try {
        if (method == "progressive") {
            ProgressiveCausticSettings s;
            s.photonsPerIteration = p.get<int64_t>("photons_per_iteration", s.photonsPerIteration);
            s.initialRadius = p.get("initial_radius", s.initialRadius);
            s.alpha = p.get("alpha", s.alpha);
            s.seed = static_cast<uint32_t>(p.get<int64_t>("seed", s.seed, 0, UINT32_MAX));
            const int iterations = p.get("iterations", 64, 1, std::numeric_limits<int>::max());
            return std::make_unique<ProgressiveCausticPass>(s, iterations, maxSpecularDepth);
        }
        if (method != "photon_map") {
            throw p.error("method",
                          "unknown method '" + method + "'; valid: photon_map, progressive");
        }
        CausticSettings s;
        s.photons = p.get<int64_t>("photons", s.photons);
        s.k = p.get("k", s.k);
        s.maxRadius = p.get("max_radius", s.maxRadius);
        const std::string kernel = p.get<std::string>("kernel", kernelName(s.kernel));
        const auto parsed = parseKernel(kernel);
        if (!parsed) {
            throw p.error("kernel",
                          "unknown kernel '" + kernel + "'; valid: cone, epanechnikov, gaussian");
        }
        s.kernel = *parsed;
        s.seed = static_cast<uint32_t>(p.get<int64_t>("seed", s.seed, 0, UINT32_MAX));
        const int viewSpp = p.get("view_spp", 16, 1, std::numeric_limits<int>::max());
        return std::make_unique<CausticPass>(s, maxSpecularDepth, viewSpp);
    } catch (const UsageError& e) {
        throw atKey(p, "caustics.", e);
    }
}

// The composite: sums the contributions so far into the beauty; no parameters.
std::unique_ptr<Pass> compositePass(const ScriptTable&, const PassOverrides&) {
    return std::make_unique<CompositePass>();
}

using PassFactory =
    std::function<std::unique_ptr<Pass>(const ScriptTable& parameters, const PassOverrides&)>;

const std::vector<std::pair<std::string, PassFactory>>& passTypes() {
    static const std::vector<std::pair<std::string, PassFactory>> table = {
        {"radiosity", radiosityPass}, {"path", pathPass},        {"distribution", distributionPass},
        {"whitted", whittedPass},     {"caustics", causticPass}, {"composite", compositePass},
    };
    return table;
}

std::string joined(const std::vector<std::string>& names) {
    std::string text;
    for (const std::string& name : names)
        text += (text.empty() ? "" : ", ") + name;
    return text;
}

// The pass of one [[pass]] table, its parameters read and the unread ones refused.
std::unique_ptr<Pass> makeScriptPass(const ScriptPass& entry, const PassOverrides& overrides) {
    const ScriptTable& parameters = entry.parameters;
    const std::string valid = joined(passTypeNames());
    if (entry.type.empty())
        throw parameters.error("type", "missing; valid pass types: " + valid);
    for (const auto& [type, factory] : passTypes()) {
        if (type == entry.type) {
            std::unique_ptr<Pass> pass = factory(parameters, overrides);
            parameters.reportUnused();
            return pass;
        }
    }
    throw parameters.error("type", "unknown pass type '" + entry.type + "'; valid: " + valid);
}

}  // namespace

std::vector<std::string> passTypeNames() {
    std::vector<std::string> names;
    for (const auto& [name, factory] : passTypes())
        names.push_back(name);
    return names;
}

Pipeline makeScriptPipeline(const PassScript& script, const PassOverrides& overrides) {
    std::vector<std::unique_ptr<Pass>> passes;
    for (const ScriptPass& entry : script.passes) {
        // The composite sums what the passes before it made: a pass after it would be lost.
        if (!passes.empty() && passes.back()->type() == "composite") {
            throw entry.parameters.error(
                "", "a pass after the composite pass: the composite must be the last pass");
        }
        passes.push_back(makeScriptPass(entry, overrides));
    }
    Pipeline pipeline(std::filesystem::path(script.file).filename().string(), std::move(passes));
    if (const auto problem = checkPipeline(pipeline))
        throw script.passes.at(problem->pass).parameters.error("", problem->message);
    return pipeline;
}

std::vector<std::string> pipelinePresetNames() {
    std::vector<std::string> names;
    for (const auto& [name, factory] : presets())
        names.push_back(name);
    return names;
}

Pipeline makePipelinePreset(const std::string& name, const RenderSettings& settings) {
    std::string valid;
    for (const auto& [presetName, factory] : presets()) {
        if (presetName == name) {
            Pipeline pipeline(name, factory(settings));
            // A preset is consistent by construction; a problem here is a bug in this file.
            if (const auto problem = checkPipeline(pipeline))
                throw std::logic_error("pipeline preset " + name + ": " + problem->message);
            return pipeline;
        }
        valid += (valid.empty() ? "" : ", ") + presetName;
    }
    throw UsageError("--pipeline: unknown pipeline '" + name + "'; valid: " + valid);
}

}  // namespace penumbra
