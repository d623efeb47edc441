// Structural validation of a parsed glTF file. tinygltf accepts files that break the
// specification (accessors past their buffer view, indices to missing objects, cycles), so
// everything the rest of the loader relies on is checked here first, with the JSON pointer of
// the offending property.
#include "core/gltf_detail.h"

#include <cmath>

namespace penumbra::gltf {
namespace {

using Model = tinygltf::Model;

bool inRange(int index, size_t size) {
    return index >= 0 && static_cast<size_t>(index) < size;
}

// "Indices MUST always point to existing elements" (3.3).
void checkIndex(const Context& ctx, int index, size_t size, const std::string& pointer,
                const char* array) {
    if (!inRange(index, size)) {
        ctx.fail(pointer, "index " + std::to_string(index) + " is out of range: the file has " +
                              std::to_string(size) + " " + array);
    }
}

std::string componentName(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return "byte";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return "unsigned byte";
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return "short";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return "unsigned short";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return "unsigned int";
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return "float";
        default:
            return "component type " + std::to_string(componentType);
    }
}

std::string typeName(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
        default:
            return "type " + std::to_string(type);
    }
}

// Bytes of one element, including the column padding of small matrices (3.6.2.4).
size_t elementSize(const tinygltf::Accessor& a) {
    const size_t component = tinygltf::GetComponentSizeInBytes(a.componentType);
    const size_t rows = a.type == TINYGLTF_TYPE_MAT2 ? 2 : a.type == TINYGLTF_TYPE_MAT3 ? 3 : 0;
    if (rows == 0)
        return component * tinygltf::GetNumComponentsInType(a.type);
    return rows * ((rows * component + 3) / 4 * 4);
}

// ---- buffers and buffer views (3.6.1) ----------------------------------------------------------

void validateBufferViews(const Context& ctx) {
    const Model& m = ctx.model;
    for (size_t i = 0; i < m.bufferViews.size(); ++i) {
        const tinygltf::BufferView& v = m.bufferViews[i];
        const std::string p = at("bufferViews", i);
        checkIndex(ctx, v.buffer, m.buffers.size(), p + "/buffer", "buffers");
        // The actual data size counts, not the declared byteLength: a GLB BIN chunk may be
        // longer (3.6.1.2) and tinygltf has already compared external files with byteLength.
        const size_t size = m.buffers[v.buffer].data.size();
        if (v.byteLength == 0)
            ctx.fail(p + "/byteLength", "must be at least 1");
        if (v.byteOffset > size || v.byteLength > size - v.byteOffset) {
            ctx.fail(p, "bytes [" + std::to_string(v.byteOffset) + ", " +
                            std::to_string(v.byteOffset + v.byteLength) + ") are past the end of " +
                            "buffer " + std::to_string(v.buffer) + " (" + std::to_string(size) +
                            " bytes)");
        }
        // bufferView schema: byteStride in [4, 252], a multiple of 4 (0 means undefined).
        if (v.byteStride != 0 && (v.byteStride < 4 || v.byteStride > 252 || v.byteStride % 4)) {
            ctx.fail(p + "/byteStride",
                     "must be a multiple of 4 in [4, 252], got " + std::to_string(v.byteStride));
        }
    }
}

// ---- accessors (3.6.2) -------------------------------------------------------------------------

// The accessor fits its buffer view and is aligned (3.6.2.4).
void validateAccessorRange(const Context& ctx, size_t index) {
    const tinygltf::Accessor& a = ctx.model.accessors[index];
    const tinygltf::BufferView& view = ctx.model.bufferViews[a.bufferView];
    const std::string p = at("accessors", index);
    const size_t component = tinygltf::GetComponentSizeInBytes(a.componentType);
    const size_t element = elementSize(a);
    if (a.byteOffset % component || (a.byteOffset + view.byteOffset) % component) {
        ctx.fail(p + "/byteOffset",
                 "the offset into the buffer view and into the buffer must be multiples of the "
                 "component size " +
                     std::to_string(component) + " (3.6.2.4)");
    }
    if (view.byteStride % component || (view.byteStride != 0 && view.byteStride < element)) {
        ctx.fail(at("bufferViews", a.bufferView) + "/byteStride",
                 "stride " + std::to_string(view.byteStride) + " does not suit accessor " +
                     std::to_string(index) + " (elements of " + std::to_string(element) +
                     " bytes, components of " + std::to_string(component) + ")");
    }
    const size_t stride = view.byteStride ? view.byteStride : element;
    // Checked in this order so that no product below can overflow.
    if (a.byteOffset > view.byteLength || a.count > view.byteLength ||
        a.byteOffset + stride * (a.count - 1) + element > view.byteLength) {
        ctx.fail(p, "needs bytes up to " +
                        std::to_string(a.byteOffset + stride * (a.count - 1) + element) +
                        " of buffer view " + std::to_string(a.bufferView) + ", which has " +
                        std::to_string(view.byteLength) + " (3.6.2.4)");
    }
}

