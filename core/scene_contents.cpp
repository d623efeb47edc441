#include "core/scene_contents.h"

#include "core/bsdf.h"
#include "core/light.h"

#include <algorithm>

namespace penumbra {

namespace {

// Triangles of a mesh looked at to classify its material (scene_contents.h).
constexpr size_t kTrianglesPerMesh = 16;

}  // namespace

SceneContents analyseScene(const Scene& scene) {
    SceneContents contents;
    for (uint32_t m = 0; m < scene.meshes().size(); ++m) {
        const size_t count = scene.meshes()[m].triangles.size();
        const size_t step = std::max<size_t>(1, count / kTrianglesPerMesh);
        for (size_t t = 0; t < count && !(contents.diffuse && contents.specular); t += step) {
            const SurfaceHit hit = scene.surfaceAt(m, static_cast<uint32_t>(t), Vec3(1.0f / 3.0f));
            const Bsdf bsdf = scene.bsdf(hit);
            contents.diffuse = contents.diffuse || bsdf.hasNonDeltaLobe();
            contents.specular = contents.specular || (bsdf.lobes() & kLobeSpecular) != 0;
        }
    }
    for (const auto& light : scene.lights()) {
        if (light->kind() == LightKind::Area)
            ++contents.areaLights;
        else
            ++contents.punctualLights;
    }
    return contents;
}

}  // namespace penumbra
