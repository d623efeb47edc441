// Flux deposited on the radiosity mesh (radiosity/deposited_flux.h): the sums follow the points
// down as leaves split, and the hierarchical solver reflects and carries the deposited light on
// with the closed form of a closed box.
#include "radiosity/deposited_flux.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solver.h"
#include "tests/support/gltf_builder.h"
#include "tests/support/radiosity_scenes.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace penumbra::test {
namespace {

// `perTriangle` deposits at uniform random points of every triangle of the scene, each of a random
// power in [0.5, 1.5) lm per channel, arriving on the front side (or on the back for every
// `backEvery`-th deposit; 0 = never).
std::vector<FluxDeposit> randomDeposits(const Scene& scene, int perTriangle, int backEvery,
                                        uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    std::vector<FluxDeposit> deposits;
    int count = 0;
    for (uint32_t m = 0; m < scene.meshes().size(); ++m) {
        for (uint32_t t = 0; t < scene.meshes()[m].triangles.size(); ++t) {
            const Scene::Triangle tri = scene.triangle(m, t);
            const Vec3 front = glm::normalize(glm::cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
            for (int i = 0; i < perTriangle; ++i) {
                const Vec3 b = sampleUniformTriangle(Vec2(uniform(random), uniform(random)));
                const bool back = backEvery > 0 && ++count % backEvery == 0;
                deposits.push_back({m, t, b, back ? -front : front,
                                    Color(0.5f + uniform(random), 0.5f + uniform(random),
                                          0.5f + uniform(random))});
            }
        }
    }
    return deposits;
}

bool isAncestorOrSelf(const RadiosityMesh& mesh, int ancestor, int element) {
    for (int e = element; e >= 0; e = mesh.parent(e)) {
        if (e == ancestor)
            return true;
    }
    return false;
}

// Every element side's flux is the sum of the deposits inside it, found from scratch.
void expectSumsOfTheDepositsInside(const RadiosityMesh& mesh, const DepositedFlux& flux,
                                   const std::vector<FluxDeposit>& deposits) {
    std::vector<int> leaf;
    for (const FluxDeposit& d : deposits)
        leaf.push_back(mesh.locate(d.mesh, d.triangle, d.barycentric).element);
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        for (const bool front : {true, false}) {
            Color expected(0.0f);
            for (size_t i = 0; i < deposits.size(); ++i) {
                const bool arrivedFront = glm::dot(deposits[i].normal, mesh.normal(leaf[i])) > 0.0f;
                if (arrivedFront == front && isAncestorOrSelf(mesh, element, leaf[i]))
                    expected += deposits[i].power;
            }
            const Color got = flux.flux(element, front);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(got[c], expected[c], 1e-4f * (1.0f + expected[c]))
                    << "element " << element << (front ? " front" : " back");
        }
    }
}

TEST(DepositedFlux, SumsFollowThePointsDownAsLeavesSplit) {
    GltfBuilder builder;
    const int floor = builder.addMaterial({.baseColor = Color(0.5f)});
    builder.addQuad(Vec3(-1, 0, 1), Vec3(1, 0, 1), Vec3(1, 0, -1), Vec3(-1, 0, -1), floor);
    const auto scene = loadBuiltScene(builder, "deposited-flux-floor");
    RadiosityMesh mesh(*scene, MeshingSettings{1.0f, 0.0f});
    const std::vector<FluxDeposit> deposits = randomDeposits(*scene, 300, 5, 7);
    DepositedFlux flux(mesh, deposits);
    EXPECT_EQ(flux.count(), deposits.size());
    EXPECT_EQ(flux.dropped(), 0u);
    expectSumsOfTheDepositsInside(mesh, flux, deposits);

    // Three rounds of splits, of every other leaf, so that leaves of different levels meet.
    for (int round = 0; round < 3; ++round) {
        const size_t elements = mesh.elementCount();
        for (size_t e = 0; e < elements; e += 2) {
            if (mesh.isLeaf(static_cast<int>(e)) && mesh.canSplit(static_cast<int>(e)))
                mesh.split(static_cast<int>(e));
        }
        flux.update();
        expectSumsOfTheDepositsInside(mesh, flux, deposits);
    }
    Color total(0.0f);
    for (const FluxDeposit& d : deposits)
        total += d.power;
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(flux.totalPower()[c], total[c], 1e-4f * total[c]);
}

// A closed box of reflectance rho without any light, flux Phi deposited uniformly on its inside:
// every bounce stays in the box, so the reflected flux is Phi (rho + rho² + ...) = Phi rho / (1 -
// rho) and, the walls being Lambertian, the area-weighted mean radiance of the inside is
// Phi rho / (pi A (1 - rho)). The first reflection alone (elementDirect) carries Phi rho, exactly:
// it is the deposits' own sums.
TEST(DepositedFlux, ClosedBoxReflectsItAsTheFurnaceClosedForm) {
    constexpr float rho = 0.5f;
    GltfBuilder builder;
    const int wall = builder.addMaterial({.baseColor = Color(rho)});
    addClosedBox(builder, wall, wall);
    const auto scene = loadBuiltScene(builder, "deposited-flux-box");
    const std::vector<FluxDeposit> deposits = randomDeposits(*scene, 2000, 0, 3);
    Color phi(0.0f);
    for (const FluxDeposit& d : deposits)
        phi += d.power;

    RadiositySettings settings;
    settings.minElementArea = 0.5f / 16.0f;
    RadiosityMesh mesh(*scene, settings.meshing(*scene));
    RadiositySolver solver(*scene, mesh, settings, deposits);
    solver.solve();

    Color radiance(0.0f), direct(0.0f);
    double area = 0.0;
    for (size_t e = 0; e < mesh.elementCount(); ++e) {
        const int element = static_cast<int>(e);
        if (!mesh.isLeaf(element))
            continue;
        area += mesh.area(element);
        radiance += mesh.area(element) * solver.elementRadiance(element, true);
        direct += mesh.area(element) * solver.elementDirect(element, true);
        EXPECT_EQ(solver.elementRadiance(element, false), Color(0.0f)) << "element " << element;
    }
    EXPECT_NEAR(area, 24.0, 1e-3);
    for (int c = 0; c < 3; ++c) {
        const double expected = phi[c] * rho / (kPi * area * (1.0 - rho));
        // The solver's convergence (1e-4) and its links' transfer error (the furnace tests: 1 %
        // per leaf at rho 0.5, less in the mean).
        EXPECT_NEAR(radiance[c] / area / expected, 1.0, 0.01) << "channel " << c;
        EXPECT_NEAR(kPi * direct[c] / (phi[c] * rho), 1.0, 1e-4) << "channel " << c;
    }
}

}  // namespace
}  // namespace penumbra::test