// The index and value arrays of a sparse accessor fit their buffer views (3.6.2.3).
void validateSparse(const Context& ctx, size_t index) {
    const Model& m = ctx.model;
    const tinygltf::Accessor& a = m.accessors[index];
    const std::string p = at("accessors", index) + "/sparse";
    if (a.sparse.count < 1 || static_cast<size_t>(a.sparse.count) > a.count) {
        ctx.fail(p + "/count", "must be in [1, accessor count " + std::to_string(a.count) + "]");
    }
    const int indexType = a.sparse.indices.componentType;
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        ctx.fail(p + "/indices/componentType", "must be an unsigned integer type");
    }
    const struct {
        const char* name;
        int view;
        int offset;
        size_t bytes;
    } parts[] = {
        {"indices", a.sparse.indices.bufferView, a.sparse.indices.byteOffset,
         size_t(a.sparse.count) * tinygltf::GetComponentSizeInBytes(indexType)},
        {"values", a.sparse.values.bufferView, a.sparse.values.byteOffset,
         size_t(a.sparse.count) * elementSize(a)},
    };
    for (const auto& part : parts) {
        const std::string pp = p + "/" + part.name;
        checkIndex(ctx, part.view, m.bufferViews.size(), pp + "/bufferView", "bufferViews");
        const tinygltf::BufferView& view = m.bufferViews[part.view];
        // Sparse data is tightly packed: its views must not have a stride (accessor.sparse schema).
        if (view.byteStride != 0)
            ctx.fail(pp + "/bufferView", "the buffer view has a byteStride");
        if (part.offset < 0 || size_t(part.offset) + part.bytes > view.byteLength) {
            ctx.fail(pp, "needs " + std::to_string(part.bytes) + " bytes from offset " +
                             std::to_string(part.offset) + " of buffer view " +
                             std::to_string(part.view) + ", which has " +
                             std::to_string(view.byteLength));
        }
    }
}

void validateAccessors(const Context& ctx) {
    const Model& m = ctx.model;
    for (size_t i = 0; i < m.accessors.size(); ++i) {
        const tinygltf::Accessor& a = m.accessors[i];
        const std::string p = at("accessors", i);
        // 3.6.2.2: signed 32-bit integers are not a glTF component type.
        if (a.componentType == TINYGLTF_COMPONENT_TYPE_INT ||
            tinygltf::GetComponentSizeInBytes(a.componentType) <= 0 ||
            a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE) {
            ctx.fail(p + "/componentType",
                     "invalid " + componentName(a.componentType) + " (3.6.2.2)");
        }
        if (tinygltf::GetNumComponentsInType(a.type) <= 0)
            ctx.fail(p + "/type", "invalid type");
        if (a.count == 0)
            ctx.fail(p + "/count", "must be at least 1");
        if (a.bufferView >= 0) {
            checkIndex(ctx, a.bufferView, m.bufferViews.size(), p + "/bufferView", "bufferViews");
            validateAccessorRange(ctx, i);
        }
        if (a.sparse.isSparse)
            validateSparse(ctx, i);
    }
}

// ---- meshes (3.7.2.1) --------------------------------------------------------------------------

