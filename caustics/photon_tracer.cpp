#include "caustics/photon_tracer.h"

#include "core/progress.h"
#include "core/ray.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "core/scene_contents.h"
#include "core/surface_crossing.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>
#include <span>

namespace penumbra {

namespace {

// Photons per task: the unit of parallel work and of the deterministic merge.
constexpr uint64_t kChunkSize = 1024;
// Above this many specular meshes, one sphere around all of them is the target: the mixture
// density is evaluated over every sphere for every photon.
constexpr size_t kMaxTargets = 64;
// After this many S vertices, Russian roulette ends at least this fraction of the photons, so
// that a photon cannot bounce for ever between perfect mirrors (as the path tracer does).
constexpr int kRouletteStartDepth = 3;
constexpr float kMinTerminationProbability = 0.05f;

// Whether the BSDF of any triangle of the mesh has a delta lobe (or, with `sharpGlossy`, a sharp
// glossy one). The material's textures can change the lobes (a roughness map), so a textured
// material is checked at every triangle's centroid; an untextured one at its first triangle.
bool hasSpecularLobe(const Scene& scene, uint32_t meshIndex, bool sharpGlossy) {
    const Mesh& mesh = scene.meshes()[meshIndex];
    const Material& m = scene.materials()[mesh.material];
    const bool textured = m.metallicRoughnessTexture.valid() || m.transmissionTexture.valid();
    const size_t count =
        textured ? mesh.triangles.size() : std::min<size_t>(1, mesh.triangles.size());
    for (uint32_t t = 0; t < count; ++t) {
        const SurfaceHit hit = scene.surfaceAt(meshIndex, t, Vec3(1.0f / 3.0f));
        const Bsdf bsdf = scene.bsdf(hit);
        if ((bsdf.lobes() & kLobeSpecular) || (sharpGlossy && bsdf.hasSharpGlossyLobe()))
            return true;
    }
    return false;
}

// The mesh's bounding sphere, a little larger: rounding must not let a grazing photon miss the
// sphere but hit the mesh.
Sphere aimSphere(const Mesh& mesh) {
    Sphere s = boundingSphere(mesh);
    s.radius = s.radius * (1.0f + 1e-4f) + 1e-6f;
    return s;
}

// The spheres photons are aimed at: one per mesh with a delta (or sharp glossy) lobe, or one
// around all of them.
std::vector<Sphere> aimTargets(const Scene& scene, bool sharpGlossy, int& specularMeshes) {
    std::vector<Sphere> targets;
    Bounds3 all;
    for (uint32_t m = 0; m < scene.meshes().size(); ++m) {
        const Mesh& mesh = scene.meshes()[m];
        if (mesh.triangles.empty() || !hasSpecularLobe(scene, m, sharpGlossy))
            continue;
        targets.push_back(aimSphere(mesh));
        for (const Vec3& p : mesh.positions)
            all.extend(p);
    }
    specularMeshes = static_cast<int>(targets.size());
    if (targets.size() > kMaxTargets) {
        const float radius = all.boundingRadius() * (1.0f + 1e-4f) + 1e-6f;
        targets.assign(1, Sphere{all.center(), radius});
    }
    return targets;
}

// The cone of directions from a point towards a sphere: its axis, the cosine of its half angle
// and its solid angle 2 pi (1 - cos), written as 2 pi sin² / (1 + cos) to keep the precision of
// small cones. From inside the sphere, every direction (cos = -1, 4 pi).
struct Cone {
    Vec3 axis;
    float cosMax;
    float solidAngle;

