// The hierarchical radiosity solver against a dense full-matrix solve of the same leaves and
// against closed forms (a point light over a floor, the direct light of an emitting floor on the
// ceiling); subdivision at a hard shadow boundary; its stats, the stages it reports to a progress
// sink and the console's lines of them; the settings it refuses.
#include "core/errors.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "radiosity/solve_progress.h"
#include "tests/support/full_matrix_solve.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::test {
namespace {

// --- Against a dense solve -----------------------------------------------------------------------

TEST(HierarchicalRadiosity, AgreesWithFullMatrixSolve) {
    // A room with a ceiling light, and a red block casting shadows: the hierarchical solution
    // against Gauss-Seidel on the full matrix over the same leaves (every pair of leaf sides linked
    // directly, with the same form factors and the same visibility sampling).
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.7f)});
    addClosedBox(builder, white, white);
    const int red = builder.addMaterial({.baseColor = Color(0.7f, 0.2f, 0.1f)});
    addFloorBlock(builder, red);  // 0.8 x 0.6 x 0.8, faces outward, no bottom
    addCeilingLight(builder, 0.3f, 0.99f, 20.0f);
    const auto scene = loadBuiltScene(builder, "radiosity-full-matrix");

    RadiositySettings settings;
    settings.minElementArea = 0.01f;  // about 1000 leaves: the dense solve stays fast
    settings.epsilon = 1e-3f;
    // The links' solution against the dense solve of the same kernel: the final gather replaces
    // the links' transfer by the rays' (with it, the means agree within 0.2 %, one patch side
    // within 5 %).
    settings.finalGatherRays = 0;
    // The solve's leaves, not those the shown direct light and the refinement at creases split
    // after it (four times as many: the dense solve over them takes minutes).
    settings.directAtCorners = false;
    settings.indirectAtCorners = 0;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    ASSERT_TRUE(solver.converged());
    const std::vector<Color> full = solveFullMatrix(solver, mesh);

    // The reflected light (emission is the same in both by construction), in luminance, per leaf
    // side and summed per patch side.
    struct Sums {
        double hierarchical = 0.0, full = 0.0, area = 0.0;
    };
    Sums total;
    std::vector<Sums> patches(2 * mesh.patchCount());
    std::vector<std::pair<double, double>> leaves;  // (hierarchical, full) per leaf side
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element))
            continue;
        for (const bool front : {true, false}) {
            const Color Le = front ? mesh.Le(element) : Color(0.0f);
            const Color h = solver.elementRadiance(element, front) - Le;
            const Color f = full[2 * e + (front ? 0 : 1)] - Le;
            ASSERT_TRUE(validRadiance(h));
            ASSERT_TRUE(validRadiance(f));
            const double area = mesh.area(element);
            for (Sums* s : {&total, &patches[2 * mesh.patch(element) + (front ? 0 : 1)]}) {
                s->hierarchical += area * luminance(h);
                s->full += area * luminance(f);
                s->area += area;
            }
            leaves.emplace_back(luminance(h), luminance(f));
        }
    }
    const double mean = total.full / total.area;
    double worstPatch = 0.0, worstLeaf = 0.0, meanLeaf = 0.0;
    for (const Sums& p : patches) {
        // Patch sides that receive light at all (not the backs of walls and block faces).
        if (p.full > 0.1 * mean * p.area)
            worstPatch = std::max(worstPatch, std::abs(p.hierarchical / p.full - 1.0));
    }
    for (const auto& [h, f] : leaves) {
        worstLeaf = std::max(worstLeaf, std::abs(h - f) / mean);
        meanLeaf += std::abs(h - f) / mean / static_cast<double>(leaves.size());
    }
    std::cout << leaves.size() / 2 << " leaves, " << solver.linkCount()
              << " links; reflected radiance: mean " << total.hierarchical / total.area
              << " (full matrix " << mean << "); largest relative difference of a lit patch side "
              << worstPatch << "; difference of a leaf side, in units of the mean: average "
              << meanLeaf << ", largest " << worstLeaf << "\n";
    EXPECT_NEAR(total.hierarchical / total.full, 1.0, 0.01);
    EXPECT_LT(worstPatch, 0.01);
    EXPECT_LT(meanLeaf, 0.01);
    // A single leaf side differs more where a coarse link in a penumbra estimates its visible
    // fraction with 16 rays for the whole pair, the dense solve with 16 per leaf pair; and most
    // (measured up to 0.095, under 0.06 elsewhere) at the ceiling leaves straddling the foot of
    // the lamp, which hangs 1 cm under it (one-sided: the ceiling over it is covered, isCovered in
    // element_sampling.h): their value is that of their exposed strip beside the lamp, which the
    // hierarchical solution lights through links at their parents, shared one level down by the
    // children's own visible fractions (setReceiverWeights), the dense solve through each leaf's
    // own links. Hence 0.1.
    EXPECT_LT(worstLeaf, 0.1);
}

