// Reading accessors that validateModel has checked: gather the (possibly strided) elements,
// apply sparse substitution, decode the components.
#include "core/gltf_detail.h"

#include <bit>
#include <cstring>

namespace penumbra::gltf {
namespace {

// glTF buffers are little endian (3.6.1.1); components are copied as they are.
static_assert(std::endian::native == std::endian::little, "big-endian hosts need byte swapping");

template <typename T>
T load(const uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

uint32_t decodeUnsigned(const uint8_t* p, int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return load<uint16_t>(p);
        default:
            return load<uint32_t>(p);  // UNSIGNED_INT, the only other valid index type
    }
}

// One component as a float; normalized integers use the int-to-float equations of 3.11.
float decodeFloat(const uint8_t* p, int componentType, bool normalized) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const float c = static_cast<float>(load<int8_t>(p));
            return normalized ? glm::max(c / 127.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return normalized ? *p / 255.0f : static_cast<float>(*p);
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            const float c = static_cast<float>(load<int16_t>(p));
            return normalized ? glm::max(c / 32767.0f, -1.0f) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            const float c = static_cast<float>(load<uint16_t>(p));
            return normalized ? c / 65535.0f : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return static_cast<float>(load<uint32_t>(p));
        default:
            return load<float>(p);
    }
}

const uint8_t* viewData(const tinygltf::Model& m, int view, size_t offset) {
    const tinygltf::BufferView& v = m.bufferViews[view];
    return m.buffers[v.buffer].data.data() + v.byteOffset + offset;
}

// Replaces the elements listed by the sparse indices with the sparse values (3.6.2.3), after
// checking that the indices increase strictly and stay below the element count.
void applySparse(const Context& ctx, int index, size_t elementSize, std::vector<uint8_t>& out) {
    const tinygltf::Accessor& a = ctx.model.accessors[index];
    const auto& s = a.sparse;
    const size_t indexSize = tinygltf::GetComponentSizeInBytes(s.indices.componentType);
    const uint8_t* indices = viewData(ctx.model, s.indices.bufferView, s.indices.byteOffset);
    const uint8_t* values = viewData(ctx.model, s.values.bufferView, s.values.byteOffset);
    int64_t previous = -1;
    for (int k = 0; k < s.count; ++k) {
        const uint32_t i = decodeUnsigned(indices + k * indexSize, s.indices.componentType);
        if (i <= previous || i >= a.count) {
            ctx.fail(at("accessors", index) + "/sparse/indices",
                     "index " + std::to_string(i) + " at position " + std::to_string(k) +
                         (i >= a.count ? " is past the accessor count " + std::to_string(a.count)
                                       : " does not increase strictly") +
                         " (3.6.2.3)");
        }
        std::memcpy(out.data() + i * elementSize, values + k * elementSize, elementSize);
        previous = i;
    }
}

// The accessor's elements tightly packed, each `componentSize * components` bytes.
std::vector<uint8_t> packedElements(const Context& ctx, int index) {
    const tinygltf::Accessor& a = ctx.model.accessors[index];
    const size_t size = tinygltf::GetComponentSizeInBytes(a.componentType) *
                        tinygltf::GetNumComponentsInType(a.type);
    // Without a buffer view, a sparse accessor starts from zeros (3.6.2.3).
    std::vector<uint8_t> out(a.count * size, 0);
    if (a.bufferView >= 0) {
        const size_t stride = ctx.model.bufferViews[a.bufferView].byteStride;
        const uint8_t* src = viewData(ctx.model, a.bufferView, a.byteOffset);
        if (stride == 0 || stride == size) {
            std::memcpy(out.data(), src, out.size());
        } else {
            for (size_t i = 0; i < a.count; ++i)
                std::memcpy(&out[i * size], src + i * stride, size);
        }
    }
    if (a.sparse.isSparse)
        applySparse(ctx, index, size, out);
    return out;
}

// The accessor's components as floats, N per element (N = the accessor type's size).
template <int N>
std::vector<glm::vec<N, float>> readVectors(const Context& ctx, int index) {
    static_assert(sizeof(glm::vec<N, float>) == N * sizeof(float), "GLM vectors must be packed");
    const tinygltf::Accessor& a = ctx.model.accessors[index];
    const std::vector<uint8_t> bytes = packedElements(ctx, index);
    std::vector<glm::vec<N, float>> out(a.count);
    if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
        std::memcpy(out.data(), bytes.data(), bytes.size());
        return out;
    }
    const size_t componentSize = tinygltf::GetComponentSizeInBytes(a.componentType);
    for (size_t i = 0; i < a.count; ++i) {
        for (int c = 0; c < N; ++c) {
            out[i][c] =
                decodeFloat(&bytes[(i * N + c) * componentSize], a.componentType, a.normalized);
        }
    }
    return out;
}

}  // namespace

std::vector<Vec2> readVec2(const Context& ctx, int accessor) {
    return readVectors<2>(ctx, accessor);
}

std::vector<Vec3> readVec3(const Context& ctx, int accessor) {
    return readVectors<3>(ctx, accessor);
}

std::vector<Vec4> readVec4(const Context& ctx, int accessor) {
    return readVectors<4>(ctx, accessor);
}

std::vector<uint32_t> readIndices(const Context& ctx, int accessor) {
    const tinygltf::Accessor& a = ctx.model.accessors[accessor];
    const std::vector<uint8_t> bytes = packedElements(ctx, accessor);
    const size_t size = tinygltf::GetComponentSizeInBytes(a.componentType);
    std::vector<uint32_t> out(a.count);
    for (size_t i = 0; i < a.count; ++i)
        out[i] = decodeUnsigned(&bytes[i * size], a.componentType);
    return out;
}

}  // namespace penumbra::gltf
