#include "core/scene_contents.h"

#include "core/bsdf.h"
#include "core/light.h"

#include <algorithm>
#include <optional>
#include <vector>

namespace penumbra {

namespace {

// Triangles of a mesh looked at to classify its material (scene_contents.h).
constexpr size_t kTrianglesPerMesh = 16;

// Stratified light samples per light and specular mesh for the solid angle (lightSolidAngle).
constexpr int kSolidAngleSamples = 4;

// An area light as seen from p, unoccluded: the solid angle it subtends, the mean of 1 / pdf over
// directions sampled with its own solid-angle pdf (E_p[1 / p] is the measure of p's support),
// and the mean squared distance to its sampled points.
struct LightView {
    double solidAngle = 0.0, distance2 = 0.0;
};

LightView viewOf(const Light& light, const Vec3& p) {
    LightView view;
    int found = 0;
    for (int i = 0; i < kSolidAngleSamples; ++i) {
        const Vec2 u((i % 2 + 0.5f) / 2.0f, (i / 2 + 0.5f) / 2.0f);
        const std::optional<LightLiSample> s = light.sampleLi(LightSampleContext{p}, u);
        if (!s || !(s->pdf > 0.0f))
            continue;
        view.solidAngle += 1.0 / s->pdf;
        view.distance2 += glm::dot(s->pLight - p, s->pLight - p);
        ++found;
    }
    view.solidAngle = std::min(view.solidAngle / kSolidAngleSamples, 4.0 * kPi);
    view.distance2 = found > 0 ? view.distance2 / found : 0.0;
    return view;
}

// SceneContents::lightSolidAngleAtSpecular.
float lightSolidAngleAtSpecular(const Scene& scene, const std::vector<Sphere>& specularMeshes) {
    double weighted = 0.0, weights = 0.0;
    for (const Sphere& target : specularMeshes) {
        double solidAngle = 0.0, reaching = 0.0;
        for (const auto& light : scene.lights()) {
            if (light->kind() != LightKind::Area)
                continue;
            const LightView view = viewOf(*light, target.center);
            if (!(view.distance2 > 0.0))
                continue;
            solidAngle += view.solidAngle;
            // The fraction of the light's sky the sphere covers, as the caustic photons are
            // aimed (caustics/photon_tracer.h).
            const double covered = std::min(double(sqr(target.radius)) / view.distance2, 1.0);
            reaching += luminance(light->power()) * covered;
        }
        weighted += reaching * solidAngle;
        weights += reaching;
    }
    return weights > 0.0 ? static_cast<float>(weighted / weights) : 0.0f;
}

}  // namespace

Sphere boundingSphere(const Mesh& mesh) {
    Bounds3 bounds;
    for (const Vec3& p : mesh.positions)
        bounds.extend(p);
    Sphere s{bounds.center(), 0.0f};
    for (const Vec3& p : mesh.positions)
        s.radius = std::max(s.radius, glm::distance(p, s.center));
    return s;
}

SceneContents analyseScene(const Scene& scene) {
    SceneContents contents;
    std::vector<Sphere> specularMeshes;
    for (uint32_t m = 0; m < scene.meshes().size(); ++m) {
        const size_t count = scene.meshes()[m].triangles.size();
        const size_t step = std::max<size_t>(1, count / kTrianglesPerMesh);
        bool specular = false;
        for (size_t t = 0; t < count; t += step) {
            const SurfaceHit hit = scene.surfaceAt(m, static_cast<uint32_t>(t), Vec3(1.0f / 3.0f));
            const Bsdf bsdf = scene.bsdf(hit);
            contents.diffuse = contents.diffuse || bsdf.hasNonDeltaLobe();
            contents.sharpGlossy = contents.sharpGlossy || bsdf.hasSharpGlossyLobe();
            specular = specular || (bsdf.lobes() & kLobeSpecular) != 0;
        }
        if (specular)
            specularMeshes.push_back(boundingSphere(scene.meshes()[m]));
        contents.specular = contents.specular || specular;
    }
    for (const auto& light : scene.lights()) {
        if (light->kind() == LightKind::Area)
            ++contents.areaLights;
        else if (light->kind() == LightKind::Environment)
            contents.environment = true;
        else
            ++contents.punctualLights;
    }
    contents.medium = scene.medium() != nullptr;
    contents.mediumScatters = contents.medium && scene.medium()->scatters();
    contents.mediumEmits = contents.medium && scene.medium()->emits();
    contents.lightSolidAngleAtSpecular = lightSolidAngleAtSpecular(scene, specularMeshes);
    return contents;
}

}  // namespace penumbra
