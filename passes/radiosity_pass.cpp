#include "passes/radiosity_pass.h"

#include "caustics/caustic_map.h"
#include "core/material.h"
#include "core/stats.h"
#include "passes/specular_transfer.h"
#include "radiosity/meshed_hit.h"
#include "radiosity/solve_progress.h"
#include "raytrace/tracing_steps.h"

#include <chrono>
#include <functional>

namespace penumbra {

namespace {

const NamedValues<std::string> kSolvers = {{"hierarchical", "hierarchical"},
                                           {"progressive", "progressive"}};
const NamedValues<RadiosityPass::Caustics> kCausticsModes = {
    {"auto", RadiosityPass::Caustics::Auto}, {"exclude", RadiosityPass::Caustics::Exclude}};
const NamedValues<RadiosityPass::Transfer> kTransferModes = {
    {"auto", RadiosityPass::Transfer::Auto}, {"exclude", RadiosityPass::Transfer::Exclude}};
const NamedValues<RadiositySettings::Iteration> kIterations = {
    {"gauss-seidel", RadiositySettings::Iteration::GaussSeidel},
    {"jacobi", RadiositySettings::Iteration::Jacobi}};

// The script keys of the hierarchical solver (the table at the top of
// radiosity/radiosity_settings.cpp), in the order the plan prints them; sizes of 0 are the solver's
// automatic ones until the scene resolves them.
template <typename Settings, typename Keys>
void hierarchicalKeys(Settings& s, Keys& keys) {
    keys("epsilon", s.epsilon);
    keys.orAuto("patch_edge_length", s.patchEdgeLength, 0.0f);
    keys.orAuto("min_element_area", s.minElementArea, 0.0f);
    keys("contact_lines", s.contactLines);
    keys("shadow_lines", s.shadowLines);
    keys("convergence", s.convergence);
    keys("visibility_samples", s.visibilitySamples);
    keys("max_iterations", s.maxIterations);
    keys("max_refinements", s.maxRefinements);
    keys.choice("iteration", s.iteration, kIterations, "iteration");
    keys("cluster_min_patches", s.clusterMinPatches);
    keys("subdivision_threshold", s.subdivisionThreshold);
    keys.orAuto("final_gather", s.finalGatherRays, RadiositySettings::kAutoFinalGather, 0,
                RadiositySettings::kMaxFinalGatherRays);
    keys("direct_at_corners", s.directAtCorners);
    keys("indirect_at_corners", s.indirectAtCorners);
}

// The script keys of progressive refinement (radiosity/progressive_solver.cpp's table).
template <typename Settings, typename Keys>
void progressiveKeys(Settings& s, Keys& keys) {
    keys.orAuto("patch_edge_length", s.patchEdgeLength, 0.0f);
    keys("element_area", s.elementArea);
    keys("threshold", s.threshold);
    keys("max_shots", s.maxShots);
    keys("visibility_samples", s.visibilitySamples);
    keys("adaptive_visibility", s.adaptiveVisibility);
    keys("ambient", s.ambient);
}

// The caustic photons as flux deposited where they landed.
std::vector<FluxDeposit> causticDeposits(const CausticMap* map) {
    if (!map)
        return {};  // the planner skipped the caustic pass: no specular surface
    return asDeposits(map->photons());
}

}  // namespace

RadiosityPass::RadiosityPass(RadiositySettings settings, Caustics caustics, Transfer transfer)
    : settings_(std::move(settings)), caustics_(caustics), transfer_(transfer) {
    validateRadiositySettings(std::get<RadiositySettings>(settings_));
}

RadiosityPass::RadiosityPass(ProgressiveSettings settings) : settings_(settings) {
    validateProgressiveSettings(settings);
}

RadiosityPass::~RadiosityPass() = default;

std::unique_ptr<Pass> RadiosityPass::fromScript(const ScriptTable& table, const PassOverrides&) {
    ParameterReader keys(table);
    std::string solver = "hierarchical";
    keys.choice("solver", solver, kSolvers, "solver");
    if (solver == "progressive") {
        ProgressiveSettings s;
        progressiveKeys(s, keys);
        return keys.construct("radiosity.", [&] { return std::make_unique<RadiosityPass>(s); });
    }
    RadiositySettings s;
    Caustics caustics = Caustics::Auto;
    keys.choice("caustics", caustics, kCausticsModes);
    Transfer transfer = Transfer::Auto;
    keys.choice("specular_transfer", transfer, kTransferModes);
    int64_t transferPhotons = kAutoTransferPhotons;
    keys.orAuto("transfer_photons", transferPhotons, kAutoTransferPhotons, int64_t{1},
                int64_t{1} << 32);
    hierarchicalKeys(s, keys);
    return keys.construct("radiosity.", [&] {
        auto pass = std::make_unique<RadiosityPass>(s, caustics, transfer);
        pass->transferPhotons_ = transferPhotons;
        return pass;
    });
}

void RadiosityPass::adapt(const PipelineShape& shape) {
    view_ = !shape.neededLater.count(products::kRadiositySolution);
    shown_ = view_ || shape.solutionShownLater;
    withoutSolution_ = view_ ? WithoutSolution::kCannot : shape.withoutSolutionLater;
    const bool hierarchical = std::holds_alternative<RadiositySettings>(settings_);
    takesCaustics_ = caustics_ == Caustics::Auto && shape.madeBefore.count(products::kCausticMap) &&
                     hierarchical;
    // A later pass that reuses the solution at path vertices takes the light they receive
    // through specular surfaces from it only when the solution also holds the caustics
    // (raytrace/path_tracer.h, specularInRadiosity); one that traces it whatever the solution
    // holds (the corrected hybrid) would count it twice.
    transfers_ = transfer_ == Transfer::Auto && hierarchical && !shape.specularTracedLater &&
                 (!shape.specularFromSolutionLater || takesCaustics_);
}

std::string RadiosityPass::lightPaths() const {
    if (!view_)
        return "";
    if (!transfers_)
        return takesCaustics_ ? "L D* E | L S+ D+ E" : "LD*E";
    return takesCaustics_ ? "L E | L S* D (S* D)* E" : "L E | L D (S* D)* E";
}

uint64_t RadiosityPass::transferPhotons(const RadiosityMesh& mesh) const {
    if (transferPhotons_ != kAutoTransferPhotons)
        return static_cast<uint64_t>(transferPhotons_);
    return automaticTransferPhotons(mesh);
}

std::string RadiosityPass::skipReason(const SceneContents& contents) const {
    if (!view_ && !contents.diffuse)
        return "no surface has a diffuse lobe, so the solution would be zero";
    return "";
}

namespace {

// With a time limit, a share of the time left now; none without.
Deadline shareOfTimeLeft(const PassContext& context, double share) {
    if (!context.deadline)
        return std::nullopt;
    const auto now = std::chrono::steady_clock::now();
    return now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                     (*context.deadline - now) * share);
}

// With a time limit, the solve's time is up once it has used a share of the time left when it
// began, so that the image gets the rest: the refinement stops there and the links still being
// decided are made as they stand (a coarser solution: a coarser radiosity view or distribution
// image, never one sample after the whole budget). When only a pass that corrects the solution
// reuses it, the solve is abandoned instead if its links would not be made by then, and that pass
// traces without it (the corrected hybrid becomes the path tracer), and its share is larger: on the
// modern hall the corrected hybrid's error per second of path tracing is a third of the path
// tracer's (docs/benchmarks.md), so a solve that ends before two thirds of the time still pays;
// any other solution gets half. A preview that traces without the solution (WithoutSolution::
// kTraces) takes the coarser solution too, but has the solve abandoned if it would not end
// within the whole time limit: on the grey-white room at 4 s the coarsest solve took 8.7 s and
// left one sample per pixel.
Deadline solveDeadline(const PassContext& context, bool optional) {
    return shareOfTimeLeft(context, optional ? 2.0 / 3.0 : 0.5);
}

// With a time limit, the specular transfer (specular_transfer.h) runs as long as the time limit
// has not passed, even when the solve ended past its share, and begins no round after its first
// that would end past a quarter of the time left: on the modern hall, whose solve for the
// `distribution` preview at 16 s always ends past its share, its two rounds took 1.5-2 s of the
// 7 s left and brought the preview from 0.954-0.964 of the reference's mean to 0.989-1.000
// (docs/radiosity.md, "After the solve, under a time limit").
constexpr double kTransferShare = 0.25;

// With a time limit, the gather of the indirect light at the corners (indirect_at_corners.h) has
// a share of the time left after the solve, and gathers with fewer rays if the rays asked would
// take longer. An image pass still has to sample the rest: on the modern hall's `distribution`
// preview at 16 s (docs/radiosity.md, "After the solve, under a time limit") shares of 0.25, 0.4
// and 0.6 gave relMSE 0.0130, 0.0110 and 0.0110 (means of seeds 0-2) against 0.0168 without the
// corners: 0.4 has 0.6's error and leaves the image more samples. The radiosity view's samples
// only anti-alias its pixels: it gives the gather most of the time.
Deadline cornerDeadline(const PassContext& context, bool view) {
    return shareOfTimeLeft(context, view ? 0.75 : 0.4);
}

}  // namespace