// --- Punctual lights -----------------------------------------------------------------------------

TEST(HierarchicalRadiosity, PointLightShootsIntoTheFloor) {
    // A point light of I candela at height h over a 4 x 4 m floor, nothing else: the floor's
    // reflected radiance integrates to rho I Omega / pi, Omega the solid angle of the floor seen
    // from the light, and directly below the light L = rho I / (pi h^2).
    const PointLightOverFloor setup;  // I = 10 cd at 1 m over 4 x 4 m, rho 0.5
    GltfBuilder builder;
    setup.build(builder);
    const auto scene = loadBuiltScene(builder, "radiosity-point-light");
    RadiositySettings settings;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();

    double power = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (mesh.isLeaf(element)) {
            power += mesh.area(element) * solver.elementRadiance(element, true).g;
            EXPECT_EQ(solver.elementRadiance(element, false), Color(0.0f));
            // One plane and a point light: all of its light is the light's first reflection.
            EXPECT_EQ(solver.elementIndirect(element, true), Color(0.0f));
            EXPECT_EQ(solver.elementDirect(element, true), solver.elementRadiance(element, true));
        }
    }
    const double expectedPower = setup.reflectedPower();
    EXPECT_NEAR(power, expectedPower, 0.01 * expectedPower);
    const double below = setup.rho * setup.intensity / (kPi * setup.height * setup.height);
    const Color centre = solver.radiance(0, 0, Vec3(0.5f, 0.0f, 0.5f), true);
    std::cout << "floor: " << mesh.leafCount() << " leaves; reflected power " << power << " (exact "
              << expectedPower << "), below the light " << centre.g << " (exact " << below << ")\n";
    // The interpolated value under the peak of the cos^3 falloff is an average over the
    // elements around it, so slightly low: 3 %.
    EXPECT_NEAR(centre.g, below, 0.03 * below);
}

// --- The indirect-only solution ------------------------------------------------------------------

TEST(HierarchicalRadiosity, AllMinusIndirectIsTheDirectLightOfTheSources) {
    // A closed box whose floor alone emits: the ceiling's direct light, rho Le F(x -> floor), is
    // in closed form (EmittingFloorBox). What the solution holds beyond its indirect part,
    // All - Indirect, must be that light: per ceiling leaf (against F averaged over the leaf by
    // the seven-point rule of degree 3) and at points of the ceiling (the Gouraud-interpolated
    // values against the point value). Over the whole box, the direct light reflected is rho
    // times the floor's emitted flux, sum_i A_i direct_i = rho Le A_floor (the floor's form factors
    // to the rest of the closed box sum to 1), and the floor, which sees none of itself, has none.
    const EmittingFloorBox box;
    const auto scene = box.load("radiosity-emitting-floor");
    RadiositySettings settings;
    settings.minElementArea = 0.5f / 64.0f;
    settings.epsilon = 1e-3f;
    // The leaves that the refinement at creases adds after the solve for the indirect light at
    // the corners (crease_refinement.h) keep their parent's values: the solve's leaves are
    // what is tested here.
    settings.indirectAtCorners = 0;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    ASSERT_TRUE(solver.converged());

    double worstLeaf = 0.0, directFlux = 0.0, floorDirect = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element))
            continue;
        const Color all = solver.elementRadiance(element, true) - mesh.Le(element);
        const Color direct = all - solver.elementIndirect(element, true);
        directFlux += mesh.area(element) * direct.g;
        // The floor faces up, the ceiling down (a wall's leaves along its edges lie as low or
        // as high).
        if (mesh.normal(element).y > 0.99f)
            floorDirect = std::max(floorDirect, static_cast<double>(maxComponent(direct)));
        if (mesh.normal(element).y > -0.99f)
            continue;
        const auto c = mesh.corners(element);
        const auto at = [&](const Vec3& p) { return box.ceilingDirect(p.x, p.z); };
        const double expected =
            (at(c[0]) + at(c[1]) + at(c[2])) / 20.0 +
            (at(0.5f * (c[0] + c[1])) + at(0.5f * (c[1] + c[2])) + at(0.5f * (c[2] + c[0]))) *
                (2.0 / 15.0) +
            at(mesh.centroid(element)) * (9.0 / 20.0);
        worstLeaf = std::max(worstLeaf, std::abs(direct.g / expected - 1.0));
    }
    // All - Indirect, interpolated, at points of the ceiling.
    const double worstPoint = box.worstCeilingPoint(*scene, [&](uint32_t m, uint32_t t, Vec3 b) {
        return solver.radiance(m, t, b, false) - solver.indirectRadiance(m, t, b);
    });
    const double expectedFlux = box.rho * box.Le * 4.0 * box.h * box.h;
    std::cout << mesh.leafCount() << " leaves; direct part on the ceiling: largest relative error "
              << worstLeaf << " per leaf, " << worstPoint << " interpolated; direct flux / pi "
              << directFlux << " (exact " << expectedFlux << "); on the floor at most "
              << floorDirect << "\n";
    EXPECT_LT(worstLeaf, 0.01);
    EXPECT_LT(worstPoint, 0.02);
    EXPECT_NEAR(directFlux, expectedFlux, 0.01 * expectedFlux);
    EXPECT_LT(floorDirect, 1e-6);
}

