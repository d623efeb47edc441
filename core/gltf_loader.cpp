// The glTF loader's top level: parse the file with tinygltf, check the required extensions,
// validate, and flatten the chosen scene's node hierarchy into a SceneDescription.
#include "core/gltf_loader.h"

#include "core/errors.h"
#include "core/gltf_detail.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <utility>

namespace penumbra {
namespace {

using gltf::at;
using gltf::Context;

constexpr std::array<std::string_view, 8> kSupportedExtensions = {
    "KHR_lights_punctual",        "KHR_materials_emissive_strength",
    "KHR_materials_specular",     "KHR_materials_ior",
    "KHR_materials_transmission", "KHR_materials_volume",
    "KHR_texture_transform",      "EXT_lights_ies"};

bool isSupported(const std::string& extension) {
    return std::find(kSupportedExtensions.begin(), kSupportedExtensions.end(), extension) !=
           kSupportedExtensions.end();
}

template <typename Range>
std::string join(const Range& names) {
    std::string out;
    for (const auto& name : names)
        out += (out.empty() ? "" : ", ") + std::string(name);
    return out;
}

// A line of tinygltf's output, without trailing space and cut short: tinygltf quotes whole data
// URIs, which can be megabytes long.
std::string shorten(std::string line) {
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back())))
        line.pop_back();
    constexpr size_t kMax = 200;
    if (line.size() > kMax)
        line = line.substr(0, kMax) + "...";
    return line;
}

// A GLB file starts with the magic "glTF" (chapter 4, "Header"), whatever its name.
bool isBinary(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    char magic[4] = {};
    in.read(magic, sizeof magic);
    return in.gcount() == sizeof magic && std::equal(magic, magic + 4, "glTF");
}

// Parses the file with tinygltf, which also loads the buffers and decodes the images. Its
// errors become SceneErrors without a JSON pointer (tinygltf does not say where); its warnings
// (e.g. an image file that is missing) go to the report.
tinygltf::Model parse(const std::string& path, LoadReport& report) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        throw SceneError(path, "", "file not found");
    tinygltf::TinyGLTF loader;
    // Keeps each object's `extras` as JSON text, for SceneDescription::sceneExtrasJson.
    loader.SetStoreOriginalJSONForExtrasAndExtensions(true);
    tinygltf::Model model;
    std::string err, warn;
    const bool ok = isBinary(path) ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                   : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    // tinygltf reports some violations (e.g. a primitive without attributes) in `err` while
    // still returning true.
    if (!ok || !err.empty())
        throw SceneError(path, "", "cannot load: " + shorten(err));
    std::istringstream lines(warn);
    for (std::string line; std::getline(lines, line);) {
        if (!line.empty())
            report.warnings.push_back(path + ": " + shorten(line));
    }
    return model;
}