RadiositySettings RadiosityPass::solvedSettings(const RadiositySettings& asked) const {
    RadiositySettings settings = asked;
    // Only a view shows the direct light; the passes that reuse the solution trace it.
    settings.directAtCorners = asked.directAtCorners && view_;
    // Only a view and distribution ray tracing's ambient term show the indirect light at points;
    // the path tracers read the solution one bounce or more from the eye.
    if (!shown_)
        settings.indirectAtCorners = 0;
    return settings;
}

void RadiosityPass::prepare(PassContext& context) {
    scene_ = &context.scene;
    // The solve's stages (meshing, direct light, linking, rounds, sweeps) on standard error.
    ConsoleSolveProgress progress("radiosity", context.settings.quiet);
    const auto mesh = [&](const MeshingSettings& meshing) {
        progress.beginStage("meshing", 0);
        mesh_ = std::make_shared<RadiosityMesh>(context.scene, meshing);
        progress.endStage(std::to_string(mesh_->patchCount()) + " patches");
    };
    if (const auto* asked = std::get_if<RadiositySettings>(&settings_)) {
        const RadiositySettings settings = solvedSettings(*asked);
        const RadiositySettings* hierarchical = &settings;
        MeshingSettings meshing = hierarchical->meshing(context.scene);
        // The specular transfer carries the sharp glossy lobes' reflection as a mirror's for
        // the passes that reuse the solution; a view, which can show only one radiance per
        // point, shows it spread as the rough lobes'.
        meshing.spreadSharpGlossy = !(transfers_ && !view_ && context.contents.sharpGlossy);
        mesh(meshing);
        const std::vector<FluxDeposit> deposits =
            takesCaustics_
                ? causticDeposits(context.product<CausticMap>(products::kCausticMap).get())
                : std::vector<FluxDeposit>{};
        auto solver =
            std::make_unique<RadiositySolver>(context.scene, *mesh_, *hierarchical, deposits);
        const bool optional = withoutSolution_ == WithoutSolution::kSame;
        // A preview that can trace without the solution has it abandoned only when it would not
        // end within the whole time limit (WithoutSolution::kTraces).
        const Deadline abandonAt =
            withoutSolution_ == WithoutSolution::kTraces ? context.deadline : std::nullopt;
        solver->solve(&progress, solveDeadline(context, optional),
                      optional ? LinkRefiner::OnTimeUp::Abandon : LinkRefiner::OnTimeUp::Coarsen,
                      abandonAt);
        const bool abandoned = solver->abandoned();
        if (transfers_ && (context.contents.specular || !meshing.spreadSharpGlossy) && !abandoned &&
            !deadlinePassed(context.deadline))
            transferThroughSpecular(context.scene, *mesh_, *solver,
                                    {transferPhotons(*mesh_), context.settings.seed,
                                     shareOfTimeLeft(context, kTransferShare)},
                                    context.settings.quiet, progress);
        if (!abandoned && !deadlinePassed(context.deadline))
            solver->showIndirectAtCorners(&progress, cornerDeadline(context, view_));
        solution_ = std::move(solver);
        if (abandoned)
            return;  // no product: the correcting pass after traces every path on
    } else {
        const auto& progressive = std::get<ProgressiveSettings>(settings_);
        mesh(progressive.meshing(context.scene));
        auto solver =
            std::make_unique<ProgressiveSolver>(context.scene, *mesh_, progressive, &progress);
        solver->solve(&progress);
        solution_ = std::move(solver);
    }
    // The solution refers to the mesh: the product keeps both alive for the passes after.
    context.publish<RadiositySolution>(
        products::kRadiositySolution,
        std::shared_ptr<const RadiositySolution>(mesh_, solution_.get()));
    if (view_)
        SamplingPass::prepare(context);
}

