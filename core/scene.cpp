#include "core/scene.h"

#include "core/goniometric_light.h"
#include "core/punctual_lights.h"
#include "core/triangle_light.h"

#include <stdexcept>

namespace penumbra {

namespace {

bool canBeTransparent(const Material& m) {
    return m.alphaMode != AlphaMode::Opaque || (m.transmission > 0.0f && m.thinWalled());
}

}  // namespace

Scene::Scene(SceneDescription description, const PortalFinder& findPortals)
    : desc_(std::move(description)) {
    for (const Mesh& mesh : desc_.meshes) {
        for (const Vec3& p : mesh.positions)
            bounds_.extend(p);
        triangleCount_ += mesh.triangles.size();
    }
    accel_ = std::make_unique<Accel>(desc_.meshes);
    if (desc_.media.size() > 1)
        throw std::logic_error("Scene: at most one participating medium");
    if (!desc_.media.empty()) {
        const MediumDesc& medium = desc_.media.front();
        medium_ = std::make_unique<Medium>(medium, medium.box.value_or(bounds_));
    }
    for (const Mesh& mesh : desc_.meshes) {
        hasTransparentSurfaces_ =
            hasTransparentSurfaces_ || canBeTransparent(desc_.materials[mesh.material]);
    }
    if (desc_.environment && findPortals) {
        const std::vector<Portal> found = findPortals(*this);
        desc_.environment->portals.insert(desc_.environment->portals.end(), found.begin(),
                                          found.end());
    }

    // Punctual lights and luminaires first, then one area light per emissive triangle, then the
    // environment.
    using Origin = LightOrigin::Kind;
    for (const PunctualLightDesc& light : desc_.lights) {
        lightOrigins_.push_back({Origin::Punctual, lightOrigins_.size()});
        switch (light.type) {
            case PunctualType::Point:
                lights_.push_back(std::make_unique<PointLight>(light));
                break;
            case PunctualType::Spot:
                lights_.push_back(std::make_unique<SpotLight>(light));
                break;
            case PunctualType::Directional:
                lights_.push_back(std::make_unique<DirectionalLight>(
                    light, bounds_.empty() ? Vec3(0.0f) : bounds_.center(),
                    bounds_.empty() ? 1.0f : bounds_.boundingRadius()));
                break;
        }
    }
    for (const LuminaireDesc& luminaire : desc_.luminaires) {
        lightOrigins_.push_back({Origin::Luminaire, lightOrigins_.size() - desc_.lights.size()});
        lights_.push_back(std::make_unique<GoniometricLight>(
            luminaire.table, luminaire.position, luminaire.luminaireToWorld, luminaire.color,
            luminaire.multiplier, luminaire.name));
    }
    triangleLights_.resize(desc_.meshes.size());
    for (size_t m = 0; m < desc_.meshes.size(); ++m) {
        const Mesh& mesh = desc_.meshes[m];
        const Material& material = desc_.materials[mesh.material];
        if (!material.isEmissive())
            continue;
        triangleLights_[m].assign(mesh.triangles.size(), -1);
        for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
            auto light = std::make_unique<TriangleLight>(mesh, t, material, desc_.textures);
            if (!(light->area() > 0.0f))
                continue;
            triangleLights_[m][t] = static_cast<int>(lights_.size());
            lightOrigins_.push_back({Origin::Emissive, size_t(mesh.material)});
            lights_.push_back(std::move(light));
        }
    }
    if (desc_.environment) {
        const EnvironmentDesc& env = *desc_.environment;
        auto light = std::make_unique<EnvironmentLight>(
            env.radiance, env.worldToLocal, env.scale,
            bounds_.empty() ? Vec3(0.0f) : bounds_.center(),
            bounds_.empty() ? 1.0f : bounds_.boundingRadius(), env.file, env.sun, env.portals);
        environment_ = light.get();
        environmentIndex_ = static_cast<int>(lights_.size());
        lightOrigins_.push_back({Origin::Environment, 0});
        lights_.push_back(std::move(light));
    }
    lightSampler_ = std::make_unique<PowerLightSampler>(lights_);
}

