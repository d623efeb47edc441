// What the image-forming tracers reuse of the view-independent passes, as interfaces that
// raytrace/ defines and passes/ implements over the products (passes/reused_products.h): the
// radiosity solution's radiance at a surface point, and the caustic photon map's estimate there.
// So raytrace/ builds on core/ alone, and the reference path tracer without the radiosity and
// caustics libraries.
#pragma once

#include "core/bsdf.h"
#include "core/interaction.h"
#include "core/math.h"

namespace penumbra {

// A view-independent solution of the diffuse light (radiosity/radiosity_solution.h), read at a
// surface point on its front (or back) side, the front being the side its counter-clockwise
// winding faces. Radiance in cd/m².
class ReusedSolution {
  public:
    virtual ~ReusedSolution() = default;
    // The diffusely reflected radiance leaving the point: light paths L D+ ending there, emission
    // excluded (RadiositySolution::radiance without emission).
    virtual Color reflected(const SurfaceHit& hit, bool front) const = 0;
    // Its indirect part, light paths L D D+ ending there (RadiositySolution::indirectRadiance):
    // the ambient term of distribution ray tracing.
    virtual Color indirect(const SurfaceHit& hit, bool front) const = 0;
    // Whether the solution reflects the sharp glossy lobes (Bsdf::hasSharpGlossyLobe) spread as
    // Lambertian, as the rough ones (RadiositySolution::spreadsSharpGlossy).
    virtual bool spreadsSharpGlossy() const { return true; }
};

// Caustic light at a surface point, estimated from photons that passed specular surfaces (the
// caustic photon map, caustics/caustic_map.h): the radiance (cd/m²) the given lobes of `bsdf`
// reflect towards wo.
class ReusedCaustics {
  public:
    virtual ~ReusedCaustics() = default;
    virtual Color radiance(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                           ReflectingLobes lobes) const = 0;
};

// The Lambertian layer's share, per channel, of the light `solution` reflects at a point of this
// BSDF towards wo: a solver reflects with the whole Bsdf::diffuseGlossyReflectance() (the rough
// glossy lobes spread as Lambertian; the sharp ones too unless it carried them by photons), the
// same in every direction, of which the Lambertian layer reflects towards wo its directional
// albedo, Bsdf::matteAlbedo(wo) (exact for uniform incident light). At grazing wo the specular
// layer above takes more: the modern hall's polished floor (roughness 0.1) seen at 84 degrees
// from its normal reflects 0.44 of the hemispherical average, matteReflectance(). A tracer that
// follows the glossy lobes itself takes only this share of reflected() or indirect().
inline Color matteShare(const Bsdf& bsdf, const Vec3& wo, const ReusedSolution& solution) {
    const Color rho = bsdf.diffuseGlossyReflectance(solution.spreadsSharpGlossy());
    const Color matte = bsdf.matteAlbedo(wo);
    Color share(0.0f);
    for (int c = 0; c < 3; ++c)
        share[c] = rho[c] > 0.0f ? matte[c] / rho[c] : 0.0f;
    return share;
}

}  // namespace penumbra