// --- Subdivision ---------------------------------------------------------------------------------

// The area of the floor leaf (y = -1, facing up) whose projection holds the point (x, z).
float floorLeafArea(const RadiosityMesh& mesh, float x, float z) {
    const auto side = [](Vec2 p, Vec2 a, Vec2 b) {
        return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    };
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element) || mesh.normal(element).y < 0.9f ||
            mesh.centroid(element).y > -0.99f)
            continue;
        const auto c = mesh.corners(element);
        const Vec2 p(x, z), a(c[0].x, c[0].z), b(c[1].x, c[1].z), d(c[2].x, c[2].z);
        const float s0 = side(p, a, b), s1 = side(p, b, d), s2 = side(p, d, a);
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0))
            return mesh.area(element);
    }
    return 0.0f;
}

TEST(HierarchicalRadiosity, SubdivisionRefinesAHardShadowBoundary) {
    // A small bright ceiling light (0.1 m square) over the block of AgreesWithFullMatrixSolve: the
    // block's top edge at x = -0.6 casts a hard shadow boundary on the floor at
    // x = -0.6 * 1.99 / 1.39 = -0.859 (from the light's centre at y = 0.99). The oracle is made
    // coarse (epsilon 0.5, no refinement rounds: every floor leaf stays a 0.5 m² patch), so that
    // what refines the floor is subdivision alone. With subdivision_threshold 0.2 the leaf on the
    // boundary must end up finer than without, and finer than the leaf at the mirror point
    // x = +0.859, lit without occlusion, where only the smooth falloff of the light varies
    // (measured: 0.5 m² -> 0.002 m², the smallest element, on the boundary; 0.008 m² in the light).
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.7f)});
    addClosedBox(builder, white, white);
    addFloorBlock(builder, white);
    addCeilingLight(builder, 0.05f, 0.99f, 500.0f);
    const auto scene = loadBuiltScene(builder, "radiosity-subdivision");
    const auto solveWith = [&](float threshold, float& boundary, float& lit) {
        RadiositySettings settings;
        settings.epsilon = 0.5f;  // a coarse oracle, to leave the boundary to subdivision
        settings.subdivisionThreshold = threshold;
        settings.maxRefinements = 0;
        // What the solve's subdivision does, not the refinement of the shown direct light after
        // it (which splits the boundary's leaves too: light_driven_meshing_test.cpp).
        settings.directAtCorners = false;
        RadiosityMesh mesh(*scene, settings.meshing(*scene));
        RadiositySolver solver(*scene, mesh, settings);
        solver.solve();
        EXPECT_TRUE(solver.converged());
        boundary = floorLeafArea(mesh, -0.859f, 0.2f);
        lit = floorLeafArea(mesh, 0.859f, 0.2f);
        return mesh.leafCount();
    };
    float offBoundary = 0, offLit = 0, onBoundary = 0, onLit = 0;
    const size_t offLeaves = solveWith(0.0f, offBoundary, offLit);
    const size_t onLeaves = solveWith(0.2f, onBoundary, onLit);
    std::cout << "leaves " << offLeaves << " -> " << onLeaves << "; leaf area on the boundary "
              << offBoundary << " -> " << onBoundary << ", in the light " << offLit << " -> "
              << onLit << "\n";
    ASSERT_GT(onBoundary, 0.0f);
    ASSERT_GT(onLit, 0.0f);
    EXPECT_GT(onLeaves, offLeaves);
    EXPECT_LT(onBoundary, offBoundary);
    EXPECT_LT(onBoundary, onLit);
}