// Accessor type and component types of the attributes penumbra reads (3.7.2.1 table).
void checkAttributeFormat(const Context& ctx, const std::string& name, const tinygltf::Accessor& a,
                          const std::string& pointer) {
    const bool isFloat = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool isNormalizedUnsigned =
        a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                         a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    int type = 0;
    bool ok = isFloat;
    std::string expected = "float";
    if (name == "POSITION" || name == "NORMAL") {
        type = TINYGLTF_TYPE_VEC3;
    } else if (name == "TANGENT") {
        type = TINYGLTF_TYPE_VEC4;
    } else if (name.rfind("TEXCOORD_", 0) == 0) {
        type = TINYGLTF_TYPE_VEC2;
        ok = isFloat || isNormalizedUnsigned;
        expected = "float or normalized unsigned byte/short";
    } else {
        return;  // COLOR_n, JOINTS_n, WEIGHTS_n and application attributes are not read
    }
    if (a.type != type || !ok) {
        ctx.fail(pointer, name + " must be " + typeName(type) + " of " + expected + ", got " +
                              typeName(a.type) + " of " + (a.normalized ? "normalized " : "") +
                              componentName(a.componentType) + " (3.7.2.1)");
    }
}

// An accessor the loader will read must have data: a buffer view or sparse values. Without
// either, its data would come from an extension (3.6.2.5) that penumbra does not support.
void checkHasData(const Context& ctx, const tinygltf::Accessor& a, const std::string& pointer) {
    if (a.bufferView < 0 && !a.sparse.isSparse) {
        ctx.fail(pointer, "the accessor has neither a bufferView nor sparse data");
    }
}

void validateAttributes(const Context& ctx, const tinygltf::Primitive& prim, const std::string& p) {
    const Model& m = ctx.model;
    size_t count = 0;
    std::string first;
    for (const auto& [name, index] : prim.attributes) {
        const std::string ap = p + "/attributes/" + name;
        checkIndex(ctx, index, m.accessors.size(), ap, "accessors");
        const tinygltf::Accessor& a = m.accessors[index];
        checkAttributeFormat(ctx, name, a, ap);
        checkHasData(ctx, a, ap);
        // Each vertex attribute element is 4-byte aligned in its buffer view (3.6.2.4).
        if (a.bufferView >= 0) {
            const size_t stride = m.bufferViews[a.bufferView].byteStride;
            if (a.byteOffset % 4 || (stride == 0 ? elementSize(a) : stride) % 4) {
                ctx.fail(at("accessors", index),
                         "vertex attribute elements must start on 4-byte boundaries: byteOffset "
                         "and the (effective) byteStride must be multiples of 4 (3.6.2.4)");
            }
        }
        // "All attribute accessors for a given primitive MUST have the same count" (3.7.2.1).
        if (first.empty()) {
            first = name;
            count = a.count;
        } else if (a.count != count) {
            ctx.fail(ap, "count " + std::to_string(a.count) + " differs from the count " +
                             std::to_string(count) + " of " + first + " (3.7.2.1)");
        }
    }
}

void validateIndices(const Context& ctx, int index, const std::string& pointer) {
    const Model& m = ctx.model;
    checkIndex(ctx, index, m.accessors.size(), pointer, "accessors");
    const tinygltf::Accessor& a = m.accessors[index];
    const int c = a.componentType;
    if (a.type != TINYGLTF_TYPE_SCALAR || a.normalized ||
        (c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         c != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
        ctx.fail(pointer, "indices must be SCALAR of unsigned byte, short or int, got " +
                              typeName(a.type) + " of " + componentName(c) + " (3.7.2.1)");
    }
    checkHasData(ctx, a, pointer);
    // Index data is tightly packed; only vertex attribute views may have a stride (3.6.1.1).
    if (a.bufferView >= 0 && m.bufferViews[a.bufferView].byteStride != 0) {
        ctx.fail(at("bufferViews", a.bufferView) + "/byteStride",
                 "a buffer view of vertex indices must not have a byteStride (3.6.1.1)");
    }
}

void validateMeshes(const Context& ctx) {
    const Model& m = ctx.model;
    for (size_t i = 0; i < m.meshes.size(); ++i) {
        if (m.meshes[i].primitives.empty()) {
            ctx.fail(at("meshes", i) + "/primitives", "must not be empty");
        }
        for (size_t k = 0; k < m.meshes[i].primitives.size(); ++k) {
            const tinygltf::Primitive& prim = m.meshes[i].primitives[k];
            const std::string p = at("meshes", i) + "/primitives/" + std::to_string(k);
            validateAttributes(ctx, prim, p);
            if (prim.indices >= 0)
                validateIndices(ctx, prim.indices, p + "/indices");
            if (prim.material >= 0) {
                checkIndex(ctx, prim.material, m.materials.size(), p + "/material", "materials");
            }
            if (prim.mode < TINYGLTF_MODE_POINTS || prim.mode > TINYGLTF_MODE_TRIANGLE_FAN) {
                ctx.fail(p + "/mode", "invalid topology " + std::to_string(prim.mode));
            }
        }
    }
}

// ---- nodes and scenes (3.5) --------------------------------------------------------------------

// Property arrays of the expected length with finite values (node schema; 3.5.3).
void validateTransform(const Context& ctx, const tinygltf::Node& n, const std::string& p) {
    const struct {
        const char* name;
        const std::vector<double>& values;
        size_t size;
    } props[] = {{"matrix", n.matrix, 16},
                 {"rotation", n.rotation, 4},
                 {"scale", n.scale, 3},
                 {"translation", n.translation, 3}};
    for (const auto& prop : props) {
        if (prop.values.empty())
            continue;
        if (prop.values.size() != prop.size) {
            ctx.fail(p + "/" + prop.name, "expected " + std::to_string(prop.size) + " numbers");
        }
        for (double v : prop.values) {
            if (!std::isfinite(v))
                ctx.fail(p + "/" + prop.name, "values must be finite");
        }
    }
    // The rotation is a unit quaternion (3.5.3); small rounding is normalised away later, but
    // a zero quaternion has no direction to normalise to.
    if (!n.rotation.empty() &&
        glm::length(glm::dvec4(n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3])) < 0.5) {
        ctx.fail(p + "/rotation", "must be a unit quaternion (3.5.3)");
    }
}

