// The indirect light gathered at the leaves' corners (radiosity/indirect_at_corners.h) against
// a closed form: a floor beside a wall standing on it, the wall's reflected radiance uniform and
// nothing else reflecting, so that the floor's indirect light at a point x is
//     rho Lw F(x),
// F the form factor from a differential element of the floor to the wall (Howell's catalogue
// B-2, two rectangles by superposition). F goes from 1/2 at the wall's foot to a few per cent a
// metre away: the change within an element that the element means average away. The solution is
// a stand-in given to the gather (the wall's hits reflect Lw, all else nothing), so that the
// closed form is exact for what the gather is asked. Last, the refinement at creases
// (radiosity/crease_refinement.h) on the same floor, whose dip at the wall's foot it must let the
// corners show.
#include "radiosity/indirect_at_corners.h"

#include "core/scene.h"
#include "radiosity/crease_refinement.h"
#include "radiosity/element_sampling.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_settings.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <optional>
#include <utility>

namespace penumbra::test {
namespace {

constexpr float kRho = 0.5f, kWallRadiance = 10.0f;
// The wall: the plane x = 0, z in [-kHalfWidth, kHalfWidth], height kHeight, facing +x; the floor
// in front of it: x in [0, 2], z in [-kHalfWidth, kHalfWidth].
constexpr float kHalfWidth = 1.0f, kHeight = 1.0f, kDepth = 2.0f;

// Howell B-2: a differential element and a rectangle in a plane perpendicular to its own, of
// height a (away from the element's plane) and width b along the planes' common line, the
// element at distance c from that line, on the normal to it through one end of the width.
double perpendicularCornerFormFactor(double a, double b, double c) {
    const double X = a / b, Y = c / b, r = std::sqrt(X * X + Y * Y);
    return (std::atan(1.0 / Y) - Y / r * std::atan(1.0 / r)) / (2.0 * kPi);
}

// F from a floor point (x, z) to the whole wall, |z| < kHalfWidth.
double wallFormFactor(double x, double z) {
    return perpendicularCornerFormFactor(kHeight, kHalfWidth - z, x) +
           perpendicularCornerFormFactor(kHeight, kHalfWidth + z, x);
}

struct WallAndFloor {
    std::unique_ptr<Scene> scene;
    std::unique_ptr<RadiosityMesh> mesh;
};

WallAndFloor wallAndFloor(float patchEdgeLength = 0.1f) {
    GltfBuilder builder;
    const int floor = builder.addMaterial({.baseColor = Color(kRho)});
    const int wall = builder.addMaterial({.baseColor = Color(kRho)});
    const float w = kHalfWidth;
    builder.addQuad({0, 0, -w}, {0, 0, w}, {kDepth, 0, w}, {kDepth, 0, -w}, floor);
    builder.addQuad({0, 0, w}, {0, 0, -w}, {0, kHeight, -w}, {0, kHeight, w}, wall);
    WallAndFloor s;
    s.scene = loadBuiltScene(builder, "indirect-at-corners");
    // By default patches of at most 0.1 m: elements of a few centimetres at the wall's foot.
    s.mesh = std::make_unique<RadiosityMesh>(*s.scene,
                                             MeshingSettings{.patchEdgeLength = patchEdgeLength});
    return s;
}

IndirectAtCorners::Solution wallLitSolution() {
    return {.exposed = [](int, bool front) { return front; },
            .covered = [](int, const ElementSample&, bool, uint64_t&) { return false; },
            .seenAt =
                [](const MeshedHit& y, Sampler&, uint64_t&) {
                    return y.hit.ng.x > 0.5f && y.front ? Color(kWallRadiance) : Color(0.0f);
                },
            .unseen = [](int, bool) { return Color(0.0f); },
            .fallback = [](int, bool) { return Color(0.0f); }};
}

// The floor's leaves, corner by corner, against rho Lw F, at the default rays per corner N. The
// gather estimates F as the share of its rays that meet the wall; with N independent rays its
// relative error would have the standard deviation s = sqrt((1 - F) / (F N)) (binomial), and the
// stratified rays do no worse: every corner within 4 s (one in 16 000 would fail by chance), the
// mean error over the corners within 0.5 % (no bias), and at the wall's foot, where the wall
// fills exactly half the hemisphere, within 1 %.
TEST(IndirectAtCorners, TheFloorBesideALitWallMatchesTheFormFactor) {
    const WallAndFloor s = wallAndFloor();
    const int rays = RadiositySettings{}.indirectAtCorners;
    IndirectAtCorners corners(*s.scene, *s.mesh, rays, int(s.mesh->elementCount()));
    corners.gather(wallLitSolution());
    double worstInSigmas = 0.0, errorSum = 0.0, worstAtFoot = 0.0;
    int checked = 0, atFoot = 0;
    for (const int e : s.mesh->leafElements()) {
        if (!(s.mesh->normal(e).y > 0.5f))
            continue;
        const std::array<Color, 3> shown = corners.corners(e, true);
        for (size_t k = 0; k < 3; ++k) {
            // The corner is evaluated a thousandth of the leaf inside it: at the wall's foot,
            // x is that inset, not 0. The loader rebases the world on the geometry's centre:
            // x from the wall, z from the middle.
            const Vec3 at = ElementSampler(*s.scene, *s.mesh, e)
                                .at(insetWeights(Vec3(k == 0, k == 1, k == 2)))
                                .p -
                            Vec3(s.scene->bounds().lo.x, 0.0f, 0.0f);
            if (std::abs(at.z) > 0.5f * kHalfWidth)
                continue;
            const double F = wallFormFactor(at.x, at.z);
            const double error = shown[k].g / (kRho * kWallRadiance * F) - 1.0;
            const double sigma = std::sqrt((1.0 - F) / (F * rays));
            worstInSigmas = std::max(worstInSigmas, std::abs(error) / sigma);
            errorSum += error;
            ++checked;
            if (at.x < 0.01f) {
                worstAtFoot = std::max(worstAtFoot, std::abs(error));
                ++atFoot;
            }
        }
    }
    const double meanError = errorSum / checked;
    std::cout << checked << " corners: worst " << worstInSigmas << " standard deviations, mean "
              << 100.0 * meanError << " %; " << atFoot << " at the foot: worst "
              << 100.0 * worstAtFoot << " %\n";
    ASSERT_GT(checked, 1000);
    ASSERT_GT(atFoot, 20);
    EXPECT_LT(worstInSigmas, 4.0);
    EXPECT_LT(std::abs(meanError), 0.005);
    EXPECT_LT(worstAtFoot, 0.01);
}

// The corners that several leaves have at one vertex of one plane are gathered once, so that the
// interpolation is continuous across the leaves' edges.
TEST(IndirectAtCorners, LeavesMeetingAtAVertexShowOneValueThere) {
    const WallAndFloor s = wallAndFloor();
    IndirectAtCorners corners(*s.scene, *s.mesh, 16, int(s.mesh->elementCount()));
    corners.gather(wallLitSolution());
    std::map<uint32_t, Color> atVertex;
    int shared = 0;
    for (const int e : s.mesh->leafElements()) {
        if (!(s.mesh->normal(e).y > 0.5f))
            continue;  // the floor's only: the wall's corners at its foot are in another plane
        const std::array<Color, 3> shown = corners.corners(e, true);
        for (size_t k = 0; k < 3; ++k) {
            const auto [it, inserted] = atVertex.emplace(s.mesh->vertices(e)[k], shown[k]);
            if (!inserted) {
                EXPECT_EQ(it->second, shown[k]) << "vertex " << it->first;
                ++shared;
            }
        }
    }
    EXPECT_GT(shared, 100);
}

// Between its corners a leaf shows their interpolation only as far as each corner's value holds
// (the harmonic mean length of its rays): at a leaf's centroid, a corner at the wall's foot, whose
// rays meet the wall a few centimetres away, counts for less, and the element mean (the stand-in
// solution's fallback, here a constant) for more; far from the wall, where every corner's rays
// run far, the leaf shows its corners' interpolation.
TEST(IndirectAtCorners, ACornerCountsOnlyAsFarAsItsRaysReach) {
    const WallAndFloor s = wallAndFloor();
    IndirectAtCorners corners(*s.scene, *s.mesh, 64, int(s.mesh->elementCount()));
    IndirectAtCorners::Solution solution = wallLitSolution();
    const Color mean(0.123f);
    solution.fallback = [&](int, bool) { return mean; };
    corners.gather(solution);
    const float wallX = s.scene->bounds().lo.x;
    int atFoot = 0, far = 0;
    for (const int e : s.mesh->leafElements()) {
        if (!(s.mesh->normal(e).y > 0.5f))
            continue;
        const ElementPoint centroid{e, Vec3(1.0f / 3.0f)};
        const std::array<Color, 3> c = corners.corners(e, true);
        const Color interpolated = (c[0] + c[1] + c[2]) / 3.0f;
        const Color shown = corners.at(centroid, true);
        float nearest = INFINITY;
        for (const Vec3& p : s.mesh->corners(e))
            nearest = std::min(nearest, p.x - wallX);
        if (nearest < 1e-4f) {
            // Between the mean and the interpolation, nearer the mean than the interpolation is.
            EXPECT_LT(std::abs(shown.g - mean.g), std::abs(interpolated.g - mean.g)) << e;
            ++atFoot;
        } else if (nearest > 0.5f * kDepth) {
            EXPECT_NEAR(shown.g, interpolated.g, 1e-5f * interpolated.g + 1e-7f) << e;
            ++far;
        }
    }
    EXPECT_GT(atFoot, 10);
    EXPECT_GT(far, 10);
}

// Under a time limit the gather first makes every 64th corner's gather, a probe of its time.
// With a deadline far away the probe changes nothing: every corner holds the value the gather
// without a deadline gives (each corner's rays come from its own sequence, whatever the order),
// all of them gathered with the rays asked, and the probe cast a 64th more.
TEST(IndirectAtCorners, TheProbeOfADistantDeadlineChangesNoCorner) {
    const WallAndFloor s = wallAndFloor();
    IndirectAtCorners unhurried(*s.scene, *s.mesh, 16, int(s.mesh->elementCount()));
    ASSERT_TRUE(unhurried.gather(wallLitSolution()));
    IndirectAtCorners timed(*s.scene, *s.mesh, 16, int(s.mesh->elementCount()));
    ASSERT_TRUE(timed.gather(wallLitSolution(), nullptr,
                             std::chrono::steady_clock::now() + std::chrono::hours(1)));
    EXPECT_EQ(timed.raysPerCorner(), 16);
    EXPECT_GT(timed.rays(), unhurried.rays());
    EXPECT_LT(timed.rays(), unhurried.rays() + unhurried.rays() / 32);
    int compared = 0;
    for (const int e : s.mesh->leafElements()) {
        for (const bool front : {true, false}) {
            EXPECT_EQ(timed.corners(e, front), unhurried.corners(e, front)) << e;
            ++compared;
        }
    }
    EXPECT_GT(compared, 1000);
}

// A deadline that has passed leaves no time for the gathers: the gather gives up before its
// first ray (the test's covers cast none), so that the solution's element means are shown
// without a gather that would have taken the image's time.
TEST(IndirectAtCorners, ADeadlineThatHasPassedGathersNothing) {
    const WallAndFloor s = wallAndFloor();
    IndirectAtCorners late(*s.scene, *s.mesh, 16, int(s.mesh->elementCount()));
    EXPECT_FALSE(late.gather(wallLitSolution(), nullptr,
                             std::chrono::steady_clock::now() - std::chrono::seconds(1)));
    EXPECT_EQ(late.rays(), 0u);
}

double leafSize(const RadiosityMesh& mesh, int e) {
    return std::sqrt(2.0 * mesh.area(e));
}

// The refinement at creases (radiosity/crease_refinement.h) on the floor and wall with patches of
// half a metre, as a hall's: the corners at the foot hold their value micrometres, so without it
// the leaves there show their mean up to the wall. A stand-in solution again, whose leaf means are
// the closed form at their centroids, so that the refinement and the reconstruction are tested,
// not a solve.
struct RefinedWallAndFloor {
    WallAndFloor s = wallAndFloor(0.5f);
    float wallX = s.scene->bounds().lo.x;  // the loader rebases the world on the geometry's centre
    CreaseRefinement refinement;
    int firstCreaseLeaf = 0;  // the first element the refinement made

