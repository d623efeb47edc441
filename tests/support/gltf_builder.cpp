#include "tests/support/gltf_builder.h"

#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <stdexcept>

namespace penumbra::test {

namespace {

using nlohmann::json;

std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t v = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
        for (int k = 3; k >= 0; --k)
            out += kAlphabet[(v >> (6 * k)) & 63];
    }
    if (i + 1 == bytes.size()) {
        const uint32_t v = bytes[i] << 16;
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += "==";
    } else if (i + 2 == bytes.size()) {
        const uint32_t v = (bytes[i] << 16) | (bytes[i + 1] << 8);
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += kAlphabet[(v >> 6) & 63];
        out += '=';
    }
    return out;
}

template <typename T>
size_t append(std::vector<unsigned char>& buffer, const std::vector<T>& values) {
    while (buffer.size() % 4 != 0)
        buffer.push_back(0);
    const size_t offset = buffer.size();
    buffer.resize(offset + values.size() * sizeof(T));
    std::memcpy(buffer.data() + offset, values.data(), values.size() * sizeof(T));
    return offset;
}

json vec(const Vec3& v) {
    return json::array({v.x, v.y, v.z});
}
json quat(const Vec4& q) {
    return json::array({q.x, q.y, q.z, q.w});
}

}  // namespace

int GltfBuilder::addMaterial(const TestMaterial& material) {
    materials_.push_back(material);
    return static_cast<int>(materials_.size()) - 1;
}

void GltfBuilder::addMesh(const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices,
                          int material) {
    meshes_.push_back({positions, indices, material});
}

void GltfBuilder::addQuad(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3,
                          int material) {
    addMesh({p0, p1, p2, p3}, {0, 1, 2, 0, 2, 3}, material);
}

void GltfBuilder::addLight(const TestLight& light) {
    lights_.push_back(light);
}

void GltfBuilder::setOrthographicCamera(const Vec3& position, const Vec4& rotation, float xmag,
                                        float ymag) {
    cameraPosition_ = position;
    cameraRotation_ = rotation;
    cameraJson_ =
        nlohmann::json{
            {"type", "orthographic"},
            {"orthographic", {{"xmag", xmag}, {"ymag", ymag}, {"znear", 0.001}, {"zfar", 1000.0}}}}
            .dump();
}

void GltfBuilder::setPerspectiveCamera(const Vec3& position, const Vec4& rotation, float yfov) {
    cameraPosition_ = position;
    cameraRotation_ = rotation;
    cameraJson_ =
        nlohmann::json{{"type", "perspective"}, {"perspective", {{"yfov", yfov}, {"znear", 0.001}}}}
            .dump();
}

void GltfBuilder::setRootTransform(const Vec3& translation, float scale) {
    rootTranslation_ = translation;
    rootScale_ = scale;
}

