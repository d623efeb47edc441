// Radiosity end to end, against the path tracer: `penumbra render` of a closed Lambertian room
// through the radiosity pipeline and the reference path tracer, whose floor means must agree.
#include "core/image_io.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>

namespace penumbra::test {
namespace {

Image render(const TempDir& dir, const std::string& name, const std::string& options) {
    const std::string out = dir.file(name + ".exr");
    const CliResult result =
        runPenumbra("render " + dir.file("scene.gltf") + " -o " + out + " --quiet " + options);
    EXPECT_EQ(result.status, 0) << result.output;
    return readImage(out);
}

TEST(RadiosityPipeline, FloorAgreesWithReferencePathTracer) {
    // A closed Lambertian room lit by a square ceiling light; an orthographic camera below the
    // light looks straight down and sees only the floor. Radiosity and the path tracer solve the
    // same equation here (every surface Lambertian), so the floor's mean must agree.
    GltfBuilder scene;
    const int walls = scene.addMaterial({.baseColor = Color(0.6f)});
    const int floor = scene.addMaterial({.baseColor = Color(0.5f, 0.4f, 0.3f)});
    addClosedBox(scene, walls, floor);
    addCeilingLight(scene, 0.25f, 0.99f, 20.0f);
    // Looking down (-Y): rotation of -90 degrees about +X.
    scene.setOrthographicCamera({0, 0.9f, 0}, {-std::sqrt(0.5f), 0.0f, 0.0f, std::sqrt(0.5f)},
                                0.95f, 0.95f);
    TempDir dir("radiosity-pipeline");
    scene.write(dir.file("scene.gltf"));
    const Image radiosity = render(dir, "radiosity",
                                   "--pipeline radiosity --width 48 "
                                   "--height 48 --spp 4");
    const Image reference = render(dir, "reference",
                                   "--pipeline reference --width 48 "
                                   "--height 48 --spp 256");
    const double r = luminanceMean(radiosity), p = luminanceMean(reference);
    std::cout << "floor mean: radiosity " << r << ", path tracer " << p << " (ratio " << r / p
              << ")\n";
    // The path tracer's mean over 590k paths has a relative standard error near 0.2 %; 2 % is
    // the bound.
    EXPECT_NEAR(r / p, 1.0, 0.02);
}

}  // namespace
}  // namespace penumbra::test
