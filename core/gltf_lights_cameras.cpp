// KHR_lights_punctual lights and glTF cameras, and their placement by node transforms.
#include "core/gltf_detail.h"

namespace penumbra::gltf {
namespace {

constexpr const char* kLightsPointer = "/extensions/KHR_lights_punctual/lights";

PunctualType lightType(const Context& ctx, const tinygltf::Value& light, const std::string& p) {
    const tinygltf::Value& type = light.Get("type");
    const std::string name = type.IsString() ? type.Get<std::string>() : "";
    if (name == "point")
        return PunctualType::Point;
    if (name == "spot")
        return PunctualType::Spot;
    if (name != "directional") {
        ctx.fail(p + "/type", "must be \"directional\", \"point\" or \"spot\"");
    }
    return PunctualType::Directional;
}

// The cone angles of a spot light; the extension requires 0 <= inner < outer <= pi/2.
void readSpot(const Context& ctx, const tinygltf::Value& light, const std::string& p,
              PunctualLightDesc& out) {
    const tinygltf::Value& spot = light.Get("spot");
    if (!spot.IsObject())
        ctx.fail(p + "/spot", "a spot light needs a spot object");
    const double inner = numberOr(ctx, spot, "innerConeAngle", 0.0, p + "/spot");
    const double outer = numberOr(ctx, spot, "outerConeAngle", kPi / 4.0, p + "/spot");
    if (!(inner >= 0.0 && inner < outer && outer <= kPi / 2.0)) {
        ctx.fail(p + "/spot", "cone angles must satisfy 0 <= innerConeAngle (" +
                                  std::to_string(inner) + ") < outerConeAngle (" +
                                  std::to_string(outer) + ") <= pi/2");
    }
    out.innerConeAngle = static_cast<float>(inner);
    out.outerConeAngle = static_cast<float>(outer);
}

// One light with the extension's defaults: white, intensity 1, infinite range.
PunctualLightDesc readLight(const Context& ctx, const tinygltf::Value& light, size_t index) {
    const std::string p = std::string(kLightsPointer) + "/" + std::to_string(index);
    if (!light.IsObject())
        ctx.fail(p, "expected a light object");
    PunctualLightDesc out;
    const tinygltf::Value& name = light.Get("name");
    out.name = name.IsString() ? name.Get<std::string>() : "light " + std::to_string(index);
    out.type = lightType(ctx, light, p);
    const std::vector<double> c = numbersOr(ctx, light, "color", {1.0, 1.0, 1.0}, p);
    out.color = Color(c[0], c[1], c[2]);
    const double intensity = numberOr(ctx, light, "intensity", 1.0, p);
    if (intensity < 0.0)
        ctx.fail(p + "/intensity", "must not be negative");
    out.intensity = static_cast<float>(intensity);
    // "range ... MUST be greater than zero"; undefined means infinite (0 in PunctualLightDesc).
    if (light.Has("range")) {
        const double range = numberOr(ctx, light, "range", 0.0, p);
        if (!(range > 0.0))
            ctx.fail(p + "/range", "must be greater than 0");
        out.range = static_cast<float>(range);
    }
    if (out.type == PunctualType::Spot)
        readSpot(ctx, light, p, out);
    return out;
}

}  // namespace

std::vector<PunctualLightDesc> readLights(const Context& ctx) {
    std::vector<PunctualLightDesc> lights;
    const tinygltf::Value* ext = extension(ctx.model.extensions, "KHR_lights_punctual");
    if (!ext)
        return lights;
    const tinygltf::Value& list = ext->Get("lights");
    if (!list.IsArray())
        ctx.fail(kLightsPointer, "expected an array of lights");
    for (size_t i = 0; i < list.ArrayLen(); ++i) {
        lights.push_back(readLight(ctx, list.Get(static_cast<int>(i)), i));
    }
    return lights;
}

int nodeLight(const Context& ctx, int node) {
    const tinygltf::Value* ext = extension(ctx.model.nodes[node].extensions, "KHR_lights_punctual");
    if (!ext)
        return -1;
    const std::string p = at("nodes", node) + "/extensions/KHR_lights_punctual";
    if (!ext->Has("light"))
        ctx.fail(p, "the light index is missing");
    return indexOr(ctx, *ext, "light", -1, p);
}

PunctualLightDesc placeLight(PunctualLightDesc light, const glm::dmat4& world) {
    // Lights sit at their node's origin and shine along its local -Z (KHR_lights_punctual).
    light.position = Vec3(world[3]);
    light.direction = Vec3(glm::normalize(-glm::dvec3(world[2])));
    return light;
}

CameraDesc placeCamera(const Context& ctx, int camera, const glm::dmat4& world, int node) {
    const tinygltf::Camera& c = ctx.model.cameras[camera];
    CameraDesc out;
    out.name = c.name.empty() ? "camera " + std::to_string(camera) : c.name;
    if (c.type == "perspective") {
        out.projection = ProjectionType::Perspective;
        out.yfov = static_cast<float>(c.perspective.yfov);
        out.aspectRatio = static_cast<float>(c.perspective.aspectRatio);
        out.znear = static_cast<float>(c.perspective.znear);
    } else {
        out.projection = ProjectionType::Orthographic;
        out.xmag = static_cast<float>(c.orthographic.xmag);
        out.ymag = static_cast<float>(c.orthographic.ymag);
        out.znear = static_cast<float>(c.orthographic.znear);
    }
    // "The view matrix is derived from the global transform of the node containing the camera
    // with the scaling ignored" (3.10.2).
    const glm::dmat3 r = nodeRotation(ctx, world, node, "camera");
    out.cameraToWorld =
        Mat4(glm::dmat4(glm::dvec4(r[0], 0.0), glm::dvec4(r[1], 0.0), glm::dvec4(r[2], 0.0),
                        glm::dvec4(glm::dvec3(world[3]), 1.0)));
    return out;
}

glm::dmat3 nodeRotation(const Context& ctx, const glm::dmat4& world, int node,
                        const std::string& what) {
    // Gram-Schmidt keeps the aim (-Z) exactly and the up axis (+Y) as nearly as possible, and
    // completes a right-handed frame.
    const glm::dvec3 z = glm::normalize(glm::dvec3(world[2]));
    const glm::dvec3 y =
        glm::normalize(glm::dvec3(world[1]) - z * glm::dot(z, glm::dvec3(world[1])));
    const glm::dvec3 x = glm::cross(y, z);
    if (glm::dot(x, glm::dvec3(world[0])) < 0.0) {
        ctx.warn(at("nodes", node),
                 "the " + what + "'s node transform mirrors; the mirror is ignored");
    }
    return glm::dmat3(x, y, z);
}

}  // namespace penumbra::gltf
