// glTF 2.0 materials as loaded (factors and texture references), and their evaluation at a
// surface point into the plain numbers a BSDF is built from.
#pragma once

#include "core/math.h"
#include "core/texture.h"

#include <limits>
#include <span>
#include <string>

namespace penumbra {

enum class AlphaMode { Opaque, Mask, Blend };

// One glTF material with the extensions penumbra supports. Factors are as in the file;
// emissive already includes KHR_materials_emissive_strength (so it is a radiance in cd/m²).
struct Material {
    std::string name;

    // pbrMetallicRoughness
    Color baseColor{1.0f};
    float baseAlpha = 1.0f;
    TextureRef baseColorTexture;
    float metallic = 1.0f;
    float roughness = 1.0f;               // perceptual roughness; GGX alpha = roughness^2
    TextureRef metallicRoughnessTexture;  // roughness in G, metallic in B

    TextureRef normalTexture;
    float normalScale = 1.0f;
    TextureRef occlusionTexture;  // read but unused: a path tracer computes occlusion itself

    Color emissive{0.0f};  // emissiveFactor x emissiveStrength, cd/m² per channel
    TextureRef emissiveTexture;

    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;
    bool doubleSided = false;

    // KHR_materials_ior
    float ior = 1.5f;
    // KHR_materials_specular
    float specular = 1.0f;
    TextureRef specularTexture;  // alpha channel
    Color specularColor{1.0f};
    TextureRef specularColorTexture;
    // KHR_materials_transmission
    float transmission = 0.0f;
    TextureRef transmissionTexture;  // red channel
    // KHR_materials_volume: thickness 0 means thin-walled
    float thickness = 0.0f;
    Color attenuationColor{1.0f};
    float attenuationDistance = std::numeric_limits<float>::infinity();

    bool isEmissive() const { return maxComponent(emissive) > 0.0f; }
    bool thinWalled() const { return thickness <= 0.0f; }
    // Absorption coefficient (1/m) inside a volume material, from Beer-Lambert:
    // attenuationColor is the transmittance after attenuationDistance.
    Color absorption() const;
};

// A material's parameters evaluated at one point (textures applied, clamped to valid ranges).
// This is everything a BSDF needs; it holds no references back into the scene.
struct ShadingParams {
    Color baseColor{1.0f};
    float metallic = 0.0f;
    float roughness = 1.0f;  // perceptual, in [0, 1]
    float ior = 1.5f;
    float specular = 1.0f;
    Color specularColor{1.0f};
    float transmission = 0.0f;
    bool thinWalled = true;
};

// Evaluates the material at texture coordinates uv (one pair per TEXCOORD set).
ShadingParams evaluateMaterial(const Material& material, std::span<const Texture> textures,
                               std::span<const Vec2> uvs);

// Emitted radiance (cd/m²) of the material at uv, before any facing test.
Color evaluateEmission(const Material& material, std::span<const Texture> textures,
                       std::span<const Vec2> uvs);

// Value of a texture reference at the given TEXCOORD sets, or `fallback` when it is not set.
Vec4 lookup(const TextureRef& ref, std::span<const Texture> textures, std::span<const Vec2> uvs,
            Vec4 fallback = Vec4(1.0f));

}  // namespace penumbra
