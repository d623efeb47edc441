#include "core/light_groups.h"

#include <algorithm>
#include <cctype>

namespace penumbra {

namespace {

std::string groupName(const std::string& kind, const std::string& source) {
    std::string name = kind + "-" + source;
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_')
            c = '_';
    }
    return name;
}

// The group called `name`, added at the end when there is none yet.
LightGroup& groupCalled(std::vector<LightGroup>& groups, const std::string& name) {
    const auto found = std::find_if(groups.begin(), groups.end(),
                                    [&name](const LightGroup& g) { return g.name == name; });
    if (found != groups.end())
        return *found;
    LightGroup group;
    group.name = name;
    groups.push_back(std::move(group));
    return groups.back();
}

bool contains(const std::vector<size_t>& indices, size_t i) {
    return std::find(indices.begin(), indices.end(), i) != indices.end();
}

// A sky made by penumbra (--sky, or the ground's glow under a sun alone) is named "sky"; an
// image the user gave, "environment".
std::string mapGroupName(const EnvironmentDesc& environment) {
    const std::string& file = environment.file;
    const bool sky = file.rfind("sky ", 0) == 0 || file.rfind("no sky", 0) == 0;
    return sky ? "sky" : "environment";
}

bool mapIsBlack(const EnvironmentDesc& environment) {
    const auto pixels = environment.radiance.pixels();
    return std::all_of(pixels.begin(), pixels.end(), [](float v) { return v == 0.0f; });
}

}  // namespace

std::vector<LightGroup> lightGroups(const SceneDescription& scene) {
    std::vector<LightGroup> groups;
    for (size_t i = 0; i < scene.lights.size(); ++i)
        groupCalled(groups, groupName("light", scene.lights[i].name)).punctualLights.push_back(i);
    for (size_t i = 0; i < scene.luminaires.size(); ++i) {
        groupCalled(groups, groupName("luminaire", scene.luminaires[i].name))
            .luminaires.push_back(i);
    }
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& material = scene.materials[i];
        if (!material.isEmissive())
            continue;
        const std::string source =
            material.name.empty() ? "material_" + std::to_string(i) : material.name;
        groupCalled(groups, groupName("emissive", source)).materials.push_back(i);
    }
    if (scene.environment) {
        if (!mapIsBlack(*scene.environment))
            groupCalled(groups, mapGroupName(*scene.environment)).environmentMap = true;
        if (scene.environment->sun && scene.environment->sun->directNormalIlluminance > 0.0f)
            groupCalled(groups, "sun").sun = true;
    }
    for (const MediumDesc& medium : scene.media) {
        if (maxComponent(medium.emission) > 0.0f)
            groupCalled(groups, "medium").medium = true;
    }
    return groups;
}

SceneDescription litOnlyBy(const SceneDescription& scene, const LightGroup& group) {
    SceneDescription lit = scene;
    lit.lights.clear();
    for (const size_t i : group.punctualLights)
        lit.lights.push_back(scene.lights.at(i));
    lit.luminaires.clear();
    for (const size_t i : group.luminaires)
        lit.luminaires.push_back(scene.luminaires.at(i));
    for (size_t i = 0; i < lit.materials.size(); ++i) {
        if (!contains(group.materials, i)) {
            lit.materials[i].emissive = Color(0.0f);
            lit.materials[i].emissiveTexture = TextureRef{};
        }
    }
    if (lit.environment) {
        if (!group.environmentMap && !group.sun) {
            lit.environment.reset();
        } else {
            if (!group.environmentMap) {
                for (float& v : lit.environment->radiance.pixels())
                    v = 0.0f;
            }
            if (!group.sun)
                lit.environment->sun.reset();
        }
    }
    if (!group.medium) {
        for (MediumDesc& medium : lit.media)
            medium.emission = Color(0.0f);
    }
    return lit;
}

namespace {

// Each light's set in a LightGroupSplit's selection: its group's index; none for the environment,
// which the tracer samples by part, and for a light of no group (none sends light).
std::vector<uint32_t> selectionSets(const std::vector<int>& groupOfLight) {
    std::vector<uint32_t> sets;
    for (const int group : groupOfLight)
        sets.push_back(group >= 0 ? uint32_t(group) : LightSelection::kNoSet);
    return sets;
}

}  // namespace

LightGroupSplit::LightGroupSplit(const Scene& scene) : groups_(lightGroups(scene.description())) {
    const SceneDescription& description = scene.description();
    groupOfMaterial_.assign(description.materials.size(), -1);
    std::vector<int> groupOfPunctual(description.lights.size(), -1);
    std::vector<int> groupOfLuminaire(description.luminaires.size(), -1);
    for (size_t g = 0; g < groups_.size(); ++g) {
        const LightGroup& group = groups_[g];
        for (const size_t i : group.punctualLights)
            groupOfPunctual[i] = int(g);
        for (const size_t i : group.luminaires)
            groupOfLuminaire[i] = int(g);
        for (const size_t i : group.materials)
            groupOfMaterial_[i] = int(g);
        if (group.environmentMap)
            mapGroup_ = int(g);
        if (group.sun)
            sunGroup_ = int(g);
        if (group.medium)
            mediumGroup_ = int(g);
    }
    using Kind = Scene::LightOrigin::Kind;
    for (size_t i = 0; i < scene.lights().size(); ++i) {
        const Scene::LightOrigin& origin = scene.lightOrigin(i);
        groupOfLight_.push_back(origin.kind == Kind::Punctual    ? groupOfPunctual[origin.index]
                                : origin.kind == Kind::Luminaire ? groupOfLuminaire[origin.index]
                                : origin.kind == Kind::Emissive  ? groupOfMaterial_[origin.index]
                                                                 : -1);
    }
    selection_ = LightSelection(scene.lights(), selectionSets(groupOfLight_));
}

void LightGroupSplit::file(uint32_t light, const Color& value, std::span<Color> layers) const {
    if (groupOfLight_[light] >= 0)
        layers[size_t(groupOfLight_[light])] += value;
}

void LightGroupSplit::fileMediumEmission(const Color& value, std::span<Color> layers) const {
    if (mediumGroup_ >= 0)
        layers[size_t(mediumGroup_)] += value;
}

void LightGroupSplit::fileEmission(uint32_t material, const Color& value,
                                   std::span<Color> layers) const {
    if (groupOfMaterial_[material] >= 0)
        layers[size_t(groupOfMaterial_[material])] += value;
}

}  // namespace penumbra