// A glTF version, "<major>.<minor>" (the schema's pattern for asset.version, ^[0-9]+\.[0-9]+$),
// as (major, minor); nothing if the text is not one.
std::optional<std::pair<int, int>> gltfVersion(const std::string& text) {
    const size_t dot = text.find('.');
    const auto digits = [](std::string_view s) {
        return !s.empty() && s.size() <= 9 &&
               std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    if (dot == std::string::npos || !digits(std::string_view(text).substr(0, dot)) ||
        !digits(std::string_view(text).substr(dot + 1)))
        return std::nullopt;
    return std::pair(std::stoi(text.substr(0, dot)), std::stoi(text.substr(dot + 1)));
}

// penumbra reads glTF 2.0. The asset's version says which glTF it targets and its minVersion,
// if any, the least a loader must support to load it, at most the version itself (the
// specification's "Asset"). A 2.x file without a minVersion above 2.0 loads as 2.0, as the
// Khronos glTF-Asset-Generator's "Compatibility" models expect of a 2.0 client; anything else
// is refused rather than read as 2.0.
void checkVersion(const Context& ctx) {
    const std::string& text = ctx.model.asset.version;
    const std::optional<std::pair<int, int>> version = gltfVersion(text);
    if (!version)
        ctx.fail("/asset/version", "\"" + text + "\" is not a glTF version (<major>.<minor>)");
    if (version->first != 2)
        ctx.fail("/asset/version", "the file is glTF " + text +
                                       "; penumbra reads glTF 2.0 (convert it first, e.g. with "
                                       "gltf-pipeline)");
    const std::string& least = ctx.model.asset.minVersion;
    if (least.empty())
        return;
    const std::optional<std::pair<int, int>> minimum = gltfVersion(least);
    if (!minimum)
        ctx.fail("/asset/minVersion", "\"" + least + "\" is not a glTF version (<major>.<minor>)");
    if (*minimum > *version)
        ctx.fail("/asset/minVersion", "minVersion " + least + " is greater than the version, " +
                                          text + ", which the specification forbids");
    if (*minimum > std::pair(2, 0))
        ctx.fail("/asset/minVersion",
                 "the file needs a glTF " + least + " loader; penumbra reads glTF 2.0");
}

// "All glTF extensions required to load and/or render an asset MUST be listed in the top-level
// extensionsRequired array" (3.12): refuse the file if one of them is not supported.
void checkExtensions(const Context& ctx) {
    std::vector<std::string> unsupported;
    for (const std::string& name : ctx.model.extensionsRequired) {
        if (!isSupported(name))
            unsupported.push_back(name);
    }
    if (!unsupported.empty()) {
        ctx.fail("/extensionsRequired", "unsupported required extension(s) " + join(unsupported) +
                                            "; penumbra supports " + join(kSupportedExtensions));
    }
    for (const std::string& name : ctx.model.extensionsUsed) {
        (isSupported(name) ? ctx.report.extensionsUsed : ctx.report.extensionsIgnored)
            .push_back(name);
    }
}

// The requested scene; by default the file's `scene` (3.5.1), else the first.
int chooseScene(const Context& ctx, int sceneIndex) {
    const int count = static_cast<int>(ctx.model.scenes.size());
    const std::string range = "the file has " + std::to_string(count) + " scenes";
    if (sceneIndex >= 0) {
        if (sceneIndex >= count) {
            ctx.fail("/scenes", "scene " + std::to_string(sceneIndex) + " requested, but " + range);
        }
        return sceneIndex;
    }
    if (count == 0)
        ctx.fail("/scenes", "the file has no scene to load");
    const int chosen = std::max(ctx.model.defaultScene, 0);
    if (chosen >= count)
        ctx.fail("/scene", "scene " + std::to_string(chosen) + " is out of range: " + range);
    return chosen;
}

// A node's local transform: its matrix (column-major, as GLM's), or T * R * S (3.5.3).
glm::dmat4 localTransform(const tinygltf::Node& n) {
    if (n.matrix.size() == 16)
        return glm::make_mat4(n.matrix.data());
    glm::dmat4 m(1.0);
    if (!n.translation.empty())
        m = glm::translate(m, glm::make_vec3(n.translation.data()));
    if (!n.rotation.empty()) {
        // glTF stores (x, y, z, w); glm's quaternion constructor takes w first. Normalising
        // absorbs the rounding of exporters (validateModel rejected near-zero quaternions).
        const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
        m *= glm::mat4_cast(glm::normalize(q));
    }
    if (!n.scale.empty())
        m = glm::scale(m, glm::make_vec3(n.scale.data()));
    return m;
}

// Walks the trees of one scene, composing parent * child transforms (3.5.3), and appends every
// primitive, light and camera the nodes place. A mesh used by several nodes gives several Mesh
// entries; each glTF primitive is read once and then transformed per node.
class SceneFlattener {
  public:
    SceneFlattener(const Context& ctx, std::vector<PunctualLightDesc> lights,
                   std::vector<gltf::LuminaireProfile> profiles, SceneDescription& desc)
        : ctx_(ctx),
          lights_(std::move(lights)),
          profiles_(std::move(profiles)),
          desc_(desc),
          local_(ctx.model.meshes.size()),
          loaded_(ctx.model.meshes.size(), false) {}

    void flatten(int scene);

  private:
    glm::dvec3 boundsCenter(const std::vector<std::pair<int, glm::dmat4>>& placed);
    void visit(int node, const glm::dmat4& world);
    void addMesh(int mesh, const glm::dmat4& world);
    const std::vector<std::optional<Mesh>>& primitives(int mesh);
    int defaultMaterial();

    const Context& ctx_;
    const std::vector<PunctualLightDesc> lights_;
    const std::vector<gltf::LuminaireProfile> profiles_;
    SceneDescription& desc_;
    std::vector<std::vector<std::optional<Mesh>>> local_;  // per glTF mesh, in local space
    std::vector<bool> loaded_;
    int defaultMaterial_ = -1;
};

void SceneFlattener::flatten(int scene) {
    // Depth-first with an explicit stack (deep hierarchies must not overflow the call stack);
    // children are pushed in reverse so that they come out in file order.
    std::vector<std::pair<int, glm::dmat4>> stack;
    std::vector<std::pair<int, glm::dmat4>> placed;  // visited nodes with their world matrices
    const std::vector<int>& roots = ctx_.model.scenes[scene].nodes;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it)
        stack.emplace_back(*it, glm::dmat4(1.0));
    while (!stack.empty()) {
        const auto [node, parent] = stack.back();
        stack.pop_back();
        const glm::dmat4 world = parent * localTransform(ctx_.model.nodes[node]);
        // Normals and winding need an invertible transform; a zero scale hides the subtree.
        const double det = glm::determinant(glm::dmat3(world));
        if (!(std::abs(det) > 0.0) || !std::isfinite(det)) {
            ctx_.warn(at("nodes", node),
                      "singular transform (zero scale); node and descendants skipped");
            continue;
        }
        placed.emplace_back(node, world);
        const std::vector<int>& children = ctx_.model.nodes[node].children;
        for (auto it = children.rbegin(); it != children.rend(); ++it)
            stack.emplace_back(*it, world);
    }
    // Rebase the world on the centre of the geometry, computed in double precision, before
    // anything is rounded to float: a model placed at 1e5 m (site coordinates) then keeps the
    // sub-millimetre precision it has near the origin, instead of float's 8 mm steps there.
    desc_.origin = boundsCenter(placed);
    const glm::dmat4 rebase = glm::translate(glm::dmat4(1.0), -desc_.origin);
    for (const auto& [node, world] : placed)
        visit(node, rebase * world);
}

