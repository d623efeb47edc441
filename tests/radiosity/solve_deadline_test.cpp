// The hierarchical solver under a time limit (RadiositySolver::solve's deadline): a solve whose
// time is up before it starts still ends with a whole solution, coarser, that keeps the closed
// furnace's answer; told to abandon, it stops without links; and the hybrid pipeline whose solve
// is abandoned renders the path tracer's very image, every path traced on, as does the
// distribution preview whose solve could not end within the time limit; the rate of a stage's
// work says early whether it will end in time, so that the element exposure or the direct light
// gives the solve up within the stage; a solve nothing replaces (the radiosity view) hurries its
// direct light instead.
#include "core/image_io.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "radiosity/solve_progress.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <string>

namespace penumbra::test {
namespace {

// A deadline that has passed before the solve begins.
Deadline past() {
    return std::chrono::steady_clock::now() - std::chrono::seconds(1);
}

// Fine enough that, with time, the links go three levels below the furnace's patches.
RadiositySettings fineSettings() {
    RadiositySettings s;
    s.minElementArea = 0.5f / 64.0f;
    s.epsilon = 5e-4f;
    s.finalGatherRays = 0;
    return s;
}

// The area-weighted mean front radiance of the leaves, over the closed form Le / (1 - rho).
double furnaceMeanRatio(const RadiositySolver& solver, const RadiosityMesh& mesh, double rho) {
    double weighted = 0.0, area = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element))
            continue;
        weighted += mesh.area(element) * solver.elementRadiance(element, true).g;
        area += mesh.area(element);
    }
    return weighted / area * (1.0 - rho);
}

std::string stat(const RadiositySolver& solver, const std::string& key) {
    for (const auto& [name, value] : solver.stats()) {
        if (name == key)
            return value;
    }
    return "";
}

TEST(SolveDeadline, PastDeadlineStillGivesAWholeCoarserSolution) {
    const float rho = 0.9f;
    const auto scene = furnaceBox(rho, "solve-deadline-furnace");
    RadiosityMesh fineMesh(*scene, fineSettings().meshing(*scene));
    RadiositySolver fine(*scene, fineMesh, fineSettings());
    fine.solve();

    RadiosityMesh coarseMesh(*scene, fineSettings().meshing(*scene));
    RadiositySolver coarse(*scene, coarseMesh, fineSettings());
    coarse.solve(nullptr, past(), LinkRefiner::OnTimeUp::Coarsen);
    const double ratio = furnaceMeanRatio(coarse, coarseMesh, rho);
    std::cout << "links " << coarse.linkCount() << " with the time up, " << fine.linkCount()
              << " without; mean over Le / (1 - rho) " << ratio << "\n";
    EXPECT_FALSE(coarse.abandoned());
    EXPECT_EQ(stat(coarse, "refinement_stopped_by_time_limit"), "yes");
    EXPECT_EQ(stat(coarse, "refinement_rounds"), "0");
    EXPECT_TRUE(coarse.converged());
    EXPECT_GT(coarse.linkCount(), 0u);
    EXPECT_LT(coarse.linkCount(), fine.linkCount() / 2);
    // Every element still exchanges light with the whole closed box: the mean within 2 % of the
    // closed form (the fine solve's bound, furnace test, is 1 %; the coarse links' form factors
    // are estimated over larger elements, with an error of the same order).
    EXPECT_NEAR(ratio, 1.0, 0.02);
}

TEST(SolveDeadline, AbandonsWithoutLinksWhenTold) {
    const auto scene = furnaceBox(0.5f, "solve-deadline-abandon");
    RadiosityMesh mesh(*scene, fineSettings().meshing(*scene));
    RadiositySolver solver(*scene, mesh, fineSettings());
    solver.solve(nullptr, past(), LinkRefiner::OnTimeUp::Abandon);
    EXPECT_TRUE(solver.abandoned());
    EXPECT_EQ(solver.linkCount(), 0u);
    EXPECT_EQ(stat(solver, "abandoned_by_time_limit"), "yes");
}

