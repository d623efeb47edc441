#include "core/material.h"

#include <cmath>

namespace penumbra {

Color Material::absorption() const {
    if (!std::isfinite(attenuationDistance) || attenuationDistance <= 0.0f)
        return Color(0.0f);
    // sigma_a = -ln(c) / d  (KHR_materials_volume, "Properties"); a zero channel absorbs fully
    // over any finite distance, represented by a large finite coefficient.
    Color sigma;
    for (int i = 0; i < 3; ++i) {
        const float c = glm::clamp(attenuationColor[i], 1e-30f, 1.0f);
        sigma[i] = -std::log(c) / attenuationDistance;
    }
    return sigma;
}

Vec4 lookup(const TextureRef& ref, std::span<const Texture> textures, std::span<const Vec2> uvs,
            Vec4 fallback) {
    if (!ref.valid() || ref.texture >= static_cast<int>(textures.size()))
        return fallback;
    const Vec2 uv = ref.texCoord < static_cast<int>(uvs.size()) ? uvs[ref.texCoord] : Vec2(0.0f);
    return textures[ref.texture].sample(ref.transform.apply(uv));
}

ShadingParams evaluateMaterial(const Material& m, std::span<const Texture> textures,
                               std::span<const Vec2> uvs) {
    ShadingParams p;
    p.baseColor =
        glm::clamp(m.baseColor * Color(lookup(m.baseColorTexture, textures, uvs)), 0.0f, 1.0f);
    const Vec4 mr = lookup(m.metallicRoughnessTexture, textures, uvs);
    p.metallic = glm::clamp(m.metallic * mr.b, 0.0f, 1.0f);
    p.roughness = glm::clamp(m.roughness * mr.g, 0.0f, 1.0f);
    p.ior = m.ior;
    p.specular = glm::clamp(m.specular * lookup(m.specularTexture, textures, uvs).a, 0.0f, 1.0f);
    p.specularColor =
        glm::max(m.specularColor * Color(lookup(m.specularColorTexture, textures, uvs)), 0.0f);
    p.transmission =
        glm::clamp(m.transmission * lookup(m.transmissionTexture, textures, uvs).r, 0.0f, 1.0f);
    p.thinWalled = m.thinWalled();
    return p;
}

Color evaluateEmission(const Material& m, std::span<const Texture> textures,
                       std::span<const Vec2> uvs) {
    if (!m.isEmissive())
        return Color(0.0f);
    return m.emissive * Color(lookup(m.emissiveTexture, textures, uvs));
}

}  // namespace penumbra
