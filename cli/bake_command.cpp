// `penumbra bake SCENE -o lit.glb`: solves radiosity on a scene (with the lights' caustic photons
// and its light carried through specular surfaces, passes/specular_transfer.h) and writes the
// refined mesh with the solution as unlit vertex colours (radiosity/bake.h), for walkthroughs in
// any glTF viewer.
#include "caustics/photon_tracer.h"
#include "cli/commands.h"
#include "cli/scene_input.h"
#include "core/errors.h"
#include "core/gltf_writer.h"
#include "core/progress.h"
#include "core/scene_contents.h"
#include "core/stats.h"
#include "passes/caustic_pass.h"
#include "passes/solution_check.h"
#include "passes/specular_transfer.h"
#include "radiosity/bake.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "radiosity/solve_progress.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

namespace penumbra::cli {

namespace {

struct BakeOptions {
    SceneInput scene;
    std::string output;
    std::optional<float> exposure;  // EV; none = automatic
    int threads = 0;
    RadiositySettings radiosity;
    bool caustics = true;          // take the lights' caustic photons into the solution
    bool specularTransfer = true;  // carry the solution's light through specular surfaces
    uint32_t seed = 0;             // of the photons and of the check
    SolutionCheckSettings check;   // points 0: no check
};

// The bake's expected error: the solution against the path tracer at points of its surfaces.
void reportExpectedError(const Scene& scene, const RadiosityMesh& mesh,
                         const RadiositySolution& solution, SolutionCheckSettings settings) {
    SolutionCheck check;
    {
        Progress progress("check", uint64_t(settings.points), false);
        check = checkSolution(scene, mesh, solution, settings, &progress);
    }
    if (!(check.meanTraced > 0.0)) {
        std::cerr << "penumbra: expected error: none measured (the path tracer found no light "
                     "at the "
                  << settings.points << " points checked)\n";
        return;
    }
    const auto percent = [](double fraction) {
        std::ostringstream out;
        out << std::fixed << std::setprecision(1) << 100.0 * fraction << " %";
        return out.str();
    };
    std::cerr << "penumbra: expected error, at " << check.points.size()
              << " points drawn over the baked surfaces against the path tracer ("
              << settings.samples << " samples each): mean " << (check.bias >= 0.0 ? "+" : "")
              << percent(check.bias) << " +- " << percent(check.biasStandardError)
              << " of the mean radiance (" << check.meanTraced << " cd/m²), RMS ";
    if (check.rmsError >= check.noise) {
        std::cerr << percent(check.rmsError) << " (the path tracer's own noise, "
                  << percent(check.noise) << ", taken out)\n";
    } else {
        std::cerr << "under " << percent(check.noise)
                  << " (the path tracer's own noise: more --check-samples resolve it)\n";
    }
}

void bake(const BakeOptions& options) {
    // Refuse a bad output or setting before loading and solving.
    checkGltfOutputPath(options.output);
    validateRadiositySettings(options.radiosity);
    const bool quiet = options.scene.quiet;

    const auto start = std::chrono::steady_clock::now();
    const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
    tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, threads);
    const std::unique_ptr<Scene> scene = loadScene(options.scene);
    RadiosityMesh mesh(*scene, options.radiosity.meshing(*scene));
    if (mesh.patchCount() == 0) {
        throw UsageError(options.scene.path +
                         ": nothing to bake: the scene has no opaque triangles (transmissive "
                         "surfaces are left to the ray tracer)");
    }
    if (!quiet)
        std::cerr << "penumbra: solving radiosity on " << mesh.patchCount() << " patches\n";
    const bool specular = analyseScene(*scene).specular;
    // The lights' light through mirrors and glass (L S+ D), binned on the elements as the
    // radiosity pass takes a caustic pass's photons (radiosity/deposited_flux.h).
    std::vector<FluxDeposit> caustics;
    if (options.caustics && specular) {
        PhotonTracerSettings photons;
        // The caustic pass's base count: its automatic count grows with the image's samples,
        // which a bake has none of.
        photons.photons = CausticPass::kBasePhotons;
        photons.seed = options.seed;
        Progress progress("caustic photons", CausticPass::kBasePhotons, quiet);
        caustics = asDeposits(tracePhotons(*scene, photons, &progress).photons);
    }
    RadiositySolver solver(*scene, mesh, options.radiosity, caustics);
    ConsoleSolveProgress solveProgress("radiosity", quiet);
    solver.solve(&solveProgress);
    if (options.specularTransfer && specular) {
        transferThroughSpecular(*scene, mesh, solver,
                                {automaticTransferPhotons(mesh), options.seed, std::nullopt}, quiet,
                                solveProgress);
    }
    solver.showIndirectAtCorners(&solveProgress);
    const double solveSeconds = secondsSince(start);