    void refine(size_t maxLeaves) {
        firstCreaseLeaf = static_cast<int>(s.mesh->elementCount());
        const CreaseRefinement::Solver solver{
            .shown = [](int, bool front) { return front; },
            .split = [this](int leaf,
                            float minChildArea) { return s.mesh->split(leaf, minChildArea); },
            .settle = [] {},
            .stop = nullptr};
        refinement = CreaseRefinement::run(*s.scene, *s.mesh, solver, maxLeaves);
    }

    IndirectAtCorners::Solution solution() const {
        IndirectAtCorners::Solution lit = wallLitSolution();
        lit.fallback = [this](int e, bool) {
            const Vec3 c = s.mesh->centroid(e);
            return s.mesh->normal(e).y > 0.5f
                       ? Color(kRho * kWallRadiance * wallFormFactor(c.x - wallX, c.z))
                       : Color(0.0f);
        };
        return lit;
    }

    // The largest size of the floor's leaves with a corner within `near` of the wall, and
    // whether every floor leaf wholly beyond `far` is still a patch (level 0: not split).
    std::pair<double, bool> floorLeaves(float near, float far) const {
        double largestNear = 0.0;
        bool farUnsplit = true;
        for (const int e : s.mesh->leafElements()) {
            if (!(s.mesh->normal(e).y > 0.5f))
                continue;
            float nearest = INFINITY;
            for (const Vec3& p : s.mesh->corners(e))
                nearest = std::min(nearest, p.x - wallX);
            if (nearest < near)
                largestNear = std::max(largestNear, leafSize(*s.mesh, e));
            else if (nearest > far)
                farUnsplit = farUnsplit && s.mesh->level(e) == 0;
        }
        return {largestNear, farUnsplit};
    }
};

// The leaves along the wall's foot, on both faces, are split down to kCreaseSize; the floor's
// leaves half a metre out are not, nor are any of the wall's that do not touch the floor.
TEST(CreaseRefinement, SplitsAlongTheCreaseDownToItsSizeAndNowhereElse) {
    RefinedWallAndFloor r;
    r.refine(1u << 20);
    const auto [nearFoot, farUnsplit] = r.floorLeaves(1e-4f, 0.5f);
    std::cout << r.refinement.leavesSplit << " leaves split, " << r.s.mesh->leafCount()
              << " leaves: at the foot up to " << nearFoot << " m\n";
    EXPECT_FALSE(r.refinement.budgetReached);
    EXPECT_GE(nearFoot, kCreaseSize);
    EXPECT_LT(nearFoot, 2.0 * kCreaseSize);
    EXPECT_TRUE(farUnsplit);
    for (const int e : r.s.mesh->leafElements()) {
        if (r.s.mesh->normal(e).x > 0.5f &&
            r.s.mesh->centroid(e).y - r.s.scene->bounds().lo.y > 0.3f * kHeight) {
            EXPECT_EQ(r.s.mesh->level(e), 0) << e;
        }
    }
}

// Over a budget the refinement stops, says so, and leaves no more leaves than the budget allows.
TEST(CreaseRefinement, StopsAtItsBudget) {
    RefinedWallAndFloor r;
    const size_t budget = r.s.mesh->leafCount() + 30;
    r.refine(budget);
    EXPECT_TRUE(r.refinement.budgetReached);
    EXPECT_LE(r.s.mesh->leafCount(), budget);
    EXPECT_GT(r.refinement.leavesSplit, 0u);
}

// What the floor shows between the wall's foot and a few centimetres out, against rho Lw F (F
// from 0.50 to 0.47 over the first 5 cm). Without the refinement (the mesh's leaves of 0.25 m)
// these points were 7-8 % low: the corners at the foot hold their value a few micrometres, and
// the leaf's mean takes over. Each shown value interpolates corners of 256 stratified rays on the
// patches and down to 32 on the leaves refined at the foot (IndirectAtCorners::raysAt, as the
// solver gathers); averaged over 41 points across the middle of the floor the mean error is within
// 1.5 % at every distance (measured: within 0.6 %; 0.2 % with 256 rays at every corner).
TEST(CreaseRefinement, TheFloorShowsTheDipAtTheWallsFoot) {
    RefinedWallAndFloor r;
    r.refine(1u << 20);
    IndirectAtCorners corners(*r.s.scene, *r.s.mesh, 256, r.firstCreaseLeaf);
    corners.gather(r.solution());
    for (const float x : {0.002f, 0.005f, 0.01f, 0.02f, 0.05f}) {
        double errorSum = 0.0;
        int points = 0;
        for (int i = -20; i <= 20; ++i) {
            const float z = 0.02f * static_cast<float>(i);
            const std::optional<SurfaceHit> hit =
                r.s.scene->intersect(Ray(Vec3(r.wallX + x, 1e-3f, z), Vec3(0, -1, 0)));
            ASSERT_TRUE(hit.has_value()) << x << ", " << z;
            const ElementPoint point = r.s.mesh->locate(hit->mesh, hit->triangle, hit->barycentric);
            const double expected = kRho * kWallRadiance * wallFormFactor(x, z);
            errorSum += corners.at(point, true).g / expected - 1.0;
            ++points;
        }
        const double meanError = errorSum / points;
        std::cout << "x = " << x << " m: mean error " << 100.0 * meanError << " %\n";
        EXPECT_LT(std::abs(meanError), 0.015) << x;
    }
}

// The corners of the leaves the refinement made gather with fewer rays (IndirectAtCorners::raysAt:
// half as many per level below the solve's leaf, at least 32), every corner of a solve's leaf with
// all of its rays: there the gather shows the very values of one that gives every corner 256 rays
// (same seeds, same rays), and the whole gather casts far fewer rays than that one.
TEST(CreaseRefinement, CreaseCornersGatherFewerRaysThanTheSolvesLeaves) {
    RefinedWallAndFloor r;
    r.refine(1u << 20);
    IndirectAtCorners scaled(*r.s.scene, *r.s.mesh, 256, r.firstCreaseLeaf);
    IndirectAtCorners everywhere(*r.s.scene, *r.s.mesh, 256,
                                 static_cast<int>(r.s.mesh->elementCount()));
    scaled.gather(r.solution());
    everywhere.gather(r.solution());
    int solveLeaves = 0, creaseCornersChanged = 0;
    for (const int e : r.s.mesh->leafElements()) {
        const std::array<Color, 3> a = scaled.corners(e, true), b = everywhere.corners(e, true);
        if (e < r.firstCreaseLeaf) {
            ++solveLeaves;
            for (size_t k = 0; k < 3; ++k)
                EXPECT_EQ(a[k], b[k]) << e << ", corner " << k;
        } else {
            for (size_t k = 0; k < 3; ++k)
                creaseCornersChanged += a[k] != b[k];
        }
    }
    std::cout << scaled.rays() << " rays against " << everywhere.rays() << "; " << solveLeaves
              << " solve leaves, " << creaseCornersChanged << " crease corners changed\n";
    EXPECT_GT(solveLeaves, 10);
    EXPECT_GT(creaseCornersChanged, 100);
    EXPECT_LT(scaled.rays(), everywhere.rays() / 2);
}

}  // namespace
}  // namespace penumbra::test