// --- Stats, progress and settings ----------------------------------------------------------------

TEST(HierarchicalRadiosity, StatsReportPeakMemoryPerStage) {
    // getrusage's ru_maxrss after each stage: a running maximum, so it never falls from one stage
    // to the next, and the process holds at least the solver's own estimate of its arrays.
    const auto scene = furnaceBox(0.5f, "radiosity-stats");
    RadiositySettings settings;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    solver.solve();
    std::map<std::string, double> stats;
    for (const auto& [key, value] : solver.stats()) {
        // "yes" or "no"; every other figure is a number
        if (key != "converged" && key != "refinement_stopped_by_time_limit" &&
            key != "abandoned_by_time_limit" && key != "direct_at_corners_budget_reached" &&
            key != "direct_at_corners_stopped_by_time_limit" && key != "crease_budget_reached")
            stats[key] = std::stod(value);
    }
    const std::vector<std::string> stages = {"direct", "linking", "refine", "solve"};
    double previous = 0.0;
    for (const std::string& stage : stages) {
        const std::string key = "peak_memory_mib_" + stage;
        ASSERT_TRUE(stats.count(key)) << key;
        EXPECT_GE(stats[key], previous) << key;
        previous = stats[key];
    }
    EXPECT_GE(stats["peak_memory_mib_solve"], stats["memory_mib"]);
    EXPECT_EQ(stats["clusters"], 0.0);  // 48 patches: under clusterMinPatches
}

TEST(HierarchicalRadiosity, ReportsItsStagesToTheProgressSink) {
    // A closed room with a ceiling light and a point light: every stage is reported, in order,
    // each ended with its figures; the stages of known length are advanced by exactly their
    // total (the bar reaches 100 %), and the gathers, which converge, reach theirs too.
    GltfBuilder builder;
    const int white = builder.addMaterial({.baseColor = Color(0.6f)});
    addClosedBox(builder, white, white);
    addCeilingLight(builder, 0.3f, 0.99f, 20.0f);
    builder.addLight({.type = "point", .intensity = 1.0f, .position = {0.5f, 0.5f, 0.0f}});
    const auto scene = loadBuiltScene(builder, "radiosity-progress");
    RadiositySettings settings;
    settings.minElementArea = 0.5f / 16.0f;
    settings.finalGatherRays = 16;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings);
    RecordedProgress progress;
    solver.solve(&progress);
    ASSERT_TRUE(solver.converged());

    std::vector<std::string> expected = {
        "exposed parts of the elements", "direct light of the punctual lights",
        "linking: refinement oracle", "linking: form factors and visibility", "gather"};
    ASSERT_GE(progress.stages.size(), expected.size() + 2);
    for (size_t i = 0; i < expected.size(); ++i)
        EXPECT_EQ(progress.stages[i].name, expected[i]);
    // Then the final gather's passes, two stages each (its rays, then the sweeps), the direct
    // light at the corners (its first evaluation, then a stage per round of splits), and last a
    // stage per round of the refinement at creases (the room's twelve edges).
    int passes = -1;
    for (const auto& [key, value] : solver.stats()) {
        if (key == "final_gather_passes")
            passes = std::stoi(value);
    }
    ASSERT_GE(passes, 1);
    // The number of stages, counted back from `end` stages before the last, whose names begin
    // with `name`.
    const auto stagesBefore = [&](size_t end, const std::string& name) {
        size_t count = 0;
        while (end + count < progress.stages.size() &&
               progress.stages[progress.stages.size() - 1 - end - count].name.rfind(name, 0) == 0)
            ++count;
        return count;
    };
    const std::string creases = "refinement at creases, round ";
    const size_t creaseStages = stagesBefore(0, creases);
    ASSERT_GE(creaseStages, 1u);
    EXPECT_EQ(progress.stages[progress.stages.size() - creaseStages].name, creases + "1");
    const std::string corners = "direct light at the corners";
    const size_t cornerStages = stagesBefore(creaseStages, corners);
    ASSERT_GE(cornerStages, 1u);
    EXPECT_EQ(progress.stages[progress.stages.size() - creaseStages - cornerStages].name, corners);
    const size_t last =
        progress.stages.size() - 1 - cornerStages - creaseStages - 2 * static_cast<size_t>(passes);
    EXPECT_EQ(progress.stages[last - 1].name, "gather to convergence");
    EXPECT_EQ(progress.stages[last].name, "push-pull of the direct part, vertex values");
    for (int pass = 1; pass <= passes; ++pass) {
        const std::string name = "final gather " + std::to_string(pass);
        EXPECT_EQ(progress.stages[last + 2 * pass - 1].name, name + ": rays");
        EXPECT_EQ(progress.stages[last + 2 * pass].name, name + ": gather");
    }
    int gathers = 0;
    for (const RecordedProgress::Stage& stage : progress.stages) {
        std::cout << stage.name << ": " << stage.done << " of " << stage.total << ", "
                  << stage.summary << "\n";
        EXPECT_TRUE(stage.ended) << stage.name;
        EXPECT_FALSE(stage.summary.empty()) << stage.name;
        if (stage.total > 0) {
            EXPECT_EQ(stage.done, stage.total) << stage.name;
        }
        gathers += stage.name.rfind("gather", 0) == 0;
    }
    // A gather after the first links, one per refinement round, and the last.
    int rounds = -1;
    for (const auto& [key, value] : solver.stats()) {
        if (key == "refinement_rounds")
            rounds = std::stoi(value);
    }
    EXPECT_EQ(gathers, 2 + rounds);
    // The oracle's stages count the pairs they examine; the direct light the first leaves, the
    // patches.
    EXPECT_GT(progress.find("linking: refinement oracle")->done, 0u);
    EXPECT_EQ(progress.find("direct light")->total, mesh.patchCount());
}