TEST(SolveDeadline, TheLinksRateSaysWhetherTheyWillBeMadeInTime) {
    // Half of 1000 links in 1 s: the other half needs about 1 s more.
    EXPECT_TRUE(projectedToOverrun(1.0, 500, 1000, 0.9));
    EXPECT_FALSE(projectedToOverrun(1.0, 500, 1000, 1.1));
    EXPECT_TRUE(projectedToOverrun(0.5, 100, 1000, 4.4));
    EXPECT_FALSE(projectedToOverrun(0.5, 100, 1000, 4.6));
    // No verdict before a twentieth of the links, or a quarter of a second, or once all are made.
    EXPECT_FALSE(projectedToOverrun(1.0, 49, 1000, 0.0));
    EXPECT_TRUE(projectedToOverrun(1.0, 50, 1000, 0.0));
    EXPECT_FALSE(projectedToOverrun(0.2, 500, 1000, 0.0));
    EXPECT_FALSE(projectedToOverrun(1.0, 1000, 1000, -1.0));
    EXPECT_FALSE(projectedToOverrun(1.0, 0, 1000, -1.0));
}

TEST(SolveDeadline, TheRecentPaceLeavesOutASlowStart) {
    // 1000 items, looked at every 10: the first 100 take 2 s, the rest 0.5 s per 100. At 300
    // items (3 s, past a quarter), the pace from the start projects 7 s more; the pace since half
    // of the time (the look at 1.5 s, 75 items: 225 items in 1.5 s) 4.7 s; the truth is 3.5 s.
    const auto secondsAt = [](size_t done) {
        return done <= 100 ? 0.02 * double(done) : 2.0 + 0.005 * double(done - 100);
    };
    RecentPace pace(1000);
    bool overruns = false;
    for (size_t done = 10; done <= 300; done += 10)
        overruns = pace.overruns(secondsAt(done), done, 6.0);
    EXPECT_FALSE(overruns);
    EXPECT_TRUE(projectedToOverrun(secondsAt(300), 300, 1000, 6.0));
    EXPECT_TRUE(pace.overruns(secondsAt(310), 310, 4.0));  // 4.35 s projected
    // Restarted when the work became quicker (at 100 items, 2 s), only the quick pace counts,
    // once a quarter of the 900 items left then are done: at 400 items 3 s projected, at 410
    // 2.95 s; at 300, no verdict yet.
    RecentPace restarted(1000);
    for (size_t done = 10; done <= 400; done += 10) {
        if (done == 100)
            restarted.restart(secondsAt(done), done);
        overruns = restarted.overruns(secondsAt(done), done, done == 300 ? 0.0 : 3.1);
        if (done == 300) {
            EXPECT_FALSE(overruns);
        }
    }
    EXPECT_FALSE(overruns);
    EXPECT_TRUE(restarted.overruns(secondsAt(410), 410, 2.9));
}

TEST(SolveDeadline, HybridWithoutTimeForTheSolveRendersThePathTracersImage) {
    // A time limit far shorter than any solve: the corrected hybrid's radiosity pass abandons
    // its solve and the path pass traces every path on, so that with the same seed its image is
    // the `reference` pipeline's, pixel for pixel (the box has no specular surface, so no caustic
    // pass runs either). A path pass that still stopped at the second diffuse vertex would lose
    // the indirect light, a third of this box's.
    const std::string scene =
        std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box/cornell-box.gltf";
    const std::string options = "--time-limit 0.001 --width 32 --height 32 --threads 2 --seed 3";
    TempDir dir("solve-deadline-hybrid");
    CliResult run;
    const Image hybrid =
        renderImage(scene, dir.file("hybrid.exr"), "--pipeline hybrid " + options, &run);
    EXPECT_NE(run.output.find("abandoned_by_time_limit: yes"), std::string::npos) << run.output;
    const Image traced =
        renderImage(scene, dir.file("reference.exr"), "--pipeline reference " + options);
    ASSERT_EQ(hybrid.pixels().size(), traced.pixels().size());
    size_t differing = 0;
    for (size_t i = 0; i < hybrid.pixels().size(); ++i)
        differing += hybrid.pixels()[i] != traced.pixels()[i];
    EXPECT_EQ(differing, 0u);
    EXPECT_GT(luminanceMean(traced), 0.0);
}

