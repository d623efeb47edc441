// The glTF 2.0 loader: the first stage of scene loading (CONTRIBUTING.md, "Layering").
#pragma once

#include "core/scene_description.h"

#include <string>

namespace penumbra {

// Reads a glTF 2.0 asset, a .gltf (with its external .bin and image files resolved relative to it,
// or data URIs) or a .glb, checks it against the specification, and flattens the node hierarchy
// of one scene to world space.
//
// sceneIndex -1 loads the file's `scene`, or scene 0 when the file names none.
// Supported extensions: KHR_lights_punctual, KHR_materials_emissive_strength,
// KHR_materials_specular, KHR_materials_ior, KHR_materials_transmission, KHR_materials_volume,
// KHR_texture_transform. Other extensions are ignored (and listed in the report) unless the file
// requires them, which is an error.
//
// Throws SceneError("<path>", "<JSON pointer>", message) for anything that cannot be read or that
// breaks the specification. Lesser problems (skipped point and line primitives, dropped degenerate
// triangles, repaired normals) are listed in SceneDescription::report.warnings.
SceneDescription loadGltf(const std::string& path, int sceneIndex = -1);

}  // namespace penumbra
