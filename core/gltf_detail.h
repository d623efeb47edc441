// Internals of the glTF loader, shared by core/gltf_*.cpp and by nothing else. This is the only
// header that includes tinygltf (CONTRIBUTING.md, "Layering").
//
// Section numbers in comments refer to the glTF 2.0 specification (Khronos, version 2.0.1,
// https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html); extension rules cite the
// extension's README in https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Khronos.
#pragma once

#include "core/scene_description.h"

#include <tiny_gltf.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::gltf {

// ---- gltf_context.cpp: the shared state and JSON helpers ---------------------------------------

// The parsed file, its name for messages, and the report being filled.
struct Context {
    const tinygltf::Model& model;
    std::string file;  // the path as given to loadGltf
    LoadReport& report;

    // Throws SceneError(file, pointer, message).
    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const;
    // Appends "file: pointer: message" to report.warnings.
    void warn(const std::string& pointer, const std::string& message) const;
};

// JSON pointer of element `index` of a top-level array: at("meshes", 3) == "/meshes/3".
std::string at(std::string_view array, size_t index);

// Typed reads from untyped JSON values (tinygltf keeps extension objects as tinygltf::Value).
// A missing key gives the fallback; a value of the wrong type is an error at pointer + "/" + key.
double numberOr(const Context& ctx, const tinygltf::Value& object, const char* key, double fallback,
                const std::string& pointer);
int indexOr(const Context& ctx, const tinygltf::Value& object, const char* key, int fallback,
            const std::string& pointer);
// An array of exactly fallback.size() numbers, or the fallback when the key is missing.
std::vector<double> numbersOr(const Context& ctx, const tinygltf::Value& object, const char* key,
                              std::vector<double> fallback, const std::string& pointer);
// The object stored under `key` in an extensions map, or nullptr.
const tinygltf::Value* extension(const tinygltf::ExtensionMap& extensions, const char* key);

// ---- gltf_environment.cpp: an environment light recorded in the scene's extras ---------------

// The environment light of scene `scene` when its `extras` record one (a converted Mitsuba
// scene's `mitsuba_environment`), its image read and checked; nothing otherwise.
std::optional<EnvironmentDesc> readSceneEnvironment(const Context& ctx, int scene);

// ---- gltf_validate.cpp: structural checks before anything is read -----------------------------

// Checks every index between top-level objects, every buffer view and accessor range, the vertex
// attribute formats of every primitive, the node hierarchy, scenes, textures, samplers and
// cameras. Data-dependent rules (index values, NaN) are checked when the data is read.
// lightCount is the number of KHR_lights_punctual lights, for the nodes' light indices.
void validateModel(const Context& ctx, size_t lightCount);

// ---- gltf_accessors.cpp: reading validated accessors -------------------------------------------

// Elements of a validated accessor, sparse substitution applied (3.6.2.3). Integer components
// marked `normalized` are mapped to [0, 1] or [-1, 1] with the equations of 3.11; other integers
// are converted to their value.
std::vector<Vec2> readVec2(const Context& ctx, int accessor);
std::vector<Vec3> readVec3(const Context& ctx, int accessor);
std::vector<Vec4> readVec4(const Context& ctx, int accessor);
// Elements of a validated SCALAR accessor of unsigned integers (vertex indices), exactly.
std::vector<uint32_t> readIndices(const Context& ctx, int accessor);

// ---- gltf_primitives.cpp: geometry -------------------------------------------------------------

// One primitive of /meshes/<mesh>, in the mesh's local space: triangles (strips and fans
// converted, degenerate ones dropped), normals (invalid ones repaired), texture coordinates and,
// when its material has a normal texture, tangents (read or generated). Mesh::material is the
// glTF material index, -1 for the default material. Empty when the primitive is skipped (points,
// lines, no POSITION), with a warning.
std::optional<Mesh> readPrimitive(const Context& ctx, int mesh, int primitive,
                                  std::span<const Material> materials);

// The local primitive placed by a node's global transform: positions by the matrix, normals by
// its inverse transpose, tangents by its upper 3x3 (handedness times the determinant's sign),
// and the winding reversed when the determinant is negative (3.7.4).
Mesh instantiate(const Mesh& local, const glm::dmat4& world);

// ---- gltf_materials.cpp: materials and textures ------------------------------------------------

// Converts every glTF material, materials[i] being /materials/i, and decodes each texture they
// use once per (image, wrap modes, colour space) into `textures`.
void loadMaterials(const Context& ctx, std::vector<Material>& materials,
                   std::vector<Texture>& textures);

// ---- gltf_lights_cameras.cpp: KHR_lights_punctual and cameras ----------------------------------

// The file's KHR_lights_punctual lights, validated, in their node's frame (at the origin,
// shining along -Z); index i is light i of the extension.
std::vector<PunctualLightDesc> readLights(const Context& ctx);
// The light index a node refers to through KHR_lights_punctual, or -1.
int nodeLight(const Context& ctx, int node);
// A light placed by its node's global transform.
PunctualLightDesc placeLight(PunctualLightDesc light, const glm::dmat4& world);
// /cameras/<camera> placed by its node's global transform.
CameraDesc placeCamera(const Context& ctx, int camera, const glm::dmat4& world, int node);
// The rotation of a node's global transform, its scale removed, for what looks along its -Z
// (`what`, a camera or a luminaire, names it in the warning a mirroring transform gets).
glm::dmat3 nodeRotation(const Context& ctx, const glm::dmat4& world, int node,
                        const std::string& what);

// ---- gltf_luminaires.cpp: EXT_lights_ies -------------------------------------------------------

// A light profile of the file, read and checked.
struct LuminaireProfile {
    std::string name;
    std::shared_ptr<const CandelaTable> table;
};
// The file's EXT_lights_ies profiles (index i is profile i of the extension); a profile that
// cannot be read fails at its place, with the profile's own file and line.
std::vector<LuminaireProfile> readLuminaireProfiles(const Context& ctx);
// The luminaire a node places through EXT_lights_ies, by its global transform; nothing when the
// node has none.
std::optional<LuminaireDesc> nodeLuminaire(const Context& ctx, int node,
                                           const std::vector<LuminaireProfile>& profiles,
                                           const glm::dmat4& world);

}  // namespace penumbra::gltf