    bool contains(const Vec3& w) const { return glm::dot(w, axis) >= cosMax; }
};

Cone coneTowards(const Vec3& origin, const Sphere& s) {
    const Vec3 toCenter = s.center - origin;
    const float d2 = glm::dot(toCenter, toCenter);
    if (d2 <= sqr(s.radius))
        return Cone{Vec3(0.0f, 0.0f, 1.0f), -1.0f, 4.0f * kPi};
    const float sin2 = sqr(s.radius) / d2;
    const float cosMax = safeSqrt(1.0f - sin2);
    return Cone{toCenter / std::sqrt(d2), cosMax, 2.0f * kPi * sin2 / (1.0f + cosMax)};
}

// A direction from a mixture of uniform cones chosen in proportion to their solid angles; the
// mixture's density is (number of cones containing w) / (sum of solid angles) (a one-sample
// mixture: Veach 1997, chapter 9, the one-sample model). Nothing if every cone is empty.
struct AimedDirection {
    Vec3 w;
    float pdf;  // solid angle
};

std::optional<AimedDirection> sampleCones(std::span<const Cone> cones, float uChoice, Vec2 u) {
    float total = 0.0f;
    for (const Cone& c : cones)
        total += c.solidAngle;
    if (!(total > 0.0f))
        return std::nullopt;
    float target = uChoice * total;
    size_t chosen = cones.size() - 1;
    for (size_t i = 0; i < cones.size(); ++i) {
        if (target < cones[i].solidAngle) {
            chosen = i;
            break;
        }
        target -= cones[i].solidAngle;
    }
    const Cone& c = cones[chosen];
    const Vec3 w =
        glm::normalize(Frame::fromNormal(c.axis).toWorld(sampleUniformCone(u, c.cosMax)));
    int covering = 0;
    for (const Cone& other : cones)
        covering += other.contains(w) ? 1 : 0;
    // The chosen cone contains w up to rounding.
    covering = std::max(covering, 1);
    return AimedDirection{w, covering / total};
}

// The same mixture for a directional light: the origin is drawn uniformly on one of the discs
// that the spheres project onto its emission plane, chosen in proportion to their areas; density
// (per m²) = (number of discs containing the origin) / (sum of their areas).
struct AimedOrigin {
    Vec3 p;
    float pdf;  // area
};

AimedOrigin sampleDiscs(std::span<const Sphere> targets, const LightLeSample& plane, float uChoice,
                        Vec2 u) {
    const Frame frame = Frame::fromNormal(plane.w);
    float total = 0.0f;
    for (const Sphere& s : targets)
        total += kPi * sqr(s.radius);
    const auto project = [&](const Vec3& c) {
        return c - plane.w * glm::dot(c - plane.p, plane.w);
    };
    float target = uChoice * total;
    size_t chosen = targets.size() - 1;
    for (size_t i = 0; i < targets.size(); ++i) {
        const float area = kPi * sqr(targets[i].radius);
        if (target < area) {
            chosen = i;
            break;
        }
        target -= area;
    }
    const Vec2 d = sampleConcentricDisk(u) * targets[chosen].radius;
    const Vec3 p = project(targets[chosen].center) + frame.s * d.x + frame.t * d.y;
    int covering = 0;
    for (const Sphere& s : targets)
        covering += glm::distance(p, project(s.center)) <= s.radius ? 1 : 0;
    return AimedOrigin{p, std::max(covering, 1) / total};
}

struct ChunkResult {
    std::vector<Photon> photons;
    uint64_t aimedAtSpecular = 0;
};

// A photon's first ray and its flux (lm per channel), before the division by the photon count.
struct Emitted {
    Ray ray;
    Color beta;
};

class Tracer {
  public:
    // Photons from the scene's lights, or from `surfaces` when given (it must outlive this).
    Tracer(const Scene& scene, const PhotonTracerSettings& settings, std::vector<Sphere> targets,
           const SurfaceEmitter* surfaces = nullptr)
        : scene_(scene), settings_(settings), targets_(std::move(targets)), surfaces_(surfaces) {}

    void trace(uint64_t index, ChunkResult& out) const {
        Sampler sampler(settings_.seed);
        sampler.startPixelSample(IVec2(0, 0), static_cast<uint32_t>(settings_.firstIndex + index));
        const std::optional<Emitted> emitted =
            surfaces_ ? emitFromSurface(sampler) : emitFromLight(sampler);
        if (!emitted)
            return;
        // Each of the N photons carries 1/N of the estimate (Jensen 2001, chapter 5).
        const Color beta = emitted->beta / static_cast<float>(settings_.photons);
        if (!(maxComponent(beta) > 0.0f) || !isFinite(beta))
            return;
        followPath(emitted->ray, beta, sampler, out);
    }

  private:
    // A direction from p aimed at the specular meshes' spheres.
    std::optional<AimedDirection> aimFrom(const Vec3& p, float uTarget, Vec2 uDirection) const {
        std::vector<Cone> cones;
        cones.reserve(targets_.size());
        for (const Sphere& s : targets_)
            cones.push_back(coneTowards(p, s));
        return sampleCones(cones, uTarget, uDirection);
    }

