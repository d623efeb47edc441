#include "core/punctual_lights.h"

#include "core/sampling.h"

#include <sstream>

namespace penumbra {

float punctualAttenuation(float distance, float range) {
    const float d2 = distance * distance;
    if (range <= 0.0f)
        return 1.0f / d2;
    const float window = glm::clamp(1.0f - std::pow(distance / range, 4.0f), 0.0f, 1.0f);
    return window / d2;
}

PointLight::PointLight(const PunctualLightDesc& desc) : desc_(desc) {}

Color PointLight::intensity(const Vec3&) const {
    return desc_.color * desc_.intensity;
}

std::optional<LightLiSample> PointLight::sampleLi(const LightSampleContext& ctx, Vec2) const {
    const Vec3 toLight = desc_.position - ctx.p;
    const float distance = glm::length(toLight);
    if (!(distance > 0.0f))
        return std::nullopt;
    const Vec3 wi = toLight / distance;
    const Color L = intensity(-wi) * punctualAttenuation(distance, desc_.range);
    if (maxComponent(L) <= 0.0f)
        return std::nullopt;
    return LightLiSample{L, wi, 1.0f, desc_.position, Vec3(0.0f), Vec3(0.0f)};
}

std::optional<LightLeSample> PointLight::sampleLe(Vec2, Vec2 uDirection) const {
    LightLeSample s;
    s.p = desc_.position;
    s.w = sampleUniformSphere(uDirection);
    s.L = intensity(s.w);
    s.pdfPos = 1.0f;
    s.pdfDir = kInv4Pi;
    if (maxComponent(s.L) <= 0.0f)
        return std::nullopt;
    return s;
}

// Phi = 4 pi I for an isotropic point source.
Color PointLight::power() const {
    return 4.0f * kPi * desc_.color * desc_.intensity;
}

std::string PointLight::describe() const {
    std::ostringstream out;
    out << (kind() == LightKind::Spot ? "spot" : "point") << " '" << desc_.name << "' "
        << desc_.intensity << " cd";
    return out.str();
}

SpotLight::SpotLight(const PunctualLightDesc& desc)
    : PointLight(desc),
      cosOuter_(std::cos(desc.outerConeAngle)),
      cosInner_(std::cos(desc.innerConeAngle)) {}

// The extension's README, "Inner and Outer Cone Angles": a linear ramp in cos between the
// cones, squared for a smoother falloff.
Color SpotLight::intensity(const Vec3& w) const {
    const float cosTheta = glm::dot(w, desc_.direction);
    const float scale = 1.0f / glm::max(0.001f, cosInner_ - cosOuter_);
    const float offset = -cosOuter_ * scale;
    const float falloff = sqr(glm::clamp(cosTheta * scale + offset, 0.0f, 1.0f));
    return desc_.color * desc_.intensity * falloff;
}

std::optional<LightLeSample> SpotLight::sampleLe(Vec2, Vec2 uDirection) const {
    // Nothing is emitted outside the outer cone, so sampling it alone loses nothing.
    const Frame frame = Frame::fromNormal(desc_.direction);
    LightLeSample s;
    s.p = desc_.position;
    s.w = frame.toWorld(sampleUniformCone(uDirection, cosOuter_));
    s.L = intensity(s.w);
    s.pdfPos = 1.0f;
    s.pdfDir = 1.0f / (2.0f * kPi * (1.0f - cosOuter_));
    if (maxComponent(s.L) <= 0.0f || !std::isfinite(s.pdfDir))
        return std::nullopt;
    return s;
}

// Integral of the falloff over the sphere, with x = cos theta and the ramp
// t = (x - cos_outer) / delta, delta = max(0.001, cos_inner - cos_outer): full intensity from the
// ramp's end x1 to 1, 2 pi (1 - x1), plus the ramp integrated exactly,
// 2 pi * integral_{cos_outer}^{x1} t^2 dx = 2 pi (x1 - cos_outer)^3 / (3 delta^2).
// x1 = cos_outer + delta is cos_inner unless the cones nearly coincide, and is cut at 1 when the
// whole outer cone is narrower than 0.001 in cos (outer < 2.56 degrees): such a spot never
// reaches full intensity.
Color SpotLight::power() const {
    const float delta = glm::max(0.001f, cosInner_ - cosOuter_);
    const float ramp = glm::min(delta, 1.0f - cosOuter_);  // x1 - cos_outer
    const float rampEnd = cosOuter_ + ramp;
    const float solidAngle =
        2.0f * kPi * (1.0f - rampEnd) + 2.0f * kPi * ramp * ramp * ramp / (3.0f * delta * delta);
    return desc_.color * desc_.intensity * solidAngle;
}

DirectionalLight::DirectionalLight(const PunctualLightDesc& desc, const Vec3& sceneCenter,
                                   float sceneRadius)
    : desc_(desc), sceneCenter_(sceneCenter), sceneRadius_(glm::max(sceneRadius, 1e-6f)) {}

std::optional<LightLiSample> DirectionalLight::sampleLi(const LightSampleContext& ctx, Vec2) const {
    const Vec3 wi = -desc_.direction;
    // A target beyond the scene's bounding sphere, whatever the receiver's position.
    const float reach = glm::length(ctx.p - sceneCenter_) + 2.0f * sceneRadius_;
    const Vec3 pLight = ctx.p + wi * reach;
    return LightLiSample{desc_.color * desc_.intensity, wi, 1.0f, pLight, Vec3(0.0f), Vec3(0.0f)};
}

std::optional<LightLeSample> DirectionalLight::sampleLe(Vec2 uPosition, Vec2) const {
    const Frame frame = Frame::fromNormal(desc_.direction);
    const Vec2 d = sampleConcentricDisk(uPosition) * sceneRadius_;
    LightLeSample s;
    s.p = sceneCenter_ - desc_.direction * sceneRadius_ + frame.s * d.x + frame.t * d.y;
    s.w = desc_.direction;
    s.L = desc_.color * desc_.intensity;
    s.pdfPos = 1.0f / (kPi * sqr(sceneRadius_));
    s.pdfDir = 1.0f;
    if (maxComponent(s.L) <= 0.0f)
        return std::nullopt;
    return s;
}

Color DirectionalLight::emittedLe(const LightLeSample&, const Vec3& w) const {
    return w == desc_.direction ? desc_.color * desc_.intensity : Color(0.0f);
}

// Flux through the disk that the scene's bounding sphere presents to the light: E pi r².
Color DirectionalLight::power() const {
    return desc_.color * desc_.intensity * kPi * sqr(sceneRadius_);
}

std::string DirectionalLight::describe() const {
    std::ostringstream out;
    out << "directional '" << desc_.name << "' " << desc_.intensity << " lx";
    return out.str();
}

}  // namespace penumbra
