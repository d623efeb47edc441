#include "core/triangle_light.h"

#include "core/ray.h"
#include "core/sampling.h"

#include <array>
#include <sstream>

namespace penumbra {

TriangleLight::TriangleLight(const Mesh& mesh, uint32_t triangle, const Material& material,
                             std::span<const Texture> textures)
    : mesh_(mesh), triangle_(triangle), material_(material), textures_(textures) {
    const glm::uvec3 index = mesh.triangles[triangle];
    p0_ = mesh.positions[index.x];
    p1_ = mesh.positions[index.y];
    p2_ = mesh.positions[index.z];
    const Vec3 c = glm::cross(p1_ - p0_, p2_ - p0_);
    area_ = 0.5f * glm::length(c);
    n_ = area_ > 0.0f ? glm::normalize(c) : Vec3(0.0f, 0.0f, 1.0f);
}

std::array<Vec2, 2> TriangleLight::uvsAt(const Vec3& b) const {
    std::array<Vec2, 2> uvs{};
    const glm::uvec3 index = mesh_.triangles[triangle_];
    for (int set = 0; set < 2; ++set) {
        const auto& uv = mesh_.uvs[set];
        if (!uv.empty())
            uvs[set] = b.x * uv[index.x] + b.y * uv[index.y] + b.z * uv[index.z];
    }
    return uvs;
}

Color TriangleLight::emitted(std::span<const Vec2> uvs, const Vec3& w) const {
    if (!material_.doubleSided && glm::dot(w, n_) <= 0.0f)
        return Color(0.0f);
    return evaluateEmission(material_, textures_, uvs);
}

std::optional<LightLiSample> TriangleLight::sampleLi(const LightSampleContext& ctx, Vec2 u) const {
    if (!(area_ > 0.0f))
        return std::nullopt;
    const Vec3 b = sampleUniformTriangle(u);
    const Vec3 p = b.x * p0_ + b.y * p1_ + b.z * p2_;
    const Vec3 toLight = p - ctx.p;
    const float d2 = glm::dot(toLight, toLight);
    if (!(d2 > 0.0f))
        return std::nullopt;
    const Vec3 wi = toLight / std::sqrt(d2);
    const float cosLight = std::abs(glm::dot(wi, n_));
    if (!(cosLight > 0.0f))
        return std::nullopt;

    const Color L = emitted(uvsAt(b), -wi);
    if (maxComponent(L) <= 0.0f)
        return std::nullopt;

    LightLiSample sample;
    sample.L = L;
    sample.wi = wi;
    sample.pdf = d2 / (cosLight * area_);
    sample.pLight = p;
    sample.nLight = n_;
    sample.pLightError = barycentricPointError(b, p0_, p1_, p2_);
    return sample;
}

float TriangleLight::pdfLi(const LightSampleContext& ctx, const Vec3& wi,
                           const SurfaceHit& lightHit) const {
    if (!material_.doubleSided && glm::dot(-wi, n_) <= 0.0f)
        return 0.0f;
    const float cosLight = std::abs(glm::dot(wi, n_));
    const Vec3 toLight = lightHit.p - ctx.p;
    const float d2 = glm::dot(toLight, toLight);
    if (!(cosLight > 0.0f) || !(area_ > 0.0f))
        return 0.0f;
    return d2 / (cosLight * area_);
}

std::optional<LightLeSample> TriangleLight::sampleLe(Vec2 uPosition, Vec2 uDirection) const {
    if (!(area_ > 0.0f))
        return std::nullopt;
    LightLeSample s;
    s.b = sampleUniformTriangle(uPosition);
    s.p = s.b.x * p0_ + s.b.y * p1_ + s.b.z * p2_;
    s.pError = barycentricPointError(s.b, p0_, p1_, p2_);
    s.pdfPos = 1.0f / area_;
    // A doubleSided emitter picks its face with the first coordinate, rescaled to [0, 1) for
    // the hemisphere, so that both faces keep a stratified cosine distribution.
    Vec3 n = n_;
    float sideChoice = 1.0f;
    if (material_.doubleSided) {
        sideChoice = 0.5f;
        if (uDirection.x < 0.5f) {
            uDirection.x *= 2.0f;
        } else {
            uDirection.x = glm::min(2.0f * uDirection.x - 1.0f, 0.99999994f);
            n = -n_;
        }
    }
    const Vec3 local = sampleCosineHemisphere(uDirection);
    s.n = n;
    s.w = Frame::fromNormal(n).toWorld(local);
    s.pdfDir = sideChoice * cosineHemispherePdf(local.z);
    s.L = emitted(uvsAt(s.b), s.w);
    if (!(s.pdfDir > 0.0f) || maxComponent(s.L) <= 0.0f)
        return std::nullopt;
    return s;
}

Color TriangleLight::emittedLe(const LightLeSample& origin, const Vec3& w) const {
    return emitted(uvsAt(origin.b), w);
}

// A Lambertian emitter of radiance Le and area A emits Phi = pi A Le per face.
Color TriangleLight::power() const {
    const Color meanLe =
        material_.emissive * Color(material_.emissiveTexture.valid()
                                       ? textures_[material_.emissiveTexture.texture].average()
                                       : Vec4(1.0f));
    return (material_.doubleSided ? 2.0f : 1.0f) * kPi * area_ * meanLe;
}

std::string TriangleLight::describe() const {
    std::ostringstream out;
    out << "emissive triangle " << mesh_.name << "#" << triangle_;
    return out.str();
}

}  // namespace penumbra
