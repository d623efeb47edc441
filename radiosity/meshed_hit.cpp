#include "radiosity/meshed_hit.h"

#include "core/scene.h"
#include "radiosity/radiosity_mesh.h"

namespace penumbra {

std::optional<MeshedHit> firstMeshedHit(const Scene& scene, const RadiosityMesh& mesh, Ray ray,
                                        uint64_t& rays, Color* escaped) {
    Color transmittance(1.0f);
    if (escaped)
        *escaped = Color(0.0f);
    for (int layer = 0; layer <= Scene::kMaxTransparentLayers; ++layer) {
        ++rays;
        const std::optional<SurfaceHit> hit = scene.intersect(ray);
        if (!hit) {
            if (escaped)
                *escaped = transmittance;
            return std::nullopt;
        }
        const ElementPoint point = mesh.locate(hit->mesh, hit->triangle, hit->barycentric);
        if (point.element >= 0)
            return MeshedHit{*hit, hit->frontFace(ray.d), transmittance, point, ray.d};
        transmittance *= scene.straightTransmittance(*hit, scene.bsdf(*hit), -ray.d);
        if (!(maxComponent(transmittance) > 0.0f))
            return std::nullopt;
        ray = Scene::spawnRay(*hit, ray.d);
    }
    return std::nullopt;
}

}  // namespace penumbra
