// glTF materials (3.9) with the supported KHR_materials_* extensions, and the decoding of the
// textures they use (3.8) to linear float RGBA.
#include "core/gltf_detail.h"

#include <cstring>
#include <map>
#include <tuple>

namespace penumbra::gltf {
namespace {

// Colour textures are stored with the sRGB transfer function, data textures linearly (3.9.2,
// 3.9.3; KHR_materials_specular for specularColorTexture).
enum class ColorSpace { Linear, Srgb };

WrapMode wrapMode(int wrap) {
    switch (wrap) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return WrapMode::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return WrapMode::MirroredRepeat;
        default:
            return WrapMode::Repeat;
    }
}

std::string imageSource(const tinygltf::Image& image) {
    if (image.bufferView >= 0)
        return "in buffer view " + std::to_string(image.bufferView);
    if (image.uri.rfind("data:", 0) == 0)
        return "in a data URI";
    return "'" + image.uri + "'";
}

// The image's samples expanded to linear RGBA floats. tinygltf has decoded it with stb_image
// (8 or 16 bits per sample, 1 to 4 channels: grey, grey + alpha, RGB, RGBA). In the sRGB colour
// space the RGB (or grey) channels are decoded with the sRGB transfer function; alpha is always
// linear (3.9.2).
std::vector<Vec4> expandToRgba(const tinygltf::Image& img, ColorSpace space) {
    const size_t bytes = img.bits / 8;
    // One table entry per code value turns the per-sample conversion into a lookup.
    const size_t levels = size_t(1) << img.bits;
    std::vector<float> linear(levels), color(levels);
    for (size_t v = 0; v < levels; ++v) {
        linear[v] = static_cast<float>(v) / static_cast<float>(levels - 1);
        color[v] = space == ColorSpace::Srgb ? srgbToLinear(linear[v]) : linear[v];
    }
    const size_t count = size_t(img.width) * img.height;
    std::vector<Vec4> texels(count);
    for (size_t i = 0; i < count; ++i) {
        uint32_t c[4] = {0, 0, 0, 0};
        for (int k = 0; k < img.component; ++k) {
            const uint8_t* p = img.image.data() + (i * img.component + k) * bytes;
            if (bytes == 1) {
                c[k] = *p;
            } else {
                // stb_image returns 16-bit samples in native byte order.
                uint16_t sample;
                std::memcpy(&sample, p, sizeof sample);
                c[k] = sample;
            }
        }
        switch (img.component) {
            case 1:
                texels[i] = Vec4(Vec3(color[c[0]]), 1.0f);
                break;
            case 2:
                texels[i] = Vec4(Vec3(color[c[0]]), linear[c[1]]);
                break;
            case 3:
                texels[i] = Vec4(color[c[0]], color[c[1]], color[c[2]], 1.0f);
                break;
            default:
                texels[i] = Vec4(color[c[0]], color[c[1]], color[c[2]], linear[c[3]]);
        }
    }
    return texels;
}

// /images/<index> as a texture. tinygltf only warns about images it cannot find or decode, so
// the decoded data is checked here: a texture needs its image.
Texture decodeImage(const Context& ctx, int index, WrapMode wrapS, WrapMode wrapT,
                    ColorSpace space) {
    const tinygltf::Image& img = ctx.model.images[index];
    const bool decoded =
        img.width > 0 && img.height > 0 && img.component >= 1 && img.component <= 4 &&
        (img.bits == 8 || img.bits == 16) &&
        img.image.size() == size_t(img.width) * img.height * img.component * (img.bits / 8);
    if (!decoded) {
        ctx.fail(at("images", index),
                 "image " + imageSource(img) + " is missing or could not be decoded");
    }
    const bool external = img.bufferView < 0 && img.uri.rfind("data:", 0) != 0;
    std::string name = !img.name.empty() ? img.name
                       : external        ? img.uri
                                         : "image " + std::to_string(index);
    if (space == ColorSpace::Srgb)
        name += " (sRGB)";
    return Texture(std::move(name), img.width, img.height, expandToRgba(img, space), wrapS, wrapT);
}

// Converts materials, decoding each image once per wrap modes and colour space. The same image
// used as colour and as data becomes two textures.
class MaterialReader {
  public:
    MaterialReader(const Context& ctx, std::vector<Texture>& textures)
        : ctx_(ctx), textures_(textures) {}

    Material read(int index);

  private:
    // A textureInfo given as tinygltf fields (core properties) or as a JSON object (extensions).
    TextureRef ref(int texture, int texCoord, const tinygltf::ExtensionMap& extensions,
                   ColorSpace space, const std::string& p);
    TextureRef ref(const tinygltf::Value& parent, const char* key, ColorSpace space,
                   const std::string& parentPointer);
    int decoded(int texture, ColorSpace space, const std::string& p);

