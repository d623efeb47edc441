// Where a ray that looks at a radiosity solution meets it: the first surface along the ray that
// the solution's mesh holds, seen through the thin transparent layers (thin glass, alpha
// cut-outs) that the solvers' shadow rays pass as well (Scene::straightTransmittance). The
// radiosity view's camera rays and the final gather's rays both look this way, so that they see
// what the solver's links see.
#pragma once

#include "core/interaction.h"
#include "core/math.h"
#include "core/ray.h"
#include "radiosity/radiosity_mesh.h"

#include <cstdint>
#include <optional>

namespace penumbra {

class Scene;

struct MeshedHit {
    SurfaceHit hit;
    bool front = true;          // the side of the surface the ray meets
    Color transmittance{1.0f};  // of the layers passed on the way
    ElementPoint point;         // the leaf that holds the hit (RadiosityMesh::locate), found once
    Vec3 direction{0.0f};       // of the ray that met it
};

// Nothing when the ray leaves the scene, meets a surface the mesh does not hold and that lets no
// light straight through (solid glass: opaque and black to the solution), or passes more layers
// than Scene::transmittance() does. When the ray leaves the scene and `escaped` is given, it
// receives the transmittance of the layers passed (what the environment is seen through; zero
// otherwise). Adds the rays it traces to `rays`.
std::optional<MeshedHit> firstMeshedHit(const Scene& scene, const RadiosityMesh& mesh, Ray ray,
                                        uint64_t& rays, Color* escaped = nullptr);

}  // namespace penumbra