    BakeResult result;
    {
        Progress progress("bake", mesh.leafCount(), quiet);
        result = bakeRadiosity(
            *scene, mesh,
            [&solver](int leaf, size_t corner) {
                return solver.cornerRadiance(leaf, corner, true);
            },
            options.exposure, &progress);
    }
    const size_t bytes = writeGltf(options.output, result.model);
    if (quiet)
        return;

    std::cerr << "penumbra: wrote " << options.output << " (" << bytes / 1024
              << " KiB): " << result.model.meshes.size() << " meshes, " << mesh.elementCount()
              << " elements (" << result.leaves << " leaves), " << result.vertices << " vertices, "
              << result.triangles << " triangles\n";
    std::cerr << "penumbra: exposure " << result.exposure << " EV";
    if (result.automaticExposure) {
        std::cerr << " (automatic: " << result.exposureRadiance
                  << " cd/m², the 99th percentile of the lit surfaces' radiance, maps to 1; "
                     "set --exposure to change it)";
    }
    std::cerr << "\npenumbra: " << secondsSince(start) << " s (radiosity " << solveSeconds
              << " s)\n";
    for (const auto& [key, value] : solver.stats())
        std::cerr << "  radiosity " << key << ": " << value << "\n";
    if (!solver.converged()) {
        std::cerr << "penumbra: warning: the radiosity iteration stopped before converging "
                     "(max_iterations)\n";
    }
    if (options.check.points > 0) {
        SolutionCheckSettings check = options.check;
        check.seed = options.seed;
        reportExpectedError(*scene, mesh, solver, check);
    }
}

}  // namespace

Command addBakeCommand(CLI::App& app) {
    auto* command = app.add_subcommand(
        "bake",
        "Solve radiosity and write the lit mesh as a glTF model with vertex colours "
        "(KHR_materials_unlit) for walkthroughs in any glTF viewer");
    auto options = std::make_shared<BakeOptions>();
    RadiositySettings& r = options->radiosity;
    addSceneInputOptions(*command, options->scene, PassScripts::Refused);
    command->add_option("-o,--output", options->output, "Output model: .glb or .gltf")->required();
    command->add_option("--exposure", options->exposure,
                        "Multiply the radiance (cd/m²) by 2^EV before baking (default: "
                        "automatic, the 99th percentile of the lit surfaces maps to 1)");
    command->add_option("--threads", options->threads, "Worker threads (default: all cores)")
        ->check(atLeast(0));
    command
        ->add_option("--epsilon", r.epsilon,
                     "Radiosity refinement threshold relative to the mean radiance; smaller "
                     "is finer and slower")
        ->capture_default_str();
    command->add_option("--patch-edge-length", r.patchEdgeLength,
                        "Longest patch edge in metres (default 0: the scene's bounding radius)");
    command->add_option("--min-element-area", r.minElementArea,
                        "Smallest element in m² (default 0: total surface area / 16384)");
    command
        ->add_flag("--contact-lines", r.contactLines,
                   "Cut the surfaces along the lines where others stand on them (a block on a "
                   "floor) before meshing, so that no element straddles one")
        ->capture_default_str();
    command
        ->add_flag("--shadow-lines,!--no-shadow-lines", r.shadowLines,
                   "Cut the surfaces along the shadow boundaries of point lights, luminaires and "
                   "the sun before meshing, so that hard shadows have sharp edges (on by "
                   "default; --no-shadow-lines leaves them to the refinement)")
        ->capture_default_str();
    command
        ->add_flag("!--no-direct-at-corners", r.directAtCorners,
                   "Show the lights' direct light as the element means, not as evaluated at the "
                   "corners of elements refined until it is right")
        ->capture_default_str();
    command
        ->add_option("--indirect-at-corners", r.indirectAtCorners,
                     "Rays per element corner that gather the indirect light shown there "
                     "(0: the element means)")
        ->check(CLI::Range(0, RadiositySettings::kMaxIndirectAtCornersRays))
        ->capture_default_str();
    command
        ->add_flag("!--no-caustics", options->caustics,
                   "Leave out the light that reaches surfaces from the lights through mirrors "
                   "and glass (caustic photons, binned on the elements)")
        ->capture_default_str();
    command
        ->add_flag("!--no-specular-transfer", options->specularTransfer,
                   "Leave out the light the solution's surfaces send through mirrors and glass "
                   "onto other surfaces (photons shot from the solution, then solved again)")
        ->capture_default_str();
    command
        ->add_option("--seed", options->seed,
                     "Seed of the caustic and transfer photons and of the expected error's check")
        ->capture_default_str();
    command
        ->add_option("--check-points", options->check.points,
                     "Points drawn over the baked surfaces at which the solution is checked "
                     "against the path tracer, to report the bake's expected error; 0 = no check")
        ->capture_default_str()
        ->check(atLeast(0));
    command
        ->add_option("--check-samples", options->check.samples,
                     "Path-traced samples per checked point")
        ->capture_default_str()
        ->check(atLeast(2));
    return [options] { bake(*options); };
}

}  // namespace penumbra::cli
