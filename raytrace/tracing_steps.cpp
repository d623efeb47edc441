#include "raytrace/tracing_steps.h"

#include "core/material.h"

namespace penumbra {

void recordSurfaceGuide(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf, float depth,
                        SurfaceGuide& guide) {
    guide.valid = true;
    guide.albedo = evaluateMaterial(scene.material(hit), scene.textures(), hit.uv).baseColor;
    guide.normal = bsdf.shadingNormal();
    guide.depth = depth;
}

void recordFirstHit(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                    const Vec3& cameraOrigin, FirstHit* firstHit) {
    if (!firstHit || firstHit->valid)
        return;
    recordSurfaceGuide(scene, hit, bsdf, glm::distance(hit.p, cameraOrigin), *firstHit);
    firstHit->position = hit.p;
    firstHit->viewerSideNormal = glm::dot(hit.ng, cameraOrigin - hit.p) < 0.0f ? -hit.ng : hit.ng;
}

}  // namespace penumbra
