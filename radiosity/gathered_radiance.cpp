#include "radiosity/gathered_radiance.h"

#include "core/bsdf.h"
#include "core/sampler.h"
#include "core/scene.h"
#include "radiosity/coincident_faces.h"
#include "radiosity/solver_nodes.h"

#include <algorithm>
#include <optional>

namespace penumbra {

int GatheredRadiance::seenNode(const MeshedHit& y) const {
    const auto [e, side] =
        leafSideSeenAt(scene_, mesh_, exposure_.coincident(), y.point.element, y.front, y.hit.p);
    return node(e, side);
}

Color GatheredRadiance::seen(const MeshedHit& y, Sampler& sampler, uint64_t& rays) const {
    const int n = seenNode(y);
    const Color held = glm::max(radiance_.L(n) - radiance_.emission(n), Color(0.0f));
    const int e = element(n);
    const Color& rho = mesh_.rho(e);
    const Color& rhoGlossy = mesh_.rhoGlossy(e);
    if (!(maxComponent(rhoGlossy) > 0.0f))
        return held;
    // The part of `held` that came from the mesh's surfaces, rho (H + correction): its glossy
    // share, the element's as its rho is (the mean over its points), is what the lobe below
    // traces instead.
    const Color fromSurfaces = glm::max(held - rho * irradiance_.D(n), Color(0.0f));
    Color glossyShare(0.0f);
    for (int c = 0; c < 3; ++c)
        glossyShare[c] = rho[c] > 0.0f ? std::min(rhoGlossy[c] / rho[c], 1.0f) : 0.0f;
    Color L = held - glossyShare * fromSurfaces;
    const float follow = maxComponent(glossyShare);
    if (!(sampler.get1D() < follow))
        return L;
    const Bsdf bsdf = scene_.bsdf(y.hit);
    const Vec3 wo = -y.direction;
    const float uLobe = sampler.get1D();
    const std::optional<BsdfSample> bs = bsdf.sample(wo, uLobe, sampler.get2D());
    if (!bs || bs->isDelta() || !(bs->pdf > 0.0f))
        return L;
    // fGlossy over the mixture's pdf: the glossy lobes' integral, whichever strategy drew wi.
    const Color f = bsdf.fGlossy(wo, bs->wi);
    if (!(maxComponent(f) > 0.0f))
        return L;
    const std::optional<MeshedHit> z =
        firstMeshedHit(scene_, mesh_, Scene::spawnRay(y.hit, bs->wi), rays);
    if (!z)
        return L;
    const float cosine = std::abs(glm::dot(bs->wi, bsdf.shadingNormal()));
    L += f * z->transmittance * radiance_.L(seenNode(*z)) * (cosine / (bs->pdf * follow));
    return L;
}

}  // namespace penumbra