    void readCore(const tinygltf::Material& m, const std::string& p, Material& out);
    void readExtensions(const tinygltf::Material& m, const std::string& p, Material& out);

    const Context& ctx_;
    std::vector<Texture>& textures_;
    // (image, wrapS, wrapT, colour space) -> index into textures_
    std::map<std::tuple<int, WrapMode, WrapMode, ColorSpace>, int> cache_;
};

int MaterialReader::decoded(int texture, ColorSpace space, const std::string& p) {
    const tinygltf::Texture& t = ctx_.model.textures[texture];
    // Without a source the image would come from an extension (3.8.2); none is supported.
    if (t.source < 0) {
        ctx_.warn(p, "texture " + std::to_string(texture) + " has no image source; ignored");
        return -1;
    }
    // An undefined sampler means repeat wrapping in both directions (3.8.2).
    const tinygltf::Sampler sampler =
        t.sampler >= 0 ? ctx_.model.samplers[t.sampler] : tinygltf::Sampler();
    const auto key =
        std::make_tuple(t.source, wrapMode(sampler.wrapS), wrapMode(sampler.wrapT), space);
    if (const auto it = cache_.find(key); it != cache_.end())
        return it->second;
    textures_.push_back(decodeImage(ctx_, t.source, std::get<1>(key), std::get<2>(key), space));
    return cache_[key] = static_cast<int>(textures_.size()) - 1;
}

TextureRef MaterialReader::ref(int texture, int texCoord, const tinygltf::ExtensionMap& extensions,
                               ColorSpace space, const std::string& p) {
    TextureRef r;
    if (texture < 0)
        return r;
    if (static_cast<size_t>(texture) >= ctx_.model.textures.size()) {
        ctx_.fail(p + "/index", "texture " + std::to_string(texture) +
                                    " is out of range: the file has " +
                                    std::to_string(ctx_.model.textures.size()) + " textures");
    }
    r.texture = decoded(texture, space, p);
    r.texCoord = texCoord;
    // KHR_texture_transform: offset, rotation, scale and a texCoord override on any textureInfo.
    if (const tinygltf::Value* t = extension(extensions, "KHR_texture_transform")) {
        const std::string tp = p + "/extensions/KHR_texture_transform";
        const std::vector<double> offset = numbersOr(ctx_, *t, "offset", {0.0, 0.0}, tp);
        const std::vector<double> scale = numbersOr(ctx_, *t, "scale", {1.0, 1.0}, tp);
        r.transform.offset = Vec2(offset[0], offset[1]);
        r.transform.rotation = static_cast<float>(numberOr(ctx_, *t, "rotation", 0.0, tp));
        r.transform.scale = Vec2(scale[0], scale[1]);
        r.texCoord = indexOr(ctx_, *t, "texCoord", r.texCoord, tp);
    }
    // Clients "SHOULD support at least two texture coordinate sets" (3.7.2.1); penumbra has two.
    if (r.texCoord > 1) {
        ctx_.warn(p, "TEXCOORD_" + std::to_string(r.texCoord) +
                         " is not supported (only TEXCOORD_0 and TEXCOORD_1)");
    }
    return r;
}

TextureRef MaterialReader::ref(const tinygltf::Value& parent, const char* key, ColorSpace space,
                               const std::string& parentPointer) {
    if (!parent.Has(key))
        return {};
    const tinygltf::Value& info = parent.Get(key);
    const std::string p = parentPointer + "/" + key;
    if (!info.IsObject() || !info.Has("index"))
        ctx_.fail(p, "expected a textureInfo object");
    static const tinygltf::ExtensionMap kNone;
    const tinygltf::Value& ext = info.Get("extensions");
    return ref(indexOr(ctx_, info, "index", -1, p), indexOr(ctx_, info, "texCoord", 0, p),
               ext.IsObject() ? ext.Get<tinygltf::Value::Object>() : kNone, space, p);
}

// Core properties, defaults from the material schema (3.9, 5 "Properties Reference").
void MaterialReader::readCore(const tinygltf::Material& m, const std::string& p, Material& out) {
    const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    const std::string pp = p + "/pbrMetallicRoughness";
    if (pbr.baseColorFactor.size() != 4)
        ctx_.fail(pp + "/baseColorFactor", "expected 4 numbers");
    out.baseColor = Color(pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]);
    out.baseAlpha = static_cast<float>(pbr.baseColorFactor[3]);
    out.baseColorTexture =
        ref(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
            pbr.baseColorTexture.extensions, ColorSpace::Srgb, pp + "/baseColorTexture");
    out.metallic = static_cast<float>(pbr.metallicFactor);
    out.roughness = static_cast<float>(pbr.roughnessFactor);
    out.metallicRoughnessTexture =
        ref(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
            pbr.metallicRoughnessTexture.extensions, ColorSpace::Linear,
            pp + "/metallicRoughnessTexture");
    out.normalTexture = ref(m.normalTexture.index, m.normalTexture.texCoord,
                            m.normalTexture.extensions, ColorSpace::Linear, p + "/normalTexture");
    out.normalScale = static_cast<float>(m.normalTexture.scale);
    out.occlusionTexture =
        ref(m.occlusionTexture.index, m.occlusionTexture.texCoord, m.occlusionTexture.extensions,
            ColorSpace::Linear, p + "/occlusionTexture");
    if (!m.emissiveFactor.empty()) {
        if (m.emissiveFactor.size() != 3)
            ctx_.fail(p + "/emissiveFactor", "expected 3 numbers");
        out.emissive = Color(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]);
    }
    out.emissiveTexture =
        ref(m.emissiveTexture.index, m.emissiveTexture.texCoord, m.emissiveTexture.extensions,
            ColorSpace::Srgb, p + "/emissiveTexture");
    // 3.9.4
    if (m.alphaMode == "OPAQUE") {
        out.alphaMode = AlphaMode::Opaque;
    } else if (m.alphaMode == "MASK") {
        out.alphaMode = AlphaMode::Mask;
    } else if (m.alphaMode == "BLEND") {
        out.alphaMode = AlphaMode::Blend;
    } else {
        ctx_.fail(p + "/alphaMode", "must be OPAQUE, MASK or BLEND, got \"" + m.alphaMode + "\"");
    }
    if (m.alphaCutoff < 0.0)
        ctx_.fail(p + "/alphaCutoff", "must not be negative");
    out.alphaCutoff = static_cast<float>(m.alphaCutoff);
    out.doubleSided = m.doubleSided;  // 3.9.5
}

