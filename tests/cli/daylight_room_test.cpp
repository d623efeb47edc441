// A daylit room: a closed room lit through a window in its south wall by the CIE overcast sky, and
// by a clear sky with the sun, whose patch lands on the floor. The hybrid and the radiosity view
// against the path tracer on the image's quadrants: the sky and the sun reach the solution's
// elements through the opening as direct light, and the window shows the sky in every pipeline.
#include "core/image.h"
#include "tests/support/cli_runner.h"
#include "tests/support/gltf_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::test {
namespace {

// The room of scenes/daylit-room (its README): 4 x 3 x 4 m, a 2 x 1.5 m window in its south wall
// (z = 2), a camera in the north-west corner looking at the south-east.
const std::string kRoom = std::string(PENUMBRA_SOURCE_DIR) + "/scenes/daylit-room/room.gltf";

// The luminance means of the image's four quadrants.
std::array<double, 4> quadrants(const Image& image) {
    const int w = image.width(), h = image.height();
    std::array<double, 4> means{};
    for (int k = 0; k < 4; ++k) {
        const int x0 = (k % 2) * w / 2, y0 = (k / 2) * h / 2;
        for (int c = 0; c < 3; ++c) {
            const double weight = c == 0 ? 0.2126 : c == 1 ? 0.7152 : 0.0722;
            means[k] += weight * regionMean(image, c, x0, y0, x0 + w / 2, y0 + h / 2);
        }
    }
    return means;
}

void compare(const std::string& light, const char* name) {
    TempDir dir(std::string("daylit-room-") + name);
    const auto render = [&](const std::string& pipeline, int spp, const std::string& options) {
        return quadrants(renderImage(kRoom, dir.file(pipeline + ".exr"),
                                     "--quiet --width 48 --height 32 --pipeline " + pipeline +
                                         " --spp " + std::to_string(spp) + " " + light + options));
    };
    // 4096 samples: at 1024 the reference's own noise moved a quadrant's mean by 0.4 %, a fifth of
    // the tolerance below.
    const std::array<double, 4> reference = render("reference", 4096, "");
    // The window as a portal (core/portals.h): its corner and two neighbours.
    const std::string portal = " --portal -1,0.75,2,1,0.75,2,-1,2.25,2";
    const struct {
        const char* pipeline;
        int spp;
        std::string options;
        double tolerance;
    } cases[] = {
        // The hybrid is unbiased: the 2 % on the room's region means.
        {"hybrid", 256, "", 0.02},
        // With the window as a portal the radiosity solution and its view take the sky through
        // it: 0.985-1.011 of the reference measured under the overcast sky. With the sun, its
        // patch's edges cut into the floor (shadow_lines, radiosity/shadow_lines.h): 0.997-1.005
        // (1.8-2.3 % low in the top-left quadrant, the walls the patch lights, without the cut:
        // the leaves across the patch's edge carried the sun's light as their few samples found
        // it). The 2 % on the region means.
        {"radiosity", 16, portal, 0.02},
        // The window found as a portal (--portal auto): as good as the one given (0.999-1.009
        // with the sun).
        {"radiosity", 16, " --portal auto", 0.02},
        // Without a portal (the default finds one: --portal none), the view's corners find the
        // sky through the window by the few of their 64 + 64 fixed directions that pass the
        // opening, the same at every corner, so the walls show broad bands: 0.90-1.04 of the
        // reference under the overcast sky, 0.956-1.023 with the sun (0.903-1.031 and
        // 0.966-1.015 on 2026-12-06). 12 % guards that from getting worse.
        {"radiosity", 16, " --portal none", 0.12},
    };
    for (const auto& c : cases) {
        const std::array<double, 4> test = render(c.pipeline, c.spp, c.options);
        for (int k = 0; k < 4; ++k) {
            std::printf("[ measured ] %s %s%s quadrant %d: %.4f / %.4f = %.4f\n", name, c.pipeline,
                        c.options.c_str(), k, test[k], reference[k], test[k] / reference[k]);
            EXPECT_NEAR(test[k], reference[k], c.tolerance * reference[k])
                << c.pipeline << " " << k;
        }
    }
}

TEST(DaylitRoom, OvercastSkyThroughAWindow) {
    compare("--sky cie-overcast --sky-illuminance 10000", "overcast");
}

TEST(DaylitRoom, ClearSkyAndTheSunThroughAWindow) {
    compare(
        "--sky cie-clear --sky-illuminance 15000 --sun-direct-normal 60000 "
        "--site 39.742476,-105.1786 --time 2003-10-17T12:30:30-07:00",
        "sun");
}

// The portals `render --portal auto` printed, as their three corners: c0, c1, c2 (the fourth
// is c1 + c2 - c0).
std::vector<std::array<double, 9>> printedPortals(const std::string& output) {
    std::vector<std::array<double, 9>> portals;
    for (size_t at = output.find("  --portal "); at != std::string::npos;
         at = output.find("  --portal ", at + 1)) {
        std::array<double, 9> c{};
        if (std::sscanf(output.c_str() + at, "  --portal %lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf",
                        &c[0], &c[1], &c[2], &c[3], &c[4], &c[5], &c[6], &c[7], &c[8]) == 9)
            portals.push_back(c);
    }
    return portals;
}

// A portal found in a wall of constant z covers the opening x in [-1, 1], y in [0.75, 2.25],
// with a margin of at most 8 cm (the detector's half gap, a hundredth of the scene's bounding
// radius, and the crossings' spread), and lies in a plane z between zLow and zHigh.
void expectCoversTheWindow(const std::array<double, 9>& c, double zLow, double zHigh) {
    double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
    for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(c[3 * k + 2], c[2], 1e-3) << "corner " << k << " off the portal's plane";
        x0 = std::min(x0, c[3 * k]);
        x1 = std::max(x1, c[3 * k]);
        y0 = std::min(y0, c[3 * k + 1]);
        y1 = std::max(y1, c[3 * k + 1]);
    }
    EXPECT_GE(c[2], zLow);
    EXPECT_LE(c[2], zHigh);
    for (const auto& [found, window] : {std::pair{x0, -1.0}, {y0, 0.75}}) {
        EXPECT_LE(found, window);
        EXPECT_GE(found, window - 0.08);
    }
    for (const auto& [found, window] : {std::pair{x1, 1.0}, {y1, 2.25}}) {
        EXPECT_GE(found, window);
        EXPECT_LE(found, window + 0.08);
    }
}

