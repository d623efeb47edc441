#include "core/surface_crossing.h"

#include "core/material.h"
#include "core/sampler.h"

namespace penumbra {

bool insideSolid(const Scene& scene, const SurfaceHit& hit, const Vec3& direction) {
    return !scene.material(hit).thinWalled() && !hit.frontFace(direction);
}

Color volumeAttenuation(const Scene& scene, const SurfaceHit& hit, const Vec3& direction) {
    if (!insideSolid(scene, hit, direction))
        return Color(1.0f);
    return glm::exp(-scene.material(hit).absorption() * hit.t);
}

Color segmentAttenuation(const Scene& scene, const Ray& ray, const SurfaceHit* hit) {
    if (hit && insideSolid(scene, *hit, ray.d))
        return volumeAttenuation(scene, *hit, ray.d);
    const Medium* medium = scene.medium();
    return medium ? medium->transmittance(ray, hit ? hit->t : INFINITY) : Color(1.0f);
}

StraightThrough chooseStraightThrough(const Scene& scene, const SurfaceHit& hit, const Bsdf& bsdf,
                                      const Vec3& wo, Sampler& sampler) {
    const Color through = scene.straightTransmittance(hit, bsdf, wo);
    if (!(maxComponent(through) > 0.0f))
        return {};
    const float q = glm::min(maxComponent(through), 1.0f);
    if (sampler.get1D() < q)
        return {true, through / q};
    return {false, Color(1.0f / (1.0f - q))};
}

}  // namespace penumbra