    // The aimed ray and its flux divided by the light's selection probability.
    std::optional<Emitted> emitFromLight(Sampler& sampler) const {
        const auto choice = scene_.lightSampler().sample(sampler.get1D());
        if (!choice)
            return std::nullopt;
        const Light& light = *scene_.lights()[choice->light];
        const Vec2 uPosition = sampler.get2D();
        const Vec2 uDirection = sampler.get2D();
        const float uTarget = sampler.get1D();
        const std::optional<LightLeSample> origin = light.sampleLe(uPosition, uDirection);
        if (!origin)
            return std::nullopt;
        // A light at infinity sends its photon along the direction it chose (pdfDir 1 for a
        // directional light) from a point aimed at the targets' discs across that direction,
        // drawn with numbers the light's own choice did not use: a directional light ignores
        // uDirection; the environment's origin, drawn from uPosition, is replaced.
        if (light.kind() == LightKind::Directional || light.kind() == LightKind::Environment) {
            const Vec2 uDisc = light.kind() == LightKind::Environment ? uPosition : uDirection;
            const AimedOrigin o = sampleDiscs(targets_, *origin, uTarget, uDisc);
            return Emitted{Ray{o.p, origin->w}, origin->L / (o.pdf * origin->pdfDir * choice->pmf)};
        }
        const std::optional<AimedDirection> d = aimFrom(origin->p, uTarget, uDirection);
        if (!d)
            return std::nullopt;
        const Color L = light.emittedLe(*origin, d->w);
        const bool area = glm::dot(origin->n, origin->n) > 0.0f;
        const float cosTheta = area ? std::abs(glm::dot(origin->n, d->w)) : 1.0f;
        const Vec3 o =
            area ? offsetRayOrigin(origin->p, origin->pError, origin->n, d->w) : origin->p;
        return Emitted{Ray{o, d->w}, L * (cosTheta / (origin->pdfPos * d->pdf * choice->pmf))};
    }

    // The same for a Lambertian surface point: radiance L into its hemisphere.
    std::optional<Emitted> emitFromSurface(Sampler& sampler) const {
        const float uChoice = sampler.get1D();
        const Vec2 uPosition = sampler.get2D();
        const Vec2 uDirection = sampler.get2D();
        const float uTarget = sampler.get1D();
        const std::optional<SurfaceEmission> origin = (*surfaces_)(uChoice, uPosition);
        if (!origin || !(origin->pdf > 0.0f))
            return std::nullopt;
        const std::optional<AimedDirection> d = aimFrom(origin->p, uTarget, uDirection);
        if (!d)
            return std::nullopt;
        const float cosTheta = glm::dot(origin->n, d->w);
        if (!(cosTheta > 0.0f))
            return std::nullopt;
        return Emitted{Ray{offsetRayOrigin(origin->p, origin->pError, origin->n, d->w), d->w},
                       origin->L * (cosTheta / (origin->pdf * d->pdf))};
    }

    void followPath(Ray ray, Color beta, Sampler& sampler, ChunkResult& out) const {
        int specularVertices = 0;
        int sharpGlossyVertices = 0;  // among them
        int transparentLayers = 0;
        bool firstSurface = true;
        while (true) {
            const std::optional<SurfaceHit> hit = scene_.intersect(ray);
            if (!hit)
                return;
            beta *= volumeAttenuation(scene_, *hit, ray.d);
            const Bsdf bsdf = scene_.bsdf(*hit);
            const Vec3 wo = -ray.d;

            // Straight-through transparency, as for camera paths (core/surface_crossing.h).
            const StraightThrough straight = chooseStraightThrough(scene_, *hit, bsdf, wo, sampler);
            beta *= straight.weight;
            if (straight.passes) {
                if (++transparentLayers > Scene::kMaxTransparentLayers)
                    return;
                ray = Scene::spawnRay(*hit, ray.d);
                continue;
            }
            const bool sharpGlossy = settings_.throughSharpGlossy && bsdf.hasSharpGlossyLobe();
            if (firstSurface) {
                firstSurface = false;
                if ((bsdf.lobes() & kLobeSpecular) || sharpGlossy)
                    ++out.aimedAtSpecular;
            }

            // Store at a D surface after at least one S vertex, on a side that reflects.
            const bool front = hit->frontFace(ray.d);
            if (specularVertices > 0 && bsdf.hasNonDeltaLobe() &&
                (front || scene_.material(*hit).doubleSided) &&
                (!settings_.onlyThroughSharpGlossy || sharpGlossyVertices > 0)) {
                out.photons.push_back(Photon{hit->p, wo, beta, front ? hit->ng : -hit->ng,
                                             hit->mesh, hit->triangle, hit->barycentric});
            }
            if (specularVertices >= settings_.maxSpecularBounces)
                return;

            // Continue through S vertices only: a delta lobe's sample, or a sharp glossy lobe's
            // share of any sample (fGlossy over the mixture's pdf, whichever strategy drew wi:
            // unbiased for the glossy lobes' part of the integral, as any integrand over a
            // mixture's density is; Veach 1997, chapter 9, the one-sample model).
            const float uLobe = sampler.get1D();
            const Vec2 u = sampler.get2D();
            const std::optional<BsdfSample> bs =
                bsdf.sample(wo, uLobe, u, TransportMode::Importance);
            if (!bs || !(bs->pdf > 0.0f) || !(bs->isDelta() || sharpGlossy))
                return;
            const Color f =
                bs->isDelta() ? bs->f : bsdf.fGlossy(wo, bs->wi, TransportMode::Importance);
            if (!bs->isDelta())
                ++sharpGlossyVertices;
            const Vec3& ns = bsdf.shadingNormal();
            const float cosWiNs = std::abs(glm::dot(bs->wi, ns));
            const float cosWoNg = std::abs(glm::dot(wo, hit->ng));
            if (!(cosWiNs > 0.0f) || !(cosWoNg > 0.0f))
                return;
            // The adjoint BSDF with shading normals (Veach 1997, "Robust Monte Carlo Methods for
            // Light Transport Simulation", section 5.3): importance is scattered by
            // f |wo.ns| |wi.ng| / |wo.ng| rather than f |wi.ns|.
            Color next = beta * f * (cosWiNs / bs->pdf) *
                         (std::abs(glm::dot(wo, ns)) * std::abs(glm::dot(bs->wi, hit->ng)) /
                          (cosWoNg * cosWiNs));
            ++specularVertices;

            // Russian roulette keeps the photon's power near its current value (Jensen 2001,
            // chapter 5; Arvo and Kirk 1990): survive with probability min(1, new / old).
            float survive = glm::min(1.0f, maxComponent(next) / maxComponent(beta));
            if (specularVertices >= kRouletteStartDepth)
                survive = glm::min(survive, 1.0f - kMinTerminationProbability);
            if (!(survive > 0.0f) || sampler.get1D() >= survive)
                return;
            beta = next / survive;
            if (!isFinite(beta))
                return;
            ray = Scene::spawnRay(*hit, bs->wi);
        }
    }