// --portal auto finds the window: a rectangle in the wall's plane (z = 2) that covers the 2 x 1.5 m
// opening, and no other opening.
TEST(DaylitRoom, FindsItsWindowAsAPortal) {
    TempDir dir("daylit-room-auto-portal");
    const CliResult r = runPenumbra("render " + kRoom + " -o " + dir.file("room.exr") +
                                    " --width 8 --height 8 --spp 1 --sky cie-overcast "
                                    "--portal auto");
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_NE(r.output.find("1 opening found"), std::string::npos) << r.output;
    const std::vector<std::array<double, 9>> portals = printedPortals(r.output);
    ASSERT_EQ(portals.size(), 1u) << r.output;
    expectCoversTheWindow(portals[0], 2.0 - 1e-3, 2.0 + 1e-3);
}

// The openings are found by default when there is an environment, not with --portal none, and
// none cannot be given with other portals.
TEST(DaylitRoom, FindsItsWindowByDefaultUnlessTold) {
    TempDir dir("daylit-room-default-portal");
    const std::string render = "render " + kRoom + " -o " + dir.file("room.exr") +
                               " --width 8 --height 8 --spp 1 --sky cie-overcast";
    const CliResult byDefault = runPenumbra(render);
    ASSERT_EQ(byDefault.status, 0) << byDefault.output;
    EXPECT_EQ(printedPortals(byDefault.output).size(), 1u) << byDefault.output;
    const CliResult none = runPenumbra(render + " --portal none");
    ASSERT_EQ(none.status, 0) << none.output;
    EXPECT_EQ(none.output.find("opening"), std::string::npos) << none.output;
    const CliResult both = runPenumbra(render + " --portal none auto");
    EXPECT_EQ(both.status, 2) << both.output;
    EXPECT_NE(both.output.find("--portal none"), std::string::npos) << both.output;
}

// An axis-aligned box, its faces outwards.
void addBox(GltfBuilder& gltf, const Vec3& lo, const Vec3& hi, int material) {
    const auto corner = [&](int k) {
        return Vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    };
    gltf.addQuad(corner(0), corner(2), corner(3), corner(1), material);  // -z
    gltf.addQuad(corner(4), corner(5), corner(7), corner(6), material);  // +z
    gltf.addQuad(corner(0), corner(4), corner(6), corner(2), material);  // -x
    gltf.addQuad(corner(1), corner(3), corner(7), corner(5), material);  // +x
    gltf.addQuad(corner(0), corner(1), corner(5), corner(4), material);  // -y
    gltf.addQuad(corner(2), corner(6), corner(7), corner(3), material);  // +y
}

