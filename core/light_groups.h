// Light groups: the scene's light sources split into named sets (each punctual light, each
// luminaire profile, each emissive material, the environment's map and the sun) whose images
// sum to the beauty, so that a lighting designer can rebalance lighting systems after a render.
// Light transport is linear in the sources (the rendering equation's emission term), so the
// image of the whole scene is the sum of the images of the scene lit by each group alone.
#pragma once

#include "core/scene_description.h"

#include <string>
#include <vector>

namespace penumbra {

struct LightGroup {
    // "light-NAME" (KHR_lights_punctual), "luminaire-NAME" (a profile's name or file),
    // "emissive-NAME" (a material), "sky" or "environment" (the map), "sun"; NAME with every
    // character other than a letter, a digit, '-' and '_' replaced by '_'. Sources whose
    // names agree share a group.
    std::string name;
    std::vector<size_t> punctualLights;  // indices into SceneDescription::lights
    std::vector<size_t> luminaires;      // ... ::luminaires
    std::vector<size_t> materials;       // ... ::materials, emissive ones
    bool environmentMap = false;         // the environment's image (a sky with its ground)
    bool sun = false;                    // the environment's sun disc
};

// The groups of `scene`'s sources, in the order of the description (punctual lights, luminaires,
// emissive materials, the map, the sun); empty for a scene without light.
std::vector<LightGroup> lightGroups(const SceneDescription& scene);

// A copy of `scene` lit by `group` alone: the other punctual lights and luminaires removed, the
// other materials' emission set to zero (their surfaces stay, so they still cast shadows), the
// environment's map black when the group lacks it, its sun removed when the group lacks it, and
// the environment removed when the group has neither.
SceneDescription litOnlyBy(const SceneDescription& scene, const LightGroup& group);

}  // namespace penumbra