std::string GltfBuilder::json() const {
    using nlohmann::json;
    nlohmann::json gltf;
    gltf["asset"] = {{"version", "2.0"}, {"generator", "penumbra tests/support/gltf_builder"}};
    gltf["extensionsUsed"] = json::array(
        {"KHR_materials_specular", "KHR_materials_emissive_strength", "KHR_lights_punctual"});
    std::vector<unsigned char> buffer;
    json accessors = json::array(), views = json::array(), meshes = json::array();
    json nodes = json::array(), children = json::array();
    nodes.push_back(json::object());  // root, filled below

    for (const MeshData& mesh : meshes_) {
        Vec3 lo(INFINITY), hi(-INFINITY);
        for (const Vec3& p : mesh.positions) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const size_t positionOffset = append(buffer, mesh.positions);
        views.push_back({{"buffer", 0},
                         {"byteOffset", positionOffset},
                         {"byteLength", mesh.positions.size() * sizeof(Vec3)},
                         {"target", 34962}});
        accessors.push_back({{"bufferView", views.size() - 1},
                             {"componentType", 5126},
                             {"count", mesh.positions.size()},
                             {"type", "VEC3"},
                             {"min", vec(lo)},
                             {"max", vec(hi)}});
        const size_t indexOffset = append(buffer, mesh.indices);
        views.push_back({{"buffer", 0},
                         {"byteOffset", indexOffset},
                         {"byteLength", mesh.indices.size() * sizeof(uint32_t)},
                         {"target", 34963}});
        accessors.push_back({{"bufferView", views.size() - 1},
                             {"componentType", 5125},
                             {"count", mesh.indices.size()},
                             {"type", "SCALAR"}});
        meshes.push_back(
            {{"primitives", json::array({{{"attributes", {{"POSITION", accessors.size() - 2}}},
                                          {"indices", accessors.size() - 1},
                                          {"material", mesh.material}}})}});
        nodes.push_back({{"mesh", meshes.size() - 1}});
        children.push_back(nodes.size() - 1);
    }

    json materials = json::array();
    for (const TestMaterial& m : materials_) {
        json material = {{"pbrMetallicRoughness",
                          {{"baseColorFactor", {m.baseColor.r, m.baseColor.g, m.baseColor.b, 1.0}},
                           {"metallicFactor", m.metallic},
                           {"roughnessFactor", m.roughness}}},
                         {"doubleSided", m.doubleSided}};
        json extensions = json::object();
        if (m.lambertian)
            extensions["KHR_materials_specular"] = {{"specularFactor", 0.0}};
        if (maxComponent(m.emissive) > 0.0f) {
            material["emissiveFactor"] = vec(m.emissive);
            extensions["KHR_materials_emissive_strength"] = {
                {"emissiveStrength", m.emissiveStrength}};
        }
        if (!extensions.empty())
            material["extensions"] = extensions;
        if (!m.name.empty())
            material["name"] = m.name;
        materials.push_back(material);
    }

    json lights = json::array();
    for (const TestLight& light : lights_) {
        json l = {
            {"type", light.type}, {"color", vec(light.color)}, {"intensity", light.intensity}};
        if (!light.name.empty())
            l["name"] = light.name;
        if (light.type == "spot") {
            l["spot"] = {{"innerConeAngle", light.innerConeAngle},
                         {"outerConeAngle", light.outerConeAngle}};
        }
        lights.push_back(l);
        nodes.push_back(
            {{"translation", vec(light.position)},
             {"rotation", quat(light.rotation)},
             {"extensions", {{"KHR_lights_punctual", {{"light", lights.size() - 1}}}}}});
        children.push_back(nodes.size() - 1);
    }

    json profiles = json::array();
    for (const TestLuminaire& luminaire : luminaires_) {
        profiles.push_back({{"uri", luminaire.uri}});
        nodes.push_back({{"translation", vec(luminaire.position)},
                         {"rotation", quat(luminaire.rotation)},
                         {"extensions",
                          {{"EXT_lights_ies",
                            {{"light", profiles.size() - 1},
                             {"multiplier", luminaire.multiplier},
                             {"color", vec(luminaire.color)}}}}}});
        children.push_back(nodes.size() - 1);
    }

    if (!cameraJson_.empty()) {
        gltf["cameras"] = json::array({json::parse(cameraJson_)});
        nodes.push_back({{"camera", 0},
                         {"translation", vec(cameraPosition_)},
                         {"rotation", quat(cameraRotation_)}});
        children.push_back(nodes.size() - 1);
    }

    nodes[0] = {{"children", children},
                {"translation", vec(rootTranslation_)},
                {"scale", vec(Vec3(rootScale_))}};
    gltf["nodes"] = nodes;
    gltf["scenes"] = json::array({{{"nodes", json::array({0})}}});
    if (!sceneExtras_.empty())
        gltf["scenes"][0]["extras"] = json::parse(sceneExtras_);
    gltf["scene"] = 0;
    gltf["meshes"] = meshes;
    gltf["materials"] = materials;
    gltf["accessors"] = accessors;
    gltf["bufferViews"] = views;
    gltf["buffers"] =
        json::array({{{"byteLength", buffer.size()},
                      {"uri", "data:application/octet-stream;base64," + base64(buffer)}}});
    if (!lights.empty())
        gltf["extensions"]["KHR_lights_punctual"] = {{"lights", lights}};
    if (!profiles.empty()) {
        gltf["extensions"]["EXT_lights_ies"] = {{"lights", profiles}};
        gltf["extensionsUsed"].push_back("EXT_lights_ies");
    }
    return gltf.dump(1);
}

void GltfBuilder::write(const std::string& path) const {
    std::ofstream out(path);
    out << json();
    if (!out)
        throw std::runtime_error("cannot write " + path);
}

}  // namespace penumbra::test