RadianceEstimator RadiosityPass::makeEstimator(PassContext&) {
    return [this](const Ray& ray, Sampler&, FirstHit* firstHit, PathCounters& counters) {
        return Li(ray, firstHit, counters);
    };
}

PathRadiance RadiosityPass::Li(Ray ray, FirstHit* firstHit, PathCounters& counters) const {
    const Vec3 cameraOrigin = ray.o;
    Color escaped(0.0f);
    const std::optional<MeshedHit> seen =
        firstMeshedHit(*scene_, *mesh_, ray, counters.rays, &escaped);
    if (!seen) {
        // The environment seen directly (or through thin glass): the light path L E.
        PathRadiance L;
        if (scene_->environment())
            L[PathComponent::Emission] = escaped * scene_->escaped(ray.d);
        return L;
    }
    const SurfaceHit& hit = seen->hit;
    if (firstHit && !firstHit->valid)
        recordFirstHit(*scene_, hit, scene_->bsdf(hit), cameraOrigin, firstHit);
    // The solution's split: its indirect part (L D D+) and the first reflection of the sources
    // (L D) make up the reflected radiance.
    const Color total =
        solution_->radiance(hit.mesh, hit.triangle, hit.barycentric, true, seen->front);
    const Color reflected =
        solution_->radiance(hit.mesh, hit.triangle, hit.barycentric, false, seen->front);
    const Color indirect =
        solution_->indirectRadiance(hit.mesh, hit.triangle, hit.barycentric, seen->front);
    const Color& beta = seen->transmittance;
    PathRadiance L;
    L[PathComponent::Emission] = beta * (total - reflected);
    L[PathComponent::Direct] = beta * (reflected - indirect);
    L[PathComponent::Indirect] = beta * indirect;
    return L;
}