    const Scene& scene_;
    const PhotonTracerSettings& settings_;
    std::vector<Sphere> targets_;
    const SurfaceEmitter* surfaces_;  // null: the lights
};

// Shoots the photons of `tracer` in parallel and gathers the stored ones in photon order.
void shoot(const Tracer& tracer, const PhotonTracerSettings& settings, Progress* progress,
           PhotonTraceResult& result) {
    const uint64_t chunks = (settings.photons + kChunkSize - 1) / kChunkSize;
    std::vector<ChunkResult> results(chunks);
    tbb::parallel_for(tbb::blocked_range<uint64_t>(0, chunks), [&](const auto& range) {
        for (uint64_t c = range.begin(); c != range.end(); ++c) {
            const uint64_t begin = c * kChunkSize;
            const uint64_t end = std::min(settings.photons, begin + kChunkSize);
            for (uint64_t i = begin; i < end; ++i)
                tracer.trace(i, results[c]);
            if (progress)
                progress->advance(end - begin);
        }
    });

    size_t stored = 0;
    for (const ChunkResult& r : results)
        stored += r.photons.size();
    result.photons.reserve(stored);
    for (ChunkResult& r : results) {
        result.aimedAtSpecular += r.aimedAtSpecular;
        for (const Photon& p : r.photons)
            result.storedPower += p.power;
        result.photons.insert(result.photons.end(), r.photons.begin(), r.photons.end());
        r.photons = {};
    }
    result.shot = settings.photons;
}

}  // namespace

PhotonTraceResult tracePhotons(const Scene& scene, const PhotonTracerSettings& settings,
                               Progress* progress) {
    PhotonTraceResult result;
    for (const auto& light : scene.lights())
        result.emittedPower += light->power();
    std::vector<Sphere> targets =
        aimTargets(scene, settings.throughSharpGlossy, result.specularMeshes);
    if (targets.empty() || scene.lights().empty() || settings.photons == 0)
        return result;
    shoot(Tracer(scene, settings, std::move(targets)), settings, progress, result);
    return result;
}

PhotonTraceResult tracePhotonsFromSurfaces(const Scene& scene, const SurfaceEmitter& emitter,
                                           const Color& emittedPower,
                                           const PhotonTracerSettings& settings,
                                           Progress* progress) {
    PhotonTraceResult result;
    result.emittedPower = emittedPower;
    std::vector<Sphere> targets =
        aimTargets(scene, settings.throughSharpGlossy, result.specularMeshes);
    if (targets.empty() || !(maxComponent(emittedPower) > 0.0f) || settings.photons == 0)
        return result;
    shoot(Tracer(scene, settings, std::move(targets), &emitter), settings, progress, result);
    return result;
}

}  // namespace penumbra
