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

    std::array<Vec2, 2> uvs{};
    const glm::uvec3 index = mesh_.triangles[triangle_];
    for (int set = 0; set < 2; ++set) {
        const auto& uv = mesh_.uvs[set];
        if (!uv.empty())
            uvs[set] = b.x * uv[index.x] + b.y * uv[index.y] + b.z * uv[index.z];
    }
    const Color L = emitted(uvs, -wi);
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
