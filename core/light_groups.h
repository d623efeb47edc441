// Light groups: the scene's light sources split into named sets (each punctual light, each
// luminaire profile, each emissive material, the environment's map and the sun) whose images
// sum to the beauty, so that a lighting designer can rebalance lighting systems after a render.
// Light transport is linear in the sources (the rendering equation's emission term), so the
// image of the whole scene is the sum of the images of the scene lit by each group alone.
#pragma once

#include "core/light_sampler.h"
#include "core/scene.h"
#include "core/scene_description.h"

#include <span>
#include <string>
#include <vector>

namespace penumbra {

struct LightGroup {
    // "light-NAME" (KHR_lights_punctual), "luminaire-NAME" (a profile's name or file),
    // "emissive-NAME" (a material), "sky" or "environment" (the map), "sun", "medium" (an
    // emitting participating medium); NAME with every
    // character other than a letter, a digit, '-' and '_' replaced by '_'. Sources whose
    // names agree share a group.
    std::string name;
    std::vector<size_t> punctualLights;  // indices into SceneDescription::lights
    std::vector<size_t> luminaires;      // ... ::luminaires
    std::vector<size_t> materials;       // ... ::materials, emissive ones
    bool environmentMap = false;         // the environment's image (a sky with its ground)
    bool sun = false;                    // the environment's sun disc
    bool medium = false;                 // the participating medium's emission
};

// The groups of `scene`'s sources, in the order of the description (punctual lights, luminaires,
// emissive materials, the map, the sun, the medium); empty for a scene without light.
std::vector<LightGroup> lightGroups(const SceneDescription& scene);

// A copy of `scene` lit by `group` alone: the other punctual lights and luminaires removed, the
// other materials' emission set to zero (their surfaces stay, so they still cast shadows), the
// environment's map black when the group lacks it, its sun removed when the group lacks it, and
// the environment removed when the group has neither, the medium's emission zero when the group
// lacks it.
SceneDescription litOnlyBy(const SceneDescription& scene, const LightGroup& group);

// The light of one render filed by group, for a tracer whose every contribution comes from one
// light (the path tracer without a reused solution): next-event estimation draws one light from
// each group (selection(), whose sets are the groups) and one direction from each part of the
// environment that has a group (its map, its sun: environmentGroup()), so each group's layer is
// about as noisy as a render of that group alone, and each contribution is added to the layer of
// its light's group. The layers sum to the image.
class LightGroupSplit {
  public:
    // The groups of `scene`'s description (lightGroups()); the scene must outlive the split.
    explicit LightGroupSplit(const Scene& scene);

    const std::vector<LightGroup>& groups() const { return groups_; }
    // The sets of the scene's lights but the environment, which the tracer samples by part.
    const LightSelection& selection() const { return selection_; }
    // The group of the environment's part, or -1 (no environment, a black map, no sun).
    int environmentGroup(EnvironmentPart part) const {
        return part == EnvironmentPart::Sun ? sunGroup_ : mapGroup_;
    }

    // Adds `value`, the light of scene light `light` (not the environment), to the entry of its
    // group in `layers` (one per group).
    void file(uint32_t light, const Color& value, std::span<Color> layers) const;
    // The same for emission seen on a surface of material `material`.
    void fileEmission(uint32_t material, const Color& value, std::span<Color> layers) const;
    // The same for the participating medium's emission.
    void fileMediumEmission(const Color& value, std::span<Color> layers) const;

  private:
    std::vector<LightGroup> groups_;
    std::vector<int> groupOfMaterial_;  // per material: its group, -1 when it emits nothing
    std::vector<int> groupOfLight_;     // per light of the scene; -1 for the environment
    int mapGroup_ = -1, sunGroup_ = -1, mediumGroup_ = -1;
    LightSelection selection_;
};

}  // namespace penumbra