// A grey floor of cells x cells squares of two triangles each, `size` metres across, centred on
// the origin in the plane y = 0, facing up.
void addGridFloor(GltfBuilder& scene, int cells, float size) {
    const int grey = scene.addMaterial({.baseColor = Color(0.5f)});
    std::vector<Vec3> positions;
    std::vector<uint32_t> indices;
    for (int j = 0; j <= cells; ++j)
        for (int i = 0; i <= cells; ++i)
            positions.push_back(
                Vec3((float(i) / cells - 0.5f) * size, 0.0f, (0.5f - float(j) / cells) * size));
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            const uint32_t a = uint32_t(j * (cells + 1) + i), b = a + 1,
                           c = a + uint32_t(cells + 1), d = c + 1;
            indices.insert(indices.end(), {a, b, d, a, d, c});
        }
    }
    scene.addMesh(positions, indices, grey);
}

// A floor of 180 000 triangles, 10 x 10 m, written to `dir` as floor.gltf: under a sky, its
// elements' exposure and their direct light (the solve's first stage) take seconds.
std::string writeManyTriangleFloor(const TempDir& dir) {
    GltfBuilder scene;
    addGridFloor(scene, 300, 10.0f);
    scene.write(dir.file("floor.gltf"));
    return dir.file("floor.gltf");
}

// A floor of 2 048 triangles, 2 x 2 m, under 1 024 point lights 1 m above it, written to `dir`
// as lamps.gltf: its elements' exposure is quick (16 points on each of its 2 048 elements),
// their direct light long (16 points on each, towards each of the 1 024 lamps).
std::string writeFloorUnderManyLamps(const TempDir& dir) {
    GltfBuilder scene;
    addGridFloor(scene, 32, 2.0f);
    constexpr int kLampRows = 32;
    for (int j = 0; j < kLampRows; ++j)
        for (int i = 0; i < kLampRows; ++i)
            scene.addLight({.intensity = 0.01f,
                            .position = {(float(i) + 0.5f) / kLampRows * 2.0f - 1.0f, 1.0f,
                                         (float(j) + 0.5f) / kLampRows * 2.0f - 1.0f}});
    scene.write(dir.file("lamps.gltf"));
    return dir.file("lamps.gltf");
}

