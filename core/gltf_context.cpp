// Shared state of the glTF loader and typed reads of untyped JSON values.
#include "core/errors.h"
#include "core/gltf_detail.h"

namespace penumbra::gltf {

void Context::fail(const std::string& pointer, const std::string& message) const {
    throw SceneError(file, pointer, message);
}

void Context::warn(const std::string& pointer, const std::string& message) const {
    report.warnings.push_back(file + (pointer.empty() ? "" : ": " + pointer) + ": " + message);
}

std::string at(std::string_view array, size_t index) {
    std::string pointer = "/";
    pointer.append(array).append("/").append(std::to_string(index));
    return pointer;
}

namespace {

// The value under `key`, or nullptr when `object` is not an object or has no such key.
const tinygltf::Value* member(const tinygltf::Value& object, const char* key) {
    return object.Has(key) ? &object.Get(key) : nullptr;
}

}  // namespace

double numberOr(const Context& ctx, const tinygltf::Value& object, const char* key, double fallback,
                const std::string& pointer) {
    const tinygltf::Value* v = member(object, key);
    if (!v)
        return fallback;
    if (!v->IsNumber())
        ctx.fail(pointer + "/" + key, "expected a number");
    return v->GetNumberAsDouble();
}

int indexOr(const Context& ctx, const tinygltf::Value& object, const char* key, int fallback,
            const std::string& pointer) {
    const tinygltf::Value* v = member(object, key);
    if (!v)
        return fallback;
    // JSON integers may be written as 2.0 or 2e0 but must have no fractional part (2.7).
    if (!v->IsNumber() || v->GetNumberAsDouble() != static_cast<double>(v->GetNumberAsInt()) ||
        v->GetNumberAsInt() < 0) {
        ctx.fail(pointer + "/" + key, "expected a non-negative integer");
    }
    return v->GetNumberAsInt();
}

std::vector<double> numbersOr(const Context& ctx, const tinygltf::Value& object, const char* key,
                              std::vector<double> fallback, const std::string& pointer) {
    const tinygltf::Value* v = member(object, key);
    if (!v)
        return fallback;
    if (!v->IsArray() || v->ArrayLen() != fallback.size()) {
        ctx.fail(pointer + "/" + key,
                 "expected an array of " + std::to_string(fallback.size()) + " numbers");
    }
    for (size_t i = 0; i < fallback.size(); ++i) {
        const tinygltf::Value& e = v->Get(static_cast<int>(i));
        if (!e.IsNumber())
            ctx.fail(pointer + "/" + key + "/" + std::to_string(i), "not a number");
        fallback[i] = e.GetNumberAsDouble();
    }
    return fallback;
}

const tinygltf::Value* extension(const tinygltf::ExtensionMap& extensions, const char* key) {
    const auto it = extensions.find(key);
    return it != extensions.end() && it->second.IsObject() ? &it->second : nullptr;
}

}  // namespace penumbra::gltf
