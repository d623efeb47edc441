// KHR_lights_punctual: point, spot and directional lights.
#pragma once

#include "core/light.h"
#include "core/scene_description.h"

namespace penumbra {

// Point light of intensity I (cd): Li = I / d² times the range window. Photons (sampleLe) leave
// it uniformly over the sphere and ignore the range window, which the extension defines as a
// cut-off hint for real-time renderers.
class PointLight : public Light {
  public:
    explicit PointLight(const PunctualLightDesc& desc);

    LightKind kind() const override { return LightKind::Point; }
    bool isDelta() const override { return true; }
    std::optional<LightLiSample> sampleLi(const LightSampleContext& ctx, Vec2 u) const override;
    float pdfLi(const LightSampleContext&, const Vec3&, const SurfaceHit&) const override {
        return 0.0f;
    }
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    Color emittedLe(const LightLeSample&, const Vec3& w) const override { return intensity(w); }
    Color power() const override;
    std::string describe() const override;

  protected:
    // Intensity (cd per channel) emitted in unit direction w away from the light.
    virtual Color intensity(const Vec3& w) const;

    PunctualLightDesc desc_;
};

// Spot light: a point light with the cone falloff of KHR_lights_punctual. Photons leave it
// uniformly over the outer cone.
class SpotLight : public PointLight {
  public:
    explicit SpotLight(const PunctualLightDesc& desc);

    LightKind kind() const override { return LightKind::Spot; }
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    Color power() const override;

  protected:
    Color intensity(const Vec3& w) const override;

  private:
    float cosOuter_, cosInner_;
};

// Directional light of illuminance E (lux) on a surface perpendicular to it. Photons start
// uniformly on the disc of the scene's bounding sphere's radius, perpendicular to the light,
// one radius behind the sphere's centre (pbrt-v4's DistantLight::SampleLe), so that they cross
// the whole scene.
class DirectionalLight : public Light {
  public:
    // sceneRadius bounds the scene, to place shadow-ray targets outside it and to estimate power.
    DirectionalLight(const PunctualLightDesc& desc, const Vec3& sceneCenter, float sceneRadius);

    LightKind kind() const override { return LightKind::Directional; }
    bool isDelta() const override { return true; }
    std::optional<LightLiSample> sampleLi(const LightSampleContext& ctx, Vec2 u) const override;
    float pdfLi(const LightSampleContext&, const Vec3&, const SurfaceHit&) const override {
        return 0.0f;
    }
    std::optional<LightLeSample> sampleLe(Vec2 uPosition, Vec2 uDirection) const override;
    Color emittedLe(const LightLeSample& origin, const Vec3& w) const override;
    Color power() const override;
    std::string describe() const override;

  private:
    PunctualLightDesc desc_;
    Vec3 sceneCenter_;
    float sceneRadius_;
};

// Distance attenuation of KHR_lights_punctual with its recommended range window
// (the extension's README, "Range Property"): 1/d² inside the range, smoothly falling to zero
// at it; range 0 means infinite.
float punctualAttenuation(float distance, float range);

}  // namespace penumbra