std::optional<SurfaceHit> Scene::intersect(const Ray& ray) const {
    const std::optional<RawHit> raw = accel_->intersect(ray);
    if (!raw)
        return std::nullopt;
    SurfaceHit hit =
        surfaceAt(raw->mesh, raw->triangle, Vec3(1.0f - raw->u - raw->v, raw->u, raw->v));
    hit.t = raw->t;
    return hit;
}

Scene::Triangle Scene::triangle(uint32_t meshIndex, uint32_t triangle) const {
    const Mesh& mesh = desc_.meshes[meshIndex];
    const glm::uvec3 index = mesh.triangles[triangle];
    return {mesh.positions[index.x], mesh.positions[index.y], mesh.positions[index.z]};
}

SurfaceHit Scene::surfaceAt(uint32_t meshIndex, uint32_t triangle, const Vec3& b) const {
    const Mesh& mesh = desc_.meshes[meshIndex];
    const glm::uvec3 index = mesh.triangles[triangle];
    const Triangle vertices = this->triangle(meshIndex, triangle);

    SurfaceHit hit;
    hit.barycentric = b;
    const Triangle::Point point = vertices.at(b);
    hit.p = point.p;
    hit.pError = point.pError;
    hit.ng = glm::normalize(glm::cross(vertices.p1 - vertices.p0, vertices.p2 - vertices.p0));
    hit.ns = hit.ng;
    if (!mesh.normals.empty()) {
        const Vec3 n =
            b.x * mesh.normals[index.x] + b.y * mesh.normals[index.y] + b.z * mesh.normals[index.z];
        const float len = glm::length(n);
        // Vertex normals that disagree with the winding are turned to the front side.
        if (len > 0.0f && std::isfinite(len))
            hit.ns = glm::dot(n, hit.ng) < 0.0f ? -n / len : n / len;
    }
    if (!mesh.tangents.empty()) {
        hit.tangent = b.x * mesh.tangents[index.x] + b.y * mesh.tangents[index.y] +
                      b.z * mesh.tangents[index.z];
    }
    for (int set = 0; set < 2; ++set) {
        const auto& uv = mesh.uvs[set];
        if (!uv.empty())
            hit.uv[set] = b.x * uv[index.x] + b.y * uv[index.y] + b.z * uv[index.z];
    }
    hit.mesh = meshIndex;
    hit.triangle = triangle;
    hit.material = mesh.material;
    return hit;
}

Bsdf Scene::bsdf(const SurfaceHit& hit) const {
    const Material& m = material(hit);
    const ShadingParams params = evaluateMaterial(m, desc_.textures, hit.uv);
    Vec3 n = hit.ns;
    const Vec3 tangent(hit.tangent);
    if (m.normalTexture.valid() && glm::dot(tangent, tangent) > 0.0f) {
        // Tangent-space normal map (glTF 2.0 spec, "normalTexture"): n = T x + B y + N z with
        // (x, y, z) = 2 texel - 1, x and y scaled by normalScale, B = w (N x T).
        const Frame tbn = Frame::fromNormalTangent(n, tangent);
        const float handedness = hit.tangent.w < 0.0f ? -1.0f : 1.0f;
        const Vec3 texel = Vec3(lookup(m.normalTexture, desc_.textures, hit.uv)) * 2.0f - 1.0f;
        const Vec3 mapped = tbn.s * (texel.x * m.normalScale) +
                            tbn.t * (handedness * texel.y * m.normalScale) + tbn.n * texel.z;
        const float len = glm::length(mapped);
        if (len > 0.0f && std::isfinite(len) && glm::dot(mapped, hit.ng) > 0.0f)
            n = mapped / len;
    }
    const Frame shading = glm::dot(tangent, tangent) > 0.0f ? Frame::fromNormalTangent(n, tangent)
                                                            : Frame::fromNormal(n);
    return Bsdf(params, shading, hit.ng);
}

