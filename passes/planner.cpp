#include "passes/planner.h"

#include "core/errors.h"
#include "core/light_paths.h"
#include "passes/products.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra {

namespace {

std::string passName(size_t index, const Pass& pass) {
    return "pass " + std::to_string(index + 1) + " (" + pass.type() + ")";
}

std::string joined(const std::vector<std::string>& items, const std::string& separator) {
    std::string text;
    for (const std::string& item : items)
        text += (text.empty() ? "" : separator) + item;
    return text;
}

}  // namespace

std::optional<PipelineProblem> checkPipeline(Pipeline& pipeline) {
    const auto& passes = pipeline.passes();
    // Passes the scene skipped (planForScene) take no part: the others are fitted to the rest.
    const auto skipped = [&pipeline](size_t i) { return pipeline.skipped(i); };
    PipelineShape shape;
    for (size_t i = 0; i < passes.size(); ++i) {
        if (skipped(i))
            continue;
        for (const std::string& product : passes[i]->products())
            shape.products.insert(product);
        shape.causticPathsCounted =
            shape.causticPathsCounted || passes[i]->transportFlags().countsCausticPaths;
    }
    for (size_t i = 0; i < passes.size(); ++i) {
        if (skipped(i))
            continue;
        shape.neededLater.clear();
        shape.specularTracedLater = false;
        shape.specularFromSolutionLater = false;
        shape.withoutSolutionLater = WithoutSolution::kSame;
        shape.causticsTracedLater = false;
        shape.solutionShownLater = false;
        for (size_t j = i + 1; j < passes.size(); ++j) {
            if (skipped(j))
                continue;
            const TransportFlags later = passes[j]->transportFlags();
            shape.causticsTracedLater = shape.causticsTracedLater || later.tracesUncountedCaustics;
            shape.solutionShownLater = shape.solutionShownLater || later.showsSolution;
            for (const std::string& need : passes[j]->needs()) {
                shape.neededLater.insert(need);
                if (need == products::kRadiositySolution)
                    shape.withoutSolutionLater =
                        std::min(shape.withoutSolutionLater, later.withoutSolution);
            }
            const SpecularAtReuse specular = later.specularAtReuse;
            shape.specularTracedLater =
                shape.specularTracedLater || specular == SpecularAtReuse::kTraced;
            shape.specularFromSolutionLater =
                shape.specularFromSolutionLater || specular == SpecularAtReuse::kFromSolution;
        }
        passes[i]->adapt(shape);
        for (const std::string& product : passes[i]->products())
            shape.madeBefore.insert(product);
        const TransportFlags flags = passes[i]->transportFlags();
        shape.causticsInRadiosity = shape.causticsInRadiosity || flags.solutionTakesCaustics;
        shape.specularTransferInRadiosity =
            shape.specularTransferInRadiosity || flags.solutionTransfersSpecular;
    }

    // A product whose pass the scene skipped counts as made: it would have been empty (no
    // diffuse surface for a solution), and the passes reusing it do without.
    std::set<std::string> made;
    for (size_t i = 0; i < passes.size(); ++i) {
        for (const std::string& need : skipped(i) ? std::set<std::string>{} : passes[i]->needs()) {
            if (made.count(need) == 0) {
                return PipelineProblem{i, passName(i, *passes[i]) + " reuses the " + need +
                                              " product, which no earlier pass makes: put a pass "
                                              "of type '" +
                                              products::passTypeMaking(need) + "' before it"};
            }
        }
        for (const std::string& product : passes[i]->products())
            made.insert(product);
    }

    // Every pair of image-forming passes must count disjoint sets of light paths.
    for (size_t j = 0; j < passes.size(); ++j) {
        if (skipped(j) || passes[j]->lightPaths().empty())
            continue;
        const PathSet later = PathSet::parse(passes[j]->lightPaths());
        for (size_t i = 0; i < j; ++i) {
            if (skipped(i) || passes[i]->lightPaths().empty())
                continue;
            const PathSet common = PathSet::parse(passes[i]->lightPaths()) & later;
            const std::vector<std::string> examples = common.shortestPaths(3);
            if (!examples.empty()) {
                return PipelineProblem{
                    j, passName(j, *passes[j]) + " and " + passName(i, *passes[i]) +
                           " both count the light paths " + joined(examples, ", ") +
                           (examples.size() == 3 ? ", ..." : "") + " (" + passes[j]->type() + ": " +
                           passes[j]->lightPaths() + "; " + passes[i]->type() + ": " +
                           passes[i]->lightPaths() + "): each path must be counted once"};
            }
        }
    }
    return std::nullopt;
}