// The supported KHR_materials_* extensions, defaults from their READMEs.
void MaterialReader::readExtensions(const tinygltf::Material& m, const std::string& p,
                                    Material& out) {
    const std::string ep = p + "/extensions/";
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_emissive_strength")) {
        const std::string xp = ep + "KHR_materials_emissive_strength";
        const double strength = numberOr(ctx_, *e, "emissiveStrength", 1.0, xp);
        if (strength < 0.0)
            ctx_.fail(xp + "/emissiveStrength", "must not be negative");
        out.emissive *= static_cast<float>(strength);
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_ior")) {
        out.ior = static_cast<float>(numberOr(ctx_, *e, "ior", 1.5, ep + "KHR_materials_ior"));
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_specular")) {
        const std::string xp = ep + "KHR_materials_specular";
        out.specular = static_cast<float>(numberOr(ctx_, *e, "specularFactor", 1.0, xp));
        out.specularTexture = ref(*e, "specularTexture", ColorSpace::Linear, xp);
        const std::vector<double> c = numbersOr(ctx_, *e, "specularColorFactor", {1, 1, 1}, xp);
        out.specularColor = Color(c[0], c[1], c[2]);
        out.specularColorTexture = ref(*e, "specularColorTexture", ColorSpace::Srgb, xp);
    }
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_transmission")) {
        const std::string xp = ep + "KHR_materials_transmission";
        out.transmission = static_cast<float>(numberOr(ctx_, *e, "transmissionFactor", 0.0, xp));
        out.transmissionTexture = ref(*e, "transmissionTexture", ColorSpace::Linear, xp);
    }
    // KHR_materials_volume; thicknessTexture is not read: penumbra only needs to know whether
    // the material is thin-walled (thicknessFactor 0) or a volume boundary.
    if (const tinygltf::Value* e = extension(m.extensions, "KHR_materials_volume")) {
        const std::string xp = ep + "KHR_materials_volume";
        out.thickness = static_cast<float>(numberOr(ctx_, *e, "thicknessFactor", 0.0, xp));
        const std::vector<double> c = numbersOr(ctx_, *e, "attenuationColor", {1, 1, 1}, xp);
        out.attenuationColor = Color(c[0], c[1], c[2]);
        const double d = numberOr(ctx_, *e, "attenuationDistance", INFINITY, xp);
        if (!(d > 0.0))
            ctx_.fail(xp + "/attenuationDistance", "must be greater than 0");
        out.attenuationDistance = static_cast<float>(d);
    }
}

Material MaterialReader::read(int index) {
    const tinygltf::Material& m = ctx_.model.materials[index];
    const std::string p = at("materials", index);
    Material out;
    out.name = m.name.empty() ? "material " + std::to_string(index) : m.name;
    readCore(m, p, out);
    readExtensions(m, p, out);
    return out;
}

}  // namespace

void loadMaterials(const Context& ctx, std::vector<Material>& materials,
                   std::vector<Texture>& textures) {
    MaterialReader reader(ctx, textures);
    for (size_t i = 0; i < ctx.model.materials.size(); ++i) {
        materials.push_back(reader.read(static_cast<int>(i)));
    }
}

}  // namespace penumbra::gltf