Color Scene::emitted(const SurfaceHit& hit, const Vec3& wo) const {
    const Material& m = material(hit);
    if (!m.isEmissive())
        return Color(0.0f);
    if (!m.doubleSided && glm::dot(wo, hit.ng) <= 0.0f)
        return Color(0.0f);
    return evaluateEmission(m, desc_.textures, hit.uv);
}

int Scene::lightIndex(const SurfaceHit& hit) const {
    const std::vector<int>& lights = triangleLights_[hit.mesh];
    return lights.empty() ? -1 : lights[hit.triangle];
}

Color Scene::straightTransmittance(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo) const {
    const Material& m = material(hit);
    Color throughSurface = bsdf.straightTransmittance(wo);
    if (m.alphaMode == AlphaMode::Opaque)
        return throughSurface;
    const float alpha = m.baseAlpha * lookup(m.baseColorTexture, desc_.textures, hit.uv).a;
    if (m.alphaMode == AlphaMode::Mask)
        return alpha < m.alphaCutoff ? Color(1.0f) : throughSurface;
    // Blend: the surface covers a fraction alpha (glTF 2.0 spec, "Alpha Coverage").
    const float coverage = glm::clamp(alpha, 0.0f, 1.0f);
    return Color(1.0f - coverage) + coverage * throughSurface;
}

Ray Scene::spawnRay(const SurfaceHit& hit, const Vec3& w) {
    return Ray{offsetRayOrigin(hit.p, hit.pError, hit.ng, w), w};
}

Color Scene::transmittance(const Vec3& from, const Vec3& fromError, const Vec3& fromNormal,
                           const Vec3& to, const Vec3& toError, const Vec3& toNormal) const {
    const Color surfaces = surfaceTransmittance(from, fromError, fromNormal, to, toError, toNormal);
    if (!medium_ || !(maxComponent(surfaces) > 0.0f))
        return surfaces;
    return surfaces * mediumTransmittance(from, to);
}

Color Scene::mediumTransmittance(const Vec3& from, const Vec3& to) const {
    const Vec3 d = to - from;
    const float distance = glm::length(d);
    if (!medium_ || !(distance > 0.0f))
        return Color(1.0f);
    return medium_->transmittance(Ray{from, d / distance}, distance);
}

Color Scene::surfaceTransmittance(const Vec3& from, const Vec3& fromError, const Vec3& fromNormal,
                                  const Vec3& to, const Vec3& toError, const Vec3& toNormal) const {
    Color throughput(1.0f);
    Vec3 origin = from;
    Vec3 originError = fromError;
    Vec3 originNormal = fromNormal;
    const Vec3 toward = to - from;
    const Vec3 target =
        glm::dot(toNormal, toNormal) > 0.0f ? offsetRayOrigin(to, toError, toNormal, -toward) : to;
    for (int layer = 0; layer <= Scene::kMaxTransparentLayers; ++layer) {
        const Vec3 start = glm::dot(originNormal, originNormal) > 0.0f
                               ? offsetRayOrigin(origin, originError, originNormal, target - origin)
                               : origin;
        const Vec3 d = target - start;
        const float distance = glm::length(d);
        if (!(distance > 0.0f))
            return throughput;
        Ray ray{start, d / distance, distance * (1.0f - kShadowEpsilon)};
        if (!hasTransparentSurfaces_)
            return accel_->occluded(ray) ? Color(0.0f) : throughput;
        const std::optional<SurfaceHit> hit = intersect(ray);
        if (!hit)
            return throughput;
        if (!canBeTransparent(material(*hit)))
            return Color(0.0f);
        throughput *= straightTransmittance(*hit, bsdf(*hit), -ray.d);
        if (maxComponent(throughput) <= 0.0f)
            return Color(0.0f);
        origin = hit->p;
        originError = hit->pError;
        originNormal = hit->ng;
    }
    return Color(0.0f);
}

}  // namespace penumbra