// "The node hierarchy MUST be a set of disjoint strict trees", no cycles and at most one parent
// (3.5.2). Returns each node's parent (-1 for roots).
std::vector<int> validateHierarchy(const Context& ctx) {
    const Model& m = ctx.model;
    std::vector<int> parent(m.nodes.size(), -1), slot(m.nodes.size(), -1);
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        for (size_t j = 0; j < m.nodes[i].children.size(); ++j) {
            const int c = m.nodes[i].children[j];
            const std::string p = at("nodes", i) + "/children/" + std::to_string(j);
            checkIndex(ctx, c, m.nodes.size(), p, "nodes");
            if (parent[c] >= 0) {
                ctx.fail(p, "node " + std::to_string(c) + " already has parent node " +
                                std::to_string(parent[c]) + " (3.5.2: at most one parent)");
            }
            parent[c] = static_cast<int>(i);
            slot[c] = static_cast<int>(j);
        }
    }
    // With one parent per node, a cycle is a parent chain that comes back to itself. Walk up
    // from every node, marking the chain; reaching a node of the current walk closes a cycle.
    enum : char { kUnseen, kWalking, kDone };
    std::vector<char> state(m.nodes.size(), kUnseen);
    for (size_t start = 0; start < m.nodes.size(); ++start) {
        int node = static_cast<int>(start);
        while (node >= 0 && state[node] == kUnseen) {
            state[node] = kWalking;
            if (parent[node] >= 0 && state[parent[node]] == kWalking) {
                ctx.fail(at("nodes", parent[node]) + "/children/" + std::to_string(slot[node]),
                         "node " + std::to_string(node) +
                             " is its own ancestor: the node hierarchy has a cycle (3.5.2)");
            }
            node = parent[node];
        }
        for (node = static_cast<int>(start); node >= 0 && state[node] == kWalking;
             node = parent[node]) {
            state[node] = kDone;
        }
    }
    return parent;
}