TEST(ConsoleSolveProgress, PrintsALinePerStageInALogAndNothingWhenQuiet) {
    // Not a terminal (a temporary file): one line per stage, its name, figures and time; with
    // quiet, nothing at all.
    for (const bool quiet : {false, true}) {
        std::FILE* log = std::tmpfile();
        ASSERT_NE(log, nullptr);
        {
            ConsoleSolveProgress progress("radiosity", quiet, log);
            progress.beginStage("linking", 100);
            progress.advance(60);
            progress.advance(40);
            progress.endStage("12 links");
            progress.beginStage("oracle", 0);
            progress.advance(5);
            progress.beginStage("gather", 1000);  // ends "oracle" without figures
        }                                         // the destructor ends "gather"
        std::rewind(log);
        std::string text;
        for (int c = std::fgetc(log); c != EOF; c = std::fgetc(log))
            text.push_back(static_cast<char>(c));
        std::fclose(log);
        if (quiet) {
            EXPECT_EQ(text, "");
            continue;
        }
        std::vector<std::string> lines;
        for (size_t start = 0, end; (end = text.find('\n', start)) != std::string::npos;
             start = end + 1)
            lines.push_back(text.substr(start, end - start));
        ASSERT_EQ(lines.size(), 3u) << text;
        EXPECT_EQ(lines[0].rfind("radiosity: linking: 12 links, ", 0), 0u) << lines[0];
        EXPECT_EQ(lines[1].rfind("radiosity: oracle: ", 0), 0u) << lines[1];
        EXPECT_EQ(lines[2].rfind("radiosity: gather: ", 0), 0u) << lines[2];
        for (const std::string& line : lines)
            EXPECT_EQ(line.substr(line.size() - 2), " s") << line;
    }
}

TEST(HierarchicalRadiosity, RefusesBadSettings) {
    RadiositySettings s;
    s.epsilon = 0.0f;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.solver = "progressive";
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.visibilitySamples = 0;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.clusterMinPatches = -1;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
    s = RadiositySettings{};
    s.subdivisionThreshold = -0.1f;
    EXPECT_THROW(validateRadiositySettings(s), UsageError);
}

}  // namespace
}  // namespace penumbra::test