bool RadiosityPass::run(PassContext& context) {
    return !view_ || SamplingPass::run(context);
}

PassStats RadiosityPass::stats() const {
    PassStats stats = parameters();
    for (const auto& entry : solution_->stats())
        stats.push_back(entry);
    if (!view_)
        return stats;
    // The image's own figures keep their names (every image has them); the view's time and rays
    // are told from the solver's.
    for (const auto& [key, value] : samplingFigures()) {
        const bool ofTheImage = key == "spp" || key == "dropped_samples";
        stats.push_back({ofTheImage ? key : "view " + key, value});
    }
    return stats;
}

PassStats RadiosityPass::parameters() const {
    // Before prepare() (penumbra plan) the sizes that depend on the scene are not resolved yet.
    ParameterPrinter print;
    if (const auto* h = std::get_if<RadiositySettings>(&settings_)) {
        RadiositySettings shown = solvedSettings(*h);
        if (scene_) {
            const MeshingSettings meshing = h->meshing(*scene_);
            shown.patchEdgeLength = meshing.patchEdgeLength;
            shown.minElementArea = meshing.minElementArea;
        }
        print("solver", shown.solver);
        print.choice("caustics", caustics_, kCausticsModes);
        print.choice("specular_transfer", transfer_, kTransferModes);
        print.orAuto("transfer_photons", transferPhotons_, kAutoTransferPhotons);
        hierarchicalKeys(shown, print);
        PassStats stats = print.stats();
        // What "auto" means for this pipeline.
        for (auto& [key, value] : stats) {
            if (key == "caustics" && caustics_ == Caustics::Auto)
                value += takesCaustics_ ? " (the photons of the caustic pass before, if it runs)"
                                        : " (no caustic map before)";
            if (key == "specular_transfer" && transfer_ == Transfer::Auto)
                value += transfers_ ? " (if the scene has specular or sharp glossy surfaces)"
                                    : " (off: the path pass traces that light itself)";
            if (key == "transfer_photons" && transferPhotons_ == kAutoTransferPhotons && mesh_)
                value += " (" + std::to_string(transferPhotons(*mesh_)) + ")";
        }
        return stats;
    }
    ProgressiveSettings shown = std::get<ProgressiveSettings>(settings_);
    if (scene_)
        shown.patchEdgeLength = shown.meshing(*scene_).patchEdgeLength;
    print("solver", std::string("progressive"));
    progressiveKeys(shown, print);
    return print.stats();
}

}  // namespace penumbra
