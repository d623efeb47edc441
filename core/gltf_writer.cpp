// glTF 2.0 export through tinygltf's serialiser. Section numbers cite the glTF 2.0 specification
// (Khronos, version 2.0.1); the unlit material follows the KHR_materials_unlit README
// (https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Khronos/KHR_materials_unlit).
#include "core/gltf_writer.h"

#include "core/errors.h"

#include <tiny_gltf.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <span>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace penumbra {
namespace fs = std::filesystem;
namespace {

// Component types and buffer-view targets (section 5.1.3, 5.11.4), and the accessor types of 1 to
// 4 components.
constexpr int kFloat = TINYGLTF_COMPONENT_TYPE_FLOAT;
constexpr int kUnsignedInt = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
constexpr int kArrayBuffer = TINYGLTF_TARGET_ARRAY_BUFFER;
constexpr int kElementArrayBuffer = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
constexpr int kVectorTypes[] = {TINYGLTF_TYPE_SCALAR, TINYGLTF_TYPE_VEC2, TINYGLTF_TYPE_VEC3,
                                TINYGLTF_TYPE_VEC4};

std::string lowerExtension(const fs::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

void checkFinite(std::span<const float> values, const std::string& what) {
    for (const float v : values) {
        if (!std::isfinite(v))
            throw std::invalid_argument("writeGltf: " + what + " has a non-finite value");
    }
}

// The checks of section 3.7.2 that the writer could otherwise break: attribute counts agree,
// indices are in range, no NaN or infinity (accessor min/max and viewers need finite values).
void checkMesh(const GltfMeshData& mesh) {
    const std::string what = "mesh \"" + mesh.name + "\"";
    const size_t count = mesh.positions.size();
    if (count == 0 || mesh.indices.empty() || mesh.indices.size() % 3 != 0)
        throw std::invalid_argument("writeGltf: " + what + " has no triangles");
    if (!mesh.normals.empty() && mesh.normals.size() != count)
        throw std::invalid_argument("writeGltf: " + what + ": one normal per position expected");
    if (mesh.colorComponents != 3 && mesh.colorComponents != 4)
        throw std::invalid_argument("writeGltf: " + what + ": colours have 3 or 4 components");
    if (!mesh.colors.empty() && mesh.colors.size() != count * size_t(mesh.colorComponents))
        throw std::invalid_argument("writeGltf: " + what + ": one colour per position expected");
    for (const uint32_t i : mesh.indices) {
        if (i >= count)
            throw std::invalid_argument("writeGltf: " + what + ": index past the vertex count");
    }
    checkFinite({&mesh.positions[0].x, 3 * count}, what + " positions");
    if (!mesh.normals.empty())
        checkFinite({&mesh.normals[0].x, 3 * count}, what + " normals");
    checkFinite(mesh.colors, what + " colours");
    for (const float c : mesh.colors) {
        if (c < 0.0f || c > 1.0f)
            throw std::invalid_argument("writeGltf: " + what + ": a colour is outside [0, 1]");
    }
    std::vector<std::string> names;
    for (const GltfAttribute& attribute : mesh.customAttributes) {
        const std::string where = what + " attribute \"" + attribute.name + "\"";
        if (attribute.name.size() < 2 || attribute.name[0] != '_' ||
            std::find(names.begin(), names.end(), attribute.name) != names.end())
            throw std::invalid_argument("writeGltf: " + where +
                                        ": custom attributes need a unique name starting with _");
        if (attribute.components < 1 || attribute.components > 4 ||
            attribute.values.size() != count * size_t(attribute.components))
            throw std::invalid_argument("writeGltf: " + where + ": 1 to 4 values per position");
        checkFinite(attribute.values, where);
        names.push_back(attribute.name);
    }
}

// Appends `bytes` to buffer 0 as a new buffer view starting on a 4-byte boundary (section
// 3.6.2.4: an accessor's offset must be a multiple of its component size) and returns its index.
int addBufferView(tinygltf::Model& model, const void* bytes, size_t size, int target) {
    std::vector<unsigned char>& data = model.buffers[0].data;
    data.resize((data.size() + 3) / 4 * 4, 0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = size;
    view.target = target;
    data.resize(data.size() + size);
    std::memcpy(data.data() + view.byteOffset, bytes, size);
    model.bufferViews.push_back(view);
    return int(model.bufferViews.size()) - 1;
}

// A tightly packed accessor over a new buffer view of `count` elements of `type` (e.g.
// TINYGLTF_TYPE_VEC3) with `components` components each.
int addAccessor(tinygltf::Model& model, const void* bytes, size_t count, int type, int components,
                int componentType, int target) {
    const size_t componentSize = componentType == kFloat ? sizeof(float) : sizeof(uint32_t);
    tinygltf::Accessor accessor;
    accessor.bufferView =
        addBufferView(model, bytes, count * size_t(components) * componentSize, target);
    accessor.componentType = componentType;
    accessor.count = count;
    accessor.type = type;
    model.accessors.push_back(accessor);
    return int(model.accessors.size()) - 1;
}

// POSITION accessors must carry min and max (section 5.1.1, accessor.min).
void setBounds(tinygltf::Accessor& accessor, const std::vector<Vec3>& positions) {
    Vec3 lo = positions[0], hi = positions[0];
    for (const Vec3& p : positions) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    accessor.minValues = {lo.x, lo.y, lo.z};
    accessor.maxValues = {hi.x, hi.y, hi.z};
}

// White unlit material; the fallback values are the extension README's recommendation, so that a
// viewer without the extension shows the vertex colours on a dull non-metal.
tinygltf::Material unlitMaterial(const std::string& name, bool doubleSided) {
    tinygltf::Material material;
    material.name = name;
    material.doubleSided = doubleSided;
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    material.pbrMetallicRoughness.roughnessFactor = 0.9;
    material.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
    return material;
}

tinygltf::Model buildModel(const GltfModelData& data) {
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = data.generator;
    model.buffers.resize(1);

    tinygltf::Node root;
    root.name = "root";
    if (data.origin != glm::dvec3(0.0))
        root.translation = {data.origin.x, data.origin.y, data.origin.z};

    std::map<std::pair<std::string, bool>, int> materials;
    for (const GltfMeshData& mesh : data.meshes) {
        checkMesh(mesh);
        const auto [it, added] =
            materials.try_emplace({mesh.material, mesh.doubleSided}, int(model.materials.size()));
        if (added)
            model.materials.push_back(unlitMaterial(mesh.material, mesh.doubleSided));

        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.material = it->second;
        const size_t count = mesh.positions.size();
        primitive.attributes["POSITION"] = addAccessor(model, mesh.positions.data(), count,
                                                       TINYGLTF_TYPE_VEC3, 3, kFloat, kArrayBuffer);
        setBounds(model.accessors.back(), mesh.positions);
        if (!mesh.normals.empty()) {
            primitive.attributes["NORMAL"] = addAccessor(
                model, mesh.normals.data(), count, TINYGLTF_TYPE_VEC3, 3, kFloat, kArrayBuffer);
        }
        if (!mesh.colors.empty()) {
            primitive.attributes["COLOR_0"] = addAccessor(
                model, mesh.colors.data(), count, kVectorTypes[mesh.colorComponents - 1],
                mesh.colorComponents, kFloat, kArrayBuffer);
        }
        for (const GltfAttribute& attribute : mesh.customAttributes) {
            primitive.attributes[attribute.name] = addAccessor(
                model, attribute.values.data(), count, kVectorTypes[attribute.components - 1],
                attribute.components, kFloat, kArrayBuffer);
        }
        primitive.indices = addAccessor(model, mesh.indices.data(), mesh.indices.size(),
                                        TINYGLTF_TYPE_SCALAR, 1, kUnsignedInt, kElementArrayBuffer);

        tinygltf::Mesh gltfMesh;
        gltfMesh.name = mesh.name;
        gltfMesh.primitives.push_back(std::move(primitive));
        model.meshes.push_back(std::move(gltfMesh));
        tinygltf::Node node;
        node.name = mesh.name;
        node.mesh = int(model.meshes.size()) - 1;
        model.nodes.push_back(std::move(node));
        root.children.push_back(int(model.nodes.size()) - 1);
    }
    // A GLB's chunk lengths and a buffer's byteLength are 32-bit in practice (section 4.4.3).
    if (model.buffers[0].data.size() > std::numeric_limits<uint32_t>::max() - 64)
        throw std::invalid_argument("writeGltf: the model needs more than 4 GiB of buffer data");
    // A buffer must have a byteLength of at least 1 (section 5.10): a model without meshes has
    // none.
    if (model.buffers[0].data.empty())
        model.buffers.clear();
    if (!model.materials.empty())
        model.extensionsUsed = {"KHR_materials_unlit"};
    model.nodes.push_back(std::move(root));
    tinygltf::Scene scene;
    scene.nodes = {int(model.nodes.size()) - 1};
    model.scenes.push_back(std::move(scene));
    model.defaultScene = 0;
    return model;
}

// Writes `bytes` next to `path` under a temporary name and renames it over `path` (atomic on one
// file system), removing the temporary on any failure.
void replaceFile(const std::string& path, const std::string& bytes) {
    const fs::path target(path);
    const fs::path temporary =
        target.parent_path() / (target.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                                target.extension().string());
    std::error_code ec;
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        out.write(bytes.data(), std::streamsize(bytes.size()));
        out.close();
        if (!out) {
            fs::remove(temporary, ec);
            throw UsageError(path + ": cannot write " + temporary.string());
        }
    }
    fs::rename(temporary, target, ec);
    if (ec) {
        const std::string reason = ec.message();
        fs::remove(temporary, ec);
        throw UsageError(path + ": cannot replace the file: " + reason);
    }
}

}  // namespace

void checkGltfOutputPath(const std::string& path) {
    const fs::path p(path);
    const std::string ext = lowerExtension(p);
    if (p.stem().empty() || (ext != ".glb" && ext != ".gltf"))
        throw UsageError(path + ": unsupported model format \"" + ext +
                         "\" (supported: .glb, .gltf)");
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw UsageError(path + ": directory \"" + dir.string() + "\" does not exist");
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw UsageError(path + ": directory \"" + dir.string() + "\" is not writable");
}

size_t writeGltf(const std::string& path, const GltfModelData& data) {
    checkGltfOutputPath(path);
    const bool binary = lowerExtension(path) == ".glb";
    const tinygltf::Model model = buildModel(data);
    std::ostringstream stream(std::ios::binary);
    tinygltf::TinyGLTF serialiser;
    // .gltf: pretty-printed JSON with the buffer as a base64 data URI, self-contained like a .glb.
    if (!serialiser.WriteGltfSceneToStream(&model, stream, !binary, binary))
        throw UsageError(path + ": tinygltf could not serialise the model");
    const std::string bytes = stream.str();
    replaceFile(path, bytes);
    return bytes.size();
}

}  // namespace penumbra