void validateNodes(const Context& ctx, const std::vector<int>& parent, size_t lightCount) {
    const Model& m = ctx.model;
    for (size_t i = 0; i < m.nodes.size(); ++i) {
        const tinygltf::Node& n = m.nodes[i];
        const std::string p = at("nodes", i);
        if (n.mesh >= 0)
            checkIndex(ctx, n.mesh, m.meshes.size(), p + "/mesh", "meshes");
        if (n.camera >= 0)
            checkIndex(ctx, n.camera, m.cameras.size(), p + "/camera", "cameras");
        if (n.skin >= 0)
            checkIndex(ctx, n.skin, m.skins.size(), p + "/skin", "skins");
        const int light = nodeLight(ctx, static_cast<int>(i));
        if (light >= 0) {
            checkIndex(ctx, light, lightCount, p + "/extensions/KHR_lights_punctual/light",
                       "KHR_lights_punctual lights");
        }
        validateTransform(ctx, n, p);
    }
    for (size_t s = 0; s < m.scenes.size(); ++s) {
        for (size_t j = 0; j < m.scenes[s].nodes.size(); ++j) {
            const int n = m.scenes[s].nodes[j];
            const std::string p = at("scenes", s) + "/nodes/" + std::to_string(j);
            checkIndex(ctx, n, m.nodes.size(), p, "nodes");
            // "All nodes listed in scene.nodes array MUST be root nodes" (3.5.1).
            if (parent[n] >= 0) {
                ctx.fail(p, "node " + std::to_string(n) + " is a child of node " +
                                std::to_string(parent[n]) + ", not a root node (3.5.1)");
            }
        }
    }
}

// ---- textures, samplers, images (3.8) ----------------------------------------------------------

bool validWrap(int w) {
    return w == TINYGLTF_TEXTURE_WRAP_REPEAT || w == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE ||
           w == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
}

void validateTextures(const Context& ctx) {
    const Model& m = ctx.model;
    for (size_t i = 0; i < m.textures.size(); ++i) {
        const std::string p = at("textures", i);
        const tinygltf::Texture& t = m.textures[i];
        if (t.source >= 0)
            checkIndex(ctx, t.source, m.images.size(), p + "/source", "images");
        if (t.sampler >= 0) {
            checkIndex(ctx, t.sampler, m.samplers.size(), p + "/sampler", "samplers");
        }
    }
    for (size_t i = 0; i < m.samplers.size(); ++i) {
        const tinygltf::Sampler& s = m.samplers[i];
        if (!validWrap(s.wrapS))
            ctx.fail(at("samplers", i) + "/wrapS", "invalid wrap mode");
        if (!validWrap(s.wrapT))
            ctx.fail(at("samplers", i) + "/wrapT", "invalid wrap mode");
    }
    for (size_t i = 0; i < m.images.size(); ++i) {
        const int view = m.images[i].bufferView;
        if (view >= 0) {
            checkIndex(ctx, view, m.bufferViews.size(), at("images", i) + "/bufferView",
                       "bufferViews");
        }
    }
}

// ---- cameras (3.10 and the camera.perspective / camera.orthographic schemas) --------------------

void validateCameras(const Context& ctx) {
    for (size_t i = 0; i < ctx.model.cameras.size(); ++i) {
        const tinygltf::Camera& c = ctx.model.cameras[i];
        const std::string p = at("cameras", i);
        if (c.type == "perspective") {
            const tinygltf::PerspectiveCamera& q = c.perspective;
            const std::string pp = p + "/perspective";
            if (!(q.yfov > 0.0))
                ctx.fail(pp + "/yfov", "must be greater than 0");
            if (!(q.znear > 0.0))
                ctx.fail(pp + "/znear", "must be greater than 0");
            if (q.aspectRatio < 0.0)
                ctx.fail(pp + "/aspectRatio", "must be greater than 0");
            if (q.zfar != 0.0 && !(q.zfar > q.znear)) {
                ctx.fail(pp + "/zfar", "must be greater than znear");
            }
        } else if (c.type == "orthographic") {
            const tinygltf::OrthographicCamera& o = c.orthographic;
            const std::string op = p + "/orthographic";
            if (o.xmag == 0.0)
                ctx.fail(op + "/xmag", "must not be zero");
            if (o.ymag == 0.0)
                ctx.fail(op + "/ymag", "must not be zero");
            if (!(o.znear >= 0.0))
                ctx.fail(op + "/znear", "must not be negative");
            if (!(o.zfar > o.znear))
                ctx.fail(op + "/zfar", "must be greater than znear");
        } else {
            ctx.fail(p + "/type",
                     "must be \"perspective\" or \"orthographic\", got \"" + c.type + "\"");
        }
    }
}

}  // namespace

void validateModel(const Context& ctx, size_t lightCount) {
    validateBufferViews(ctx);
    validateAccessors(ctx);
    validateMeshes(ctx);
    const std::vector<int> parent = validateHierarchy(ctx);
    validateNodes(ctx, parent, lightCount);
    validateTextures(ctx);
    validateCameras(ctx);
}

}  // namespace penumbra::gltf
