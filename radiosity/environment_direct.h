// The environment light's direct light at a point of a meshed surface, for the given part D of
// the solvers (element_sampling.h's punctualDirect: an element's mean) and for the view's corners
// (point_direct.h): E = integral over the hemisphere about n of L(w) T(w) cos(theta) dw, L the
// environment's radiance (core/environment_light.h) and T the transmittance of a ray leaving the
// scene that way (blocked by walls, passed by thin glass); D = E / pi, cd/m².
//
// Two strategies with `count` directions each: the environment's own distribution (its bright
// sky and sun) and the cosine-weighted hemisphere (the part of the sky a window shows, which the
// environment's distribution does not know about), combined by the balance heuristic in its
// multi-sample form, sum over both of f / (count p_env + count p_cos) (Veach 1997, section 9.2.2,
// Eq. 9.10 with n_1 = n_2). Directions are points [first, first + count) of Owen-scrambled
// (0,2)-sequences (core/sampler.h) keyed by (seed, key): a caller that gives every point the
// same key and first (the view's corners) gets the same directions at every point, so the field
// is smooth; one that gives each point of an element its own range (the element means)
// stratifies the directions over the element.
#pragma once

#include "core/math.h"
#include "radiosity/element_sampling.h"

#include <cstdint>

namespace penumbra {

class Scene;

// D at x on the side n faces (x.n or -x.n); zero without an environment. Adds the rays it casts
// (at most 2 count) to `rays`.
Color environmentD(const Scene& scene, const ElementSample& x, const Vec3& n, uint32_t seed,
                   IVec2 key, uint32_t first, uint32_t count, uint64_t& rays);

}  // namespace penumbra
