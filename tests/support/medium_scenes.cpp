#include "tests/support/medium_scenes.h"

#include "core/density_grid.h"
#include "tests/support/radiosity_scenes.h"

#include <cmath>
#include <vector>

namespace penumbra::test {

std::unique_ptr<Scene> withMedium(const GltfBuilder& builder, const std::string& name,
                                  MediumDesc medium, const DensityField* density) {
    const std::unique_ptr<Scene> built = loadBuiltScene(builder, name);
    SceneDescription description = built->description();
    const Vec3 origin(description.origin);
    if (density) {
        std::vector<float> values;
        const Bounds3 box = *medium.box;
        const glm::ivec3 n = density->nodes;
        for (int z = 0; z < n.z; ++z)
            for (int y = 0; y < n.y; ++y)
                for (int x = 0; x < n.x; ++x)
                    values.push_back(
                        float(density->at(box.lo + Vec3(x, y, z) / Vec3(n - 1) * box.diagonal())));
        medium.density = std::make_shared<const DensityGrid>(
            Bounds3{box.lo - origin, box.hi - origin}, n, std::move(values));
    }
    if (medium.box)
        medium.box = Bounds3{medium.box->lo - origin, medium.box->hi - origin};
    description.media.push_back(medium);
    return std::make_unique<Scene>(std::move(description));
}

const DensityField kPuffs{
    [](const Vec3& p) {
        const auto puff = [&](const Vec3& centre, double radius) {
            return std::exp(-glm::dot(p - centre, p - centre) / (radius * radius));
        };
        return 0.1 + 3.0 * puff(Vec3(0.2f, -0.5f, -0.3f), 0.35) +
               2.0 * puff(Vec3(-0.4f, -0.3f, 0.4f), 0.25);
    },
    {20, 10, 20}};

GltfBuilder smokyRoom() {
    GltfBuilder builder;
    const int walls = builder.addMaterial({.baseColor = Color(0.6f)});
    addClosedBox(builder, walls, walls);
    builder.addLight(
        {.type = "point", .name = "Lamp", .intensity = 2.0f, .position = Vec3(0.3f, 0.5f, -0.2f)});
    return builder;
}
const MediumDesc kLowSmoke{.name = "smoke",
                           .sigmaA = Color(0.2f, 0.3f, 0.4f),
                           .sigmaS = Color(1.0f),
                           .g = 0.5f,
                           .box = Bounds3{Vec3(-1.0f), Vec3(1.0f, 0.0f, 1.0f)}};
const Ray kIntoTheSmoke{Vec3(0.0f, 0.0f, 0.9f), glm::normalize(Vec3(0.2f, -0.3f, -1.0f))};

GltfBuilder equilibriumBox(float rho, const Color& Le) {
    GltfBuilder builder;
    const int wall = builder.addMaterial(
        {.baseColor = Color(rho), .emissive = (1.0f - rho) * Le / 2.0f, .emissiveStrength = 2.0f});
    addClosedBox(builder, wall, wall);
    return builder;
}

MediumDesc glowingMedium(const Color& Le) {
    return MediumDesc{.name = "glow",
                      .sigmaA = Color(0.6f, 0.3f, 1.0f),
                      .sigmaS = Color(0.8f),
                      .g = 0.5f,
                      .emission = Le,
                      .box = Bounds3{Vec3(-1.0f), Vec3(1.0f)}};
}

GltfBuilder lampAtTheOrigin() {
    GltfBuilder builder;
    const int black = builder.addMaterial({.baseColor = Color(0.0f)});
    builder.addQuad({-1, -50, 1}, {1, -50, 1}, {1, -50, -1}, {-1, -50, -1}, black);
    builder.addLight({.type = "point", .intensity = kLampIntensity, .position = Vec3(0.0f)});
    return builder;
}

GltfBuilder panelAtFiveMetres() {
    GltfBuilder builder;
    const int panel = builder.addMaterial(
        {.baseColor = Color(0.0f), .emissive = Color(1.0f), .emissiveStrength = kPanelRadiance});
    builder.addQuad({-1, -1, -5}, {1, -1, -5}, {1, 1, -5}, {-1, 1, -5}, panel);
    return builder;
}

MediumDesc slabBetween(const Color& sigmaA, const Color& emission) {
    return MediumDesc{.name = "slab",
                      .sigmaA = sigmaA,
                      .sigmaS = Color(0.0f),
                      .g = 0.0f,
                      .emission = emission,
                      .box = Bounds3{Vec3(-10, -10, -3.5f), Vec3(10, 10, -2)}};
}

namespace {

double opticalLength(const AffineDensity& density, const glm::dvec3& a, const glm::dvec3& b) {
    return glm::length(b - a) * density(0.5 * (a + b));
}

}  // namespace

double airlight(const Vec3& o, const Vec3& d, double tEnd, double I, double sigmaS, double sigmaT,
                const HenyeyGreenstein& phase, const AffineDensity& density) {
    constexpr int kIntervals = 200000;
    const double h = tEnd / kIntervals;
    double sum = 0.0;
    for (int i = 0; i <= kIntervals; ++i) {
        const double t = i * h;
        const glm::dvec3 x = glm::dvec3(o) + t * glm::dvec3(d);
        const double r = glm::length(x);
        const double cosTheta = glm::dot(x / r, -glm::dvec3(d));
        const double D =
            opticalLength(density, glm::dvec3(0.0), x) + opticalLength(density, glm::dvec3(o), x);
        const double f =
            sigmaS * density(x) * phase.p(float(cosTheta)) * I / (r * r) * std::exp(-sigmaT * D);
        sum += f * ((i == 0 || i == kIntervals) ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    return sum * h / 3.0;
}

}  // namespace penumbra::test
