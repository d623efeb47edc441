#include "raytrace/tracing_steps.h"

#include "core/material.h"

namespace penumbra {

void recordFirstHit(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                    const Vec3& cameraOrigin, FirstHit* firstHit) {
    if (!firstHit || firstHit->valid)
        return;
    firstHit->valid = true;
    firstHit->albedo = evaluateMaterial(scene.material(hit), scene.textures(), hit.uv).baseColor;
    firstHit->normal = bsdf.shadingNormal();
    firstHit->depth = glm::distance(hit.p, cameraOrigin);
}

}  // namespace penumbra
