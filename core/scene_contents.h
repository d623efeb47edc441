// What a scene holds that decides which passes it needs and which light paths it can have:
// analysed once per render (the planner skips passes by it, PassContext carries it to the passes).
#pragma once

#include "core/scene.h"

#include <cstddef>

namespace penumbra {

struct SceneContents {
    bool diffuse = false;   // a surface with a diffuse or rough glossy lobe (D vertices)
    bool specular = false;  // a surface with a specular (delta) lobe (S vertices)
    size_t areaLights = 0, punctualLights = 0;
};

// Classifies each mesh's material at up to 16 of its triangles (enough to meet the rough and
// smooth parts of a textured roughness, few enough for scenes of millions of triangles) and
// counts the lights.
SceneContents analyseScene(const Scene& scene);

}  // namespace penumbra
