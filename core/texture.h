// Decoded textures and their lookup: bilinear filtering with the glTF sampler's wrap modes, and
// the KHR_texture_transform of a texture reference.
#pragma once

#include "core/math.h"

#include <string>
#include <vector>

namespace penumbra {

enum class WrapMode { Repeat, ClampToEdge, MirroredRepeat };

// A texture decoded once at load time to linear float RGBA. Colour textures (baseColor,
// emissive, specularColor) are converted from sRGB when decoded; data textures stay linear.
class Texture {
  public:
    Texture(std::string name, int width, int height, std::vector<Vec4> texels, WrapMode wrapS,
            WrapMode wrapT);

    // Bilinear lookup at glTF texture coordinates (origin at the top-left texel corner).
    Vec4 sample(Vec2 uv) const;
    // Mean of all texels (used for light power estimates and radiosity albedos).
    Vec4 average() const { return average_; }

    const std::string& name() const { return name_; }
    int width() const { return width_; }
    int height() const { return height_; }

  private:
    Vec4 texel(int x, int y) const;

    std::string name_;
    int width_, height_;
    std::vector<Vec4> texels_;
    WrapMode wrapS_, wrapT_;
    Vec4 average_;
};

// The IEC 61966-2-1 sRGB electro-optical transfer function (decode to linear).
float srgbToLinear(float v);
// Its inverse (encode linear to sRGB).
float linearToSrgb(float v);

// KHR_texture_transform: uv' = T * R * S * uv (the extension's README, "Transform" section).
struct TextureTransform {
    Vec2 offset{0.0f};
    float rotation = 0.0f;  // radians, counter-clockwise in UV space
    Vec2 scale{1.0f};

    Vec2 apply(Vec2 uv) const;
};

// A material slot that may be textured: index into Scene::textures() or -1.
struct TextureRef {
    int texture = -1;
    int texCoord = 0;  // which TEXCOORD_n set (after KHR_texture_transform's override)
    TextureTransform transform;

    bool valid() const { return texture >= 0; }
};

}  // namespace penumbra