// A window in a 30-cm wall, as real ones are: the opening's reveals, a meeting rail 8-12 cm into
// the wall and a vertical glazing bar 18-22 cm into it. The surfaces around the escaping rays lie
// at several depths and orientations (the wall's face, the rail's, the bar's, the reveals and the
// rail's top and bottom); the window is still one portal, in a plane within the wall's depth.
TEST(DaylitRoom, FindsAWindowWithDepthAsOnePortal) {
    TempDir dir("daylit-room-deep-window");
    GltfBuilder room;
    const int white = room.addMaterial({.baseColor = Color(0.5f), .doubleSided = true});
    // The room, 4 x 3 x 4 m, its south wall left out.
    addBox(room, {-2.1f, -0.1f, -2.1f}, {2.1f, 0.0f, 2.0f}, white);  // floor
    addBox(room, {-2.1f, 3.0f, -2.1f}, {2.1f, 3.1f, 2.0f}, white);   // ceiling
    addBox(room, {-2.1f, 0.0f, -2.1f}, {2.1f, 3.0f, -2.0f}, white);  // north wall
    addBox(room, {-2.1f, 0.0f, -2.0f}, {-2.0f, 3.0f, 2.0f}, white);  // west wall
    addBox(room, {2.0f, 0.0f, -2.0f}, {2.1f, 3.0f, 2.0f}, white);    // east wall
    // The south wall, z in [2, 2.3], around the opening.
    addBox(room, {-2.1f, -0.1f, 2.0f}, {2.1f, 0.75f, 2.3f}, white);
    addBox(room, {-2.1f, 2.25f, 2.0f}, {2.1f, 3.1f, 2.3f}, white);
    addBox(room, {-2.1f, 0.75f, 2.0f}, {-1.0f, 2.25f, 2.3f}, white);
    addBox(room, {1.0f, 0.75f, 2.0f}, {2.1f, 2.25f, 2.3f}, white);
    addBox(room, {-1.0f, 1.47f, 2.08f}, {1.0f, 1.53f, 2.12f}, white);    // the meeting rail
    addBox(room, {-0.03f, 0.75f, 2.18f}, {0.03f, 2.25f, 2.22f}, white);  // the glazing bar
    room.write(dir.file("room.gltf"));
    const CliResult r =
        runPenumbra("render " + dir.file("room.gltf") + " -o " + dir.file("room.exr") +
                    " --width 8 --height 8 --spp 1 --sky uniform --portal auto");
    ASSERT_EQ(r.status, 0) << r.output;
    const std::vector<std::array<double, 9>> portals = printedPortals(r.output);
    ASSERT_EQ(portals.size(), 1u) << r.output;
    expectCoversTheWindow(portals[0], 2.0, 2.3 + 1e-3);
}

// A room without a window and a floor in the open have no opening: a warning, and the
// environment is sampled as without portals.
TEST(DaylitRoom, NoOpeningNoPortal) {
    TempDir dir("daylit-room-no-opening");
    GltfBuilder closed;
    const int white = closed.addMaterial({.baseColor = Color(0.5f)});
    // A 2-m cube, every face turned inwards.
    closed.addQuad({-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}, white);
    closed.addQuad({-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}, white);
    closed.addQuad({-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {1, -1, -1}, white);
    closed.addQuad({-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}, white);
    closed.addQuad({-1, -1, -1}, {-1, -1, 1}, {-1, 1, 1}, {-1, 1, -1}, white);
    closed.addQuad({1, -1, -1}, {1, 1, -1}, {1, 1, 1}, {1, -1, 1}, white);
    closed.write(dir.file("closed.gltf"));
    GltfBuilder open;
    open.addQuad({-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}, open.addMaterial({}));
    open.write(dir.file("open.gltf"));
    for (const char* scene : {"closed.gltf", "open.gltf"}) {
        const CliResult r =
            runPenumbra("render " + dir.file(scene) + " -o " + dir.file("out.exr") +
                        " --width 4 --height 4 --spp 1 --sky uniform --portal auto");
        EXPECT_EQ(r.status, 0) << r.output;
        EXPECT_NE(r.output.find("found no opening"), std::string::npos) << scene << r.output;
    }
}

}  // namespace
}  // namespace penumbra::test
