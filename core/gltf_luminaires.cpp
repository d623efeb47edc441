// EXT_lights_ies: measured luminaires (IES LM-63 profiles, and EULUMDAT files by their .ldt
// name) referenced by nodes, as goniometric point lights (core/goniometric_light.h). The
// extension's README (KhronosGroup/glTF, extensions/2.0/Vendor/EXT_lights_ies): profiles in a
// top-level `lights` array, each by `uri` or by `bufferView` with mimeType
// "application/x-ies-lm-63"; a node refers to one by `light`, with a `multiplier` (>= 0, default
// 1) and a linear `color` clamped to [0, 1] (default white). The light sits at the node's origin,
// its photometric (0, 0) direction along the node's -Z, C0 along its +X, C90 along its +Y; the
// node's scale does not change its intensity.
#include "core/gltf_detail.h"
#include "core/photometric_files.h"

#include <filesystem>
#include <memory>
#include <string_view>

namespace penumbra::gltf {
namespace {

constexpr const char* kExtension = "EXT_lights_ies";
constexpr const char* kProfilesPointer = "/extensions/EXT_lights_ies/lights";
constexpr const char* kIesMimeType = "application/x-ies-lm-63";

std::string stringOr(const tinygltf::Value& object, const char* key, const std::string& fallback) {
    const tinygltf::Value& value = object.Get(key);
    return value.IsString() ? value.Get<std::string>() : fallback;
}

// One profile: the file its uri names (relative to the glTF file; .ldt read as EULUMDAT, anything
// else as IES) or the IES text in a buffer view.
Photometry readProfile(const Context& ctx, const tinygltf::Value& profile, const std::string& p) {
    if (!profile.IsObject())
        ctx.fail(p, "expected a light profile object");
    const bool hasUri = profile.Has("uri"), hasView = profile.Has("bufferView");
    if (hasUri == hasView)
        ctx.fail(p, "a light profile needs exactly one of uri and bufferView");
    try {
        if (hasUri) {
            const tinygltf::Value& uri = profile.Get("uri");
            if (!uri.IsString())
                ctx.fail(p + "/uri", "expected a string");
            const std::string name = uri.Get<std::string>();
            if (name.rfind("data:", 0) == 0) {
                ctx.fail(p + "/uri",
                         "data URIs are not read for light profiles; store the profile in a "
                         "file or a bufferView");
            }
            const std::filesystem::path file = std::filesystem::path(ctx.file).parent_path() / name;
            return file.extension() == ".ldt" || file.extension() == ".LDT" ? readLdt(file)
                                                                            : readIes(file);
        }
        if (stringOr(profile, "mimeType", "") != kIesMimeType)
            ctx.fail(p + "/mimeType",
                     std::string("a bufferView profile needs \"") + kIesMimeType + "\"");
        const int view = indexOr(ctx, profile, "bufferView", -1, p);
        if (view < 0 || view >= static_cast<int>(ctx.model.bufferViews.size()))
            ctx.fail(p + "/bufferView", "not a bufferView of the file");
        const tinygltf::BufferView& v = ctx.model.bufferViews[static_cast<size_t>(view)];
        const std::vector<unsigned char>& data = ctx.model.buffers[size_t(v.buffer)].data;
        const std::string_view text(reinterpret_cast<const char*>(data.data()) + v.byteOffset,
                                    v.byteLength);
        return parseIes(text, ctx.file + ":" + p);
    } catch (const PhotometricFileError& e) {
        ctx.fail(p, e.what());
    } catch (const SceneError&) {
        throw;
    } catch (const InputError& e) {
        ctx.fail(p, e.what());
    }
}

}  // namespace

std::vector<LuminaireProfile> readLuminaireProfiles(const Context& ctx) {
    std::vector<LuminaireProfile> profiles;
    const tinygltf::Value* ext = extension(ctx.model.extensions, kExtension);
    if (!ext)
        return profiles;
    const tinygltf::Value& list = ext->Get("lights");
    if (!list.IsArray())
        ctx.fail(kProfilesPointer, "expected an array of light profiles");
    for (size_t i = 0; i < list.ArrayLen(); ++i) {
        const std::string p = std::string(kProfilesPointer) + "/" + std::to_string(i);
        const tinygltf::Value& profile = list.Get(static_cast<int>(i));
        Photometry photometry = readProfile(ctx, profile, p);
        const std::string name = stringOr(profile, "name", photometry.source);
        profiles.push_back({name, std::make_shared<const CandelaTable>(photometry.candela)});
    }
    return profiles;
}

std::optional<LuminaireDesc> nodeLuminaire(const Context& ctx, int node,
                                           const std::vector<LuminaireProfile>& profiles,
                                           const glm::dmat4& world) {
    const tinygltf::Value* ext = extension(ctx.model.nodes[node].extensions, kExtension);
    if (!ext)
        return std::nullopt;
    const std::string p = at("nodes", node) + "/extensions/" + kExtension;
    if (!ext->Has("light"))
        ctx.fail(p, "the light profile index is missing");
    const int index = indexOr(ctx, *ext, "light", -1, p);
    if (index < 0 || index >= static_cast<int>(profiles.size())) {
        ctx.fail(p + "/light", "not a light profile of " + std::string(kProfilesPointer) + " (" +
                                   std::to_string(profiles.size()) + " of them)");
    }
    const double multiplier = numberOr(ctx, *ext, "multiplier", 1.0, p);
    if (!(multiplier >= 0.0))
        ctx.fail(p + "/multiplier", "must not be negative");
    const std::vector<double> c = numbersOr(ctx, *ext, "color", {1.0, 1.0, 1.0}, p);

    LuminaireDesc luminaire;
    luminaire.name = profiles[size_t(index)].name;
    luminaire.table = profiles[size_t(index)].table;
    luminaire.multiplier = static_cast<float>(multiplier);
    // "clamped to the [0, 1] range".
    luminaire.color = glm::clamp(Color(c[0], c[1], c[2]), Color(0.0f), Color(1.0f));
    luminaire.position = Vec3(world[3]);
    // The node's rotation without its scale: the intensity does not scale with the node.
    luminaire.luminaireToWorld = Mat3(nodeRotation(ctx, world, node, "luminaire"));
    return luminaire;
}

}  // namespace penumbra::gltf
