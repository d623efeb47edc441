// The immutable scene a render works on: geometry with its acceleration structure, materials,
// textures, lights and the light-selection distribution. Built once from a SceneDescription
// (the second stage of loading) and passed around as `const Scene&`.
#pragma once

#include "core/accel.h"
#include "core/bsdf.h"
#include "core/environment_light.h"
#include "core/interaction.h"
#include "core/light.h"
#include "core/light_sampler.h"
#include "core/medium.h"
#include "core/ray.h"
#include "core/scene_description.h"

#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace penumbra {

class Scene {
  public:
    // Finds more portals for the environment on the scene's geometry (core/portal_detection.h),
    // called while the scene is built: after its geometry, before its lights, which it must not
    // use.
    using PortalFinder = std::function<std::vector<Portal>(const Scene&)>;

    explicit Scene(SceneDescription description, const PortalFinder& findPortals = nullptr);
    // Lights and the acceleration structure point into the description's arrays.
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    const SceneDescription& description() const { return desc_; }
    std::span<const Mesh> meshes() const { return desc_.meshes; }
    std::span<const Material> materials() const { return desc_.materials; }
    std::span<const Texture> textures() const { return desc_.textures; }
    std::span<const std::unique_ptr<Light>> lights() const { return lights_; }
    const PowerLightSampler& lightSampler() const { return *lightSampler_; }
    // What light `light` of lights() stands for in the description: a punctual light, a
    // luminaire, an emissive triangle of a material or the environment, and its index in
    // SceneDescription::lights, ::luminaires or ::materials (0 for the environment).
    struct LightOrigin {
        enum class Kind { Punctual, Luminaire, Emissive, Environment };
        Kind kind;
        size_t index;
    };
    const LightOrigin& lightOrigin(size_t light) const { return lightOrigins_[light]; }
    const Bounds3& bounds() const { return bounds_; }
    size_t triangleCount() const { return triangleCount_; }

    // Closest surface along the ray.
    std::optional<SurfaceHit> intersect(const Ray& ray) const;
    // The surface point at barycentric coordinates b of a triangle (t left at 0): what
    // intersect() returns for a ray that hits it there; also for passes that place their own
    // points on surfaces (radiosity elements).
    SurfaceHit surfaceAt(uint32_t mesh, uint32_t triangle, const Vec3& b) const;
    // A triangle's vertices, for callers that place many points on it and need only their
    // positions (a radiosity solve places millions of shadow-ray ends).
    struct Triangle {
        Vec3 p0, p1, p2;
        struct Point {
            Vec3 p, pError;  // as surfaceAt() gives them
        };
        Point at(const Vec3& b) const {
            return {b.x * p0 + b.y * p1 + b.z * p2, barycentricPointError(b, p0, p1, p2)};
        }
    };
    Triangle triangle(uint32_t mesh, uint32_t triangle) const;

    const Material& material(const SurfaceHit& hit) const { return desc_.materials[hit.material]; }
    // The BSDF at a hit, with the material's textures and normal map applied.
    Bsdf bsdf(const SurfaceHit& hit) const;
    // Radiance (cd/m²) the surface emits towards wo: front face only unless doubleSided.
    Color emitted(const SurfaceHit& hit, const Vec3& wo) const;
    // The area light of an emissive triangle, or -1.
    int lightIndex(const SurfaceHit& hit) const;
    // The environment light (SceneDescription::environment), or null: what a ray that leaves the
    // scene sees. Its index in lights() is environmentLightIndex() (-1 without one).
    const EnvironmentLight* environment() const { return environment_; }
    int environmentLightIndex() const { return environmentIndex_; }
    // Radiance (cd/m²) arriving along a ray that leaves the scene in unit direction d: the
    // environment's, black without one.
    Color escaped(const Vec3& d) const {
        return environment_ ? environment_->radiance(d) : Color(0.0f);
    }

    // The participating medium (SceneDescription::media, core/medium.h), or null.
    const Medium* medium() const { return medium_.get(); }

    // Transparent surfaces (straightTransmittance) a ray passes before it is treated as blocked:
    // the same for shadow rays, photons and the rays that look at a radiosity solution, so that
    // they agree. Architectural glazing has 2 to 6, foliage cut-outs a few more.
    static constexpr int kMaxTransparentLayers = 64;

    // Light passing straight through the surface towards -wo without changing direction:
    // alpha cut-outs (alphaMode MASK below the cutoff, BLEND by 1 - alpha) and thin-walled
    // transmission. Tracers treat it as transparency, not as a scattering vertex, in primary
    // rays, path continuation and shadow rays alike (so the two agree under MIS).
    Color straightTransmittance(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo) const;

    // Fraction of light carried unoccluded from point `to` to point `from` (both on surfaces,
    // with error bounds and normals for robust offsets; a zero normal means a point off any
    // surface). 0 when blocked, 1 when free, in between through transparent surfaces and the
    // medium (its transmittance over the segment).
    Color transmittance(const Vec3& from, const Vec3& fromError, const Vec3& fromNormal,
                        const Vec3& to, const Vec3& toError, const Vec3& toNormal) const;
    // Its two factors: the surfaces' (0 when blocked, straight-through transparency) and the
    // medium's over the straight segment (1 without a medium).
    Color surfaceTransmittance(const Vec3& from, const Vec3& fromError, const Vec3& fromNormal,
                               const Vec3& to, const Vec3& toError, const Vec3& toNormal) const;
    Color mediumTransmittance(const Vec3& from, const Vec3& to) const;

    // Ray leaving a surface hit in direction w, offset robustly off the surface.
    static Ray spawnRay(const SurfaceHit& hit, const Vec3& w);

  private:
    SceneDescription desc_;
    std::unique_ptr<Accel> accel_;
    std::vector<std::unique_ptr<Light>> lights_;
    std::vector<LightOrigin> lightOrigins_;  // per light
    std::unique_ptr<PowerLightSampler> lightSampler_;
    // For each mesh, the light index of each triangle (empty for non-emissive meshes).
    std::vector<std::vector<int>> triangleLights_;
    const EnvironmentLight* environment_ = nullptr;  // owned by lights_
    int environmentIndex_ = -1;
    Bounds3 bounds_;
    std::unique_ptr<Medium> medium_;
    size_t triangleCount_ = 0;
    bool hasTransparentSurfaces_ = false;  // if not, shadow rays need only an occlusion test
};

}  // namespace penumbra