TEST(SolveDeadline, TheHybridGivesUpASolveWhoseExposureAloneTakesAThirdOfItsShare) {
    // A second's time limit cannot pay for the exposure of the floor's 180 000 patches: the
    // solve is abandoned within that stage, once a quarter of a second says so (or, on a machine
    // that ends it sooner, within the direct light after it), never in the linking.
    TempDir dir("solve-deadline-exposure");
    CliResult run;
    renderImage(writeManyTriangleFloor(dir), dir.file("floor.exr"),
                "--pipeline hybrid --sky uniform --time-limit 1 --width 8 --height 8 --threads 2",
                &run);
    const bool exposure =
        run.output.find("exposed parts of the elements: abandoned") != std::string::npos;
    const bool direct =
        run.output.find("direct light of the punctual lights: abandoned") != std::string::npos;
    EXPECT_TRUE(exposure || direct) << run.output;
    EXPECT_EQ(run.output.find("linking: refinement oracle"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("abandoned_by_time_limit: yes"), std::string::npos) << run.output;
}

TEST(SolveDeadline, TheHybridGivesUpASolveWhoseDirectLightAloneTakesHalfItsShare) {
    // A second's time limit cannot pay for the direct light of a thousand lamps on the floor:
    // the solve is abandoned within that stage, once a twentieth of it says so, not after it.
    TempDir dir("solve-deadline-direct");
    CliResult run;
    renderImage(writeFloorUnderManyLamps(dir), dir.file("floor.exr"),
                "--pipeline hybrid --time-limit 1 --width 8 --height 8 --threads 2", &run);
    EXPECT_NE(run.output.find("exposed parts of the elements: 2048 elements"), std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("direct light of the punctual lights: abandoned"), std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("abandoned_by_time_limit: yes"), std::string::npos) << run.output;
}

TEST(SolveDeadline, TheRadiosityViewHurriesTheDirectLightItHasNoTimeFor) {
    // Nothing replaces the radiosity view's solution: once the floor's direct light is projected
    // to take half of the solve's share, the rest of the leaves take one point each (on the
    // grey-white room, 21 s of direct light became 1.7 s), and the solve goes on.
    TempDir dir("solve-deadline-hurry");
    CliResult run;
    const Image image =
        renderImage(writeFloorUnderManyLamps(dir), dir.file("floor.exr"),
                    "--pipeline radiosity --time-limit 1 --width 8 --height 8 --threads 2", &run);
    EXPECT_NE(run.output.find("leaves, one point each from leaf"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("abandoned_by_time_limit: no"), std::string::npos) << run.output;
    EXPECT_GT(luminanceMean(image), 0.0);
}

TEST(SolveDeadline, ThePreviewsGiveUpASolveThatCannotEndWithinTheTimeLimit) {
    // The previews take a coarse solution while one can be had within the time limit, and trace
    // without one when it cannot: a second cannot pay for the exposure of 180 000 patches and
    // their direct light (on the grey-white room at 4 s, the coarsest solve took 8.7 s and left
    // one sample per pixel). The distribution pass then path-traces the indirect light, the
    // preview path pass traces every path on.
    TempDir dir("solve-deadline-previews");
    const std::string floor = writeManyTriangleFloor(dir);
    for (const std::string pipeline : {"distribution", "hybrid-preview"}) {
        CliResult run;
        const Image image =
            renderImage(floor, dir.file(pipeline + ".exr"),
                        "--pipeline " + pipeline +
                            " --sky uniform --time-limit 1 --width 8 --height 8 --threads 2",
                        &run);
        EXPECT_NE(run.output.find("abandoned_by_time_limit: yes"), std::string::npos) << run.output;
        if (pipeline == "distribution") {
            EXPECT_NE(run.output.find("indirect_path_traced: yes"), std::string::npos)
                << run.output;
        }
        EXPECT_GT(luminanceMean(image), 0.0);
    }
}

TEST(SolveDeadline, DistributionWithoutTimeForTheSolveRendersThePathTracersImage) {
    // A time limit far shorter than any solve: the distribution preview's radiosity pass
    // abandons its solve, and the distribution pass traces every path, so that with the same
    // seed its image is the `reference` pipeline's, pixel for pixel (the box has no specular
    // surface, so no caustic pass runs). Against the stored path-traced reference too: without
    // the indirect light the image would be a third dark; the bound is about three times the
    // largest deviation of one-sample images (seeds 0-3 of the full solve: at most 3.6 %).
    const std::string folder = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell-box";
    const std::string options = "--time-limit 0.001 --width 128 --height 128 --threads 2 --seed 3";
    TempDir dir("solve-deadline-distribution");
    CliResult run;
    const Image image = renderImage(folder + "/cornell-box.gltf", dir.file("distribution.exr"),
                                    "--pipeline distribution " + options, &run);
    EXPECT_NE(run.output.find("abandoned_by_time_limit: yes"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("indirect_path_traced: yes"), std::string::npos) << run.output;
    const Image traced = renderImage(folder + "/cornell-box.gltf", dir.file("reference.exr"),
                                     "--pipeline reference " + options);
    ASSERT_EQ(image.pixels().size(), traced.pixels().size());
    size_t differing = 0;
    for (size_t i = 0; i < image.pixels().size(); ++i)
        differing += image.pixels()[i] != traced.pixels()[i];
    EXPECT_EQ(differing, 0u);
    const double ratio = luminanceMean(image) / luminanceMean(readImage(folder + "/reference.exr"));
    std::cout << "mean luminance over the reference's: " << ratio << "\n";
    EXPECT_NEAR(ratio, 1.0, 0.1);
}

}  // namespace
}  // namespace penumbra::test