PipelinePlan planForScene(Pipeline& pipeline, const SceneContents& contents) {
    PipelinePlan plan;
    std::vector<std::string> vertices;
    if (contents.diffuse)
        vertices.push_back("D");
    if (contents.specular)
        vertices.push_back("S");
    if (contents.mediumScatters)
        vertices.push_back("V");
    plan.universe = vertices.empty()       ? "LE"
                    : vertices.size() == 1 ? "L" + vertices.front() + "*E"
                                           : "L(" + joined(vertices, "|") + ")*E";

    if (contents.areaLights + contents.punctualLights == 0 && !contents.environment &&
        !contents.mediumEmits) {
        plan.warnings.push_back(
            "the scene has no light (no emissive surface, no "
            "KHR_lights_punctual light, no environment, no emitting medium): the image is black");
    } else if (contents.areaLights == 0 && !contents.environment) {
        plan.decisions.push_back("lights: " + std::to_string(contents.punctualLights) +
                                 " punctual, no emissive surface: no area sampling");
    }

    const auto& passes = pipeline.passes();
    std::vector<std::string> skipReasons(passes.size());
    for (size_t i = 0; i < passes.size(); ++i) {
        skipReasons[i] = passes[i]->skipReason(contents);
        if (!skipReasons[i].empty())
            pipeline.skip(i);
    }
    // The passes that run are fitted to each other again (a path pass counts the caustics
    // itself once the caustic pass is skipped); a preset or a checked script stays consistent.
    if (const auto problem = checkPipeline(pipeline))
        throw std::logic_error("planning " + pipeline.name() + ": " + problem->message);
    // Then they say whether they render a medium (a path pass without the caustic map that the
    // skipped caustic pass would have made, for one).
    for (size_t i = 0; i < passes.size(); ++i) {
        if (contents.medium && skipReasons[i].empty() && !passes[i]->rendersMedia()) {
            throw UsageError(pipeline.name() + ": " + passName(i, *passes[i]) +
                             " does not render participating media, and the scene has one: the "
                             "path tracer does (--pipeline reference, or a `path` pass without a "
                             "`caustics` pass before it, and with a `correction` above 0 if it "
                             "reuses radiosity), the corrected hybrid too (--pipeline hybrid), "
                             "and Whitted's pass previews their single scattering "
                             "(--pipeline whitted)");
        }
    }
    PathSet counted = PathSet::parse("");
    for (size_t i = 0; i < passes.size(); ++i) {
        const Pass& pass = *passes[i];
        if (!skipReasons[i].empty()) {
            plan.decisions.push_back(passName(i, pass) + ": skipped: " + skipReasons[i]);
            continue;
        }
        plan.decisions.push_back(passName(i, pass) + ": runs; " +
                                 (pass.lightPaths().empty() ? "adds no image of its own"
                                                            : "counts " + pass.lightPaths()));
        if (!pass.lightPaths().empty())
            counted = counted | PathSet::parse(pass.lightPaths());
    }

    const PathSet missing = PathSet::parse(plan.universe) - counted;
    const std::vector<std::string> examples = missing.shortestPaths(3);
    if (!examples.empty()) {
        plan.warnings.push_back("no pass counts the light paths " + joined(examples, ", ") +
                                (examples.size() == 3 ? " and more like them" : "") +
                                ": their light is missing from the image");
    }
    return plan;
}

}  // namespace penumbra
