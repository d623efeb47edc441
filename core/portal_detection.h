// Finds an interior's openings to its environment (windows, skylights, open doors) as portals
// (core/portals.h), for a user who does not know their corners: `--portal auto`.
//
// From points on the scene's surfaces that are mostly enclosed, rays go out in every direction;
// those that leave the scene left it through an opening. Each such ray's crossing of the opening
// is found on the plane of the wall around it: rays turned a little off it hit that wall, facing
// them, and the crossing is where the escaping ray meets that wall's plane. The crossings are
// grouped by wall (parallel planes a few centimetres apart: a window's frame, sashes and
// glazing bars), followed along their rays to the wall's outermost plane, grouped by distance there
// (dense crowds only), and each group's rectangle, a little enlarged, is a portal. The environment
// light keeps a quarter of its samples on its own distribution (core/environment_light.h), so a
// portal that is too small, too large or misplaced costs noise, never correctness.
#pragma once

#include "core/portals.h"
#include "core/scene.h"

#include <vector>

namespace penumbra {

struct PortalDetectionSettings {
    int origins = 2048;           // points sampled on the surfaces first (those enclosed are kept)
    int targetCrossings = 4000;   // more points until this many rays found an opening...
    int maxOrigins = 32768;       // ...or this many points were tried
    int raysPerOrigin = 32;       // directions from each kept point, uniform on the sphere
    float enclosedShare = 0.75f;  // a point is inside when this share of directions hit
    int maxPortals = 32;
};

// The openings of `scene` (its geometry only; its lights are not used), largest first; none for
// a scene with no enclosed points or no openings. Deterministic.
std::vector<Portal> detectPortals(const Scene& scene, const PortalDetectionSettings& settings = {});

}  // namespace penumbra
