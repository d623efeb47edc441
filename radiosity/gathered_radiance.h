// What a gather ray sees of a radiosity solution where it meets a surface the mesh holds
// (meshed_hit.h): the final gather (final_gather.h) and the corner gather (indirect_at_corners.h)
// both read the solution through it.
//
// The solution holds one radiance per leaf side: each surface reflects with its whole diffuse and
// rough glossy reflectance, spread as Lambertian (docs/radiosity.md, "What the solution
// carries"). A rough glossy surface sends its glossy share in a lobe instead: a polished floor
// reflects what lies in its mirror direction, more of it at grazing angles (Fresnel), and a metal
// reflector sends its lamp's light out in a beam. So seen() takes the Lambertian layer's share of
// the leaf side's radiance (the element's rho less its rhoGlossy, radiosity_mesh.h) and follows
// the glossy lobes one ray further, reading the solution (emission included) where that ray lands:
// a one-sample estimate of the glossy part of the reflection integral (Kajiya 1986, "The Rendering
// Equation") with the solution standing in for the radiance one bounce on, as the hybrid's reuse
// vertex follows its glossy lobes (docs/light-paths.md). The light the surface received from
// elsewhere than the mesh's surfaces, which a ray along the lobe cannot meet (the punctual lights,
// the environment, the flux deposited through specular surfaces: DirectIrradiance's D), stays
// spread as Lambertian. The lobe is followed with the probability of its largest channel's share
// and weighed by its inverse (Russian roulette, Arvo and Kirk 1990, "Particle Transport and Image
// Synthesis"): a wall whose rough coat reflects little casts an extra ray at few of its hits, a
// metal at every one.
#pragma once

#include "core/math.h"
#include "radiosity/direct_irradiance.h"
#include "radiosity/element_exposure.h"
#include "radiosity/meshed_hit.h"
#include "radiosity/radiance_hierarchy.h"
#include "radiosity/radiosity_mesh.h"

#include <cstdint>

namespace penumbra {

class Sampler;
class Scene;

class GatheredRadiance {
  public:
    // All must outlive it.
    GatheredRadiance(const Scene& scene, const RadiosityMesh& mesh, const ElementExposure& exposure,
                     const DirectIrradiance& irradiance, const RadianceHierarchy& radiance)
        : scene_(scene),
          mesh_(mesh),
          exposure_(exposure),
          irradiance_(irradiance),
          radiance_(radiance) {}

    // The reflected radiance (cd/m², emission left out) the surface at y sends back along the
    // ray: its leaf side's, flat as the solution holds it (the Gouraud-interpolated values of the
    // view mix the sides of a crease at its vertices, and their mean over an element is not the
    // element's, which the fluxes and the links use), its glossy lobes followed (above). Draws from
    // `sampler` after the ray's own dimensions; adds the rays it casts to `rays`.
    Color seen(const MeshedHit& y, Sampler& sampler, uint64_t& rays) const;

  private:
    // The leaf side node a ray meeting y sees (coincident faces resolved).
    int seenNode(const MeshedHit& y) const;

    const Scene& scene_;
    const RadiosityMesh& mesh_;
    const ElementExposure& exposure_;
    const DirectIrradiance& irradiance_;
    const RadianceHierarchy& radiance_;
};

}  // namespace penumbra