// Centre of the world-space bounding box of all placed meshes (the transformed corners of each
// primitive's local box), or the origin when nothing is placed.
glm::dvec3 SceneFlattener::boundsCenter(const std::vector<std::pair<int, glm::dmat4>>& placed) {
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (const auto& [node, world] : placed) {
        const int mesh = ctx_.model.nodes[node].mesh;
        if (mesh < 0)
            continue;
        for (const std::optional<Mesh>& local : primitives(mesh)) {
            if (!local || local->positions.empty())
                continue;
            glm::dvec3 localLo(local->positions.front()), localHi(localLo);
            for (const Vec3& p : local->positions) {
                localLo = glm::min(localLo, glm::dvec3(p));
                localHi = glm::max(localHi, glm::dvec3(p));
            }
            for (int corner = 0; corner < 8; ++corner) {
                const glm::dvec3 c((corner & 1) ? localHi.x : localLo.x,
                                   (corner & 2) ? localHi.y : localLo.y,
                                   (corner & 4) ? localHi.z : localLo.z);
                const glm::dvec3 w(world * glm::dvec4(c, 1.0));
                lo = glm::min(lo, w);
                hi = glm::max(hi, w);
            }
        }
    }
    return lo.x <= hi.x ? 0.5 * (lo + hi) : glm::dvec3(0.0);
}

void SceneFlattener::visit(int node, const glm::dmat4& world) {
    const tinygltf::Node& n = ctx_.model.nodes[node];
    if (n.mesh >= 0) {
        if (n.skin >= 0) {
            ctx_.warn(at("nodes", node), "skinning is not supported; mesh placed by the node");
        }
        addMesh(n.mesh, world);
    }
    if (n.camera >= 0)
        desc_.cameras.push_back(gltf::placeCamera(ctx_, n.camera, world, node));
    if (const int light = gltf::nodeLight(ctx_, node); light >= 0) {
        desc_.lights.push_back(gltf::placeLight(lights_[light], world));
    }
    if (std::optional<LuminaireDesc> luminaire = gltf::nodeLuminaire(ctx_, node, profiles_, world))
        desc_.luminaires.push_back(std::move(*luminaire));
}

void SceneFlattener::addMesh(int mesh, const glm::dmat4& world) {
    for (const std::optional<Mesh>& local : primitives(mesh)) {
        if (!local)
            continue;
        Mesh placed = gltf::instantiate(*local, world);
        // "If material is undefined, then a default material MUST be used" (3.7.2.1).
        if (placed.material < 0)
            placed.material = defaultMaterial();
        desc_.meshes.push_back(std::move(placed));
    }
}

const std::vector<std::optional<Mesh>>& SceneFlattener::primitives(int mesh) {
    if (!loaded_[mesh]) {
        const int count = static_cast<int>(ctx_.model.meshes[mesh].primitives.size());
        for (int k = 0; k < count; ++k) {
            local_[mesh].push_back(gltf::readPrimitive(ctx_, mesh, k, desc_.materials));
        }
        loaded_[mesh] = true;
    }
    return local_[mesh];
}

// The default material (3.9.6) is the default-constructed Material, whose values are the
// specification's defaults; it is appended once, after the file's materials.
int SceneFlattener::defaultMaterial() {
    if (defaultMaterial_ < 0) {
        Material m;
        m.name = "default";
        desc_.materials.push_back(std::move(m));
        defaultMaterial_ = static_cast<int>(desc_.materials.size()) - 1;
    }
    return defaultMaterial_;
}

}  // namespace

SceneDescription loadGltf(const std::string& path, int sceneIndex) {
    SceneDescription desc;
    desc.file = path;
    const tinygltf::Model model = parse(path, desc.report);
    const Context ctx{model, path, desc.report};
    checkVersion(ctx);
    checkExtensions(ctx);
    std::vector<PunctualLightDesc> lights = gltf::readLights(ctx);
    gltf::validateModel(ctx, lights.size());
    const int scene = chooseScene(ctx, sceneIndex);
    gltf::loadMaterials(ctx, desc.materials, desc.textures);
    SceneFlattener(ctx, std::move(lights), gltf::readLuminaireProfiles(ctx), desc).flatten(scene);
    desc.environment = gltf::readSceneEnvironment(ctx, scene);
    desc.sceneExtrasJson = model.scenes[scene].extras_json_string;
    return desc;
}

}  // namespace penumbra
