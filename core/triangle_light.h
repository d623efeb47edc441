// An emissive triangle as an area light (the glTF emissive material of the triangle).
#pragma once

#include "core/light.h"
#include "core/material.h"
#include "core/scene_description.h"

#include <array>
#include <span>

namespace penumbra {

// Emits radiance Le (cd/m²) from its front face (counter-clockwise winding), from both faces when
// the material is doubleSided. Sampled uniformly by area, converted to solid angle:
// pdf_omega = d² / (|cos theta_light| A) (pbrt-v4 section 12.2, Eq. 12.5 with the Jacobian of
// Eq. 4.9). Emission may be textured; it is evaluated at the sampled point. Photons (sampleLe)
// start uniformly on the triangle and leave cosine-weighted over the front hemisphere, or over
// either hemisphere with probability 1/2 each when the material is doubleSided.
class TriangleLight : public Light {
  public:
    TriangleLight(const Mesh& mesh, uint32_t triangle, const Material& material,
                  std::span<const Texture> textures);

    LightKind kind() const override { return LightKind::Area; }
    bool isDelta() const override { return false; }
    std::optional<LightLiSample> sampleLi(const LightSampleContext& ctx, Vec2 u) const override;
    float pdfLi(const LightSampleContext& ctx, const Vec3& wi,
                const SurfaceHit& lightHit) const override;
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    Color emittedLe(const LightLeSample& origin, const Vec3& w) const override;
    Color power() const override;
    std::string describe() const override;

    float area() const { return area_; }
    // Radiance leaving the light at a point with texture coordinates uvs in direction w.
    Color emitted(std::span<const Vec2> uvs, const Vec3& w) const;

  private:
    // Texture coordinates of both TEXCOORD sets at barycentrics b.
    std::array<Vec2, 2> uvsAt(const Vec3& b) const;

    const Mesh& mesh_;
    uint32_t triangle_;
    const Material& material_;
    std::span<const Texture> textures_;
    Vec3 p0_, p1_, p2_;
    Vec3 n_;  // unit geometric normal of the front face
    float area_;
};

}  // namespace penumbra
