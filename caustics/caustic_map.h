// The caustic photon map: the photons of photon_tracer.h in a kd-tree, and the radiance they
// reflect, by k-nearest-neighbour density estimation (Jensen 2001, "Realistic Image Synthesis
// Using Photon Mapping", chapters 6 and 7).
//
// What it contains: the light of the paths L S+ D, i.e. light that reached a diffuse or rough
// glossy surface after one or more specular (delta) vertices, and nothing else: no emission, no
// direct light, no light that passed only through thin-walled glass (transparency, not S).
//
// Estimate at a receiving point x with normal n facing the viewer:
//     L(x, wo) = sum_p f(wo, wi_p) Phi_p W(d_p / r) / (c pi r²)   (Jensen 2001, chapter 7)
// over the nearest photons that pass the leak tests (below), W a kernel of support r
// and c pi r² its integral over the disc. r is the distance of the k-th nearest photon, which is
// itself left out of the sum, so that the estimate is unbiased where the density is uniform (the
// (k - 1) / (pi r_k²) estimator of Loftsgaarden and Quesenberry 1965: for photons of density
// lambda, pi r_k² lambda is Gamma(k, 1) distributed); with fewer than k photons within the maximum
// radius, r is the maximum radius and every photon found counts.
//
// Leaks through thin walls: only photons that pass the normal and disc tests of
// photon_kdtree.h count. Consequence: light transmitted through a rough translucent surface
// (D transmission) is not seen from the side opposite to where its photons arrived.
#pragma once

#include "caustics/photon_tracer.h"
#include "core/bsdf.h"
#include "core/interaction.h"
#include "core/stats.h"

#include <memory>
#include <optional>
#include <span>
#include <string>

namespace penumbra {

class Progress;
class Scene;

// The reconstruction kernel W(t), t = d / r in [0, 1], and its disc integral c pi r²:
//   cone:         1 - t (Jensen 2001, chapter 7, "cone filter" with constant 1), c = 1 - 2/3;
//   epanechnikov: 1 - t² (Silverman 1986, "Density Estimation for Statistics and Data
//                 Analysis", chapter 4, in two dimensions), c = 1/2;
//   gaussian:     1 - (1 - exp(-beta t²/2)) / (1 - exp(-beta)), beta = 1.953 (Pavicic 1990, as in
//                 Jensen 2001, chapter 7), c its exact disc integral (see caustic_map.cpp).
enum class CausticKernel { Cone, Epanechnikov, Gaussian };

// "cone", "epanechnikov", "gaussian": the kernel's name in pass scripts and the log.
std::string kernelName(CausticKernel kernel);

// The parameters of the caustic pass; their table (key, type, default, meaning) is at the top of
// caustic_map.cpp.
struct CausticSettings {
    int64_t photons = 200000;  // photons shot from the lights (not stored)
    int k = 50;                // nearest photons of the estimate
    float maxRadius = 0.0f;    // m; 0 = 5 % of the scene's bounding radius
    CausticKernel kernel = CausticKernel::Cone;
    uint32_t seed = 0;

    // The maximum radius, with the automatic default resolved for `scene`.
    float resolvedMaxRadius(const Scene& scene) const;
};

// Throws UsageError naming the key ("caustics.k: expected ...") for a value out of range.
void validateCausticSettings(const CausticSettings& settings);

class CausticMap {
  public:
    CausticMap(CausticMap&&) noexcept;
    CausticMap& operator=(CausticMap&&) noexcept;
    ~CausticMap();

    // Traces the photons (photon_tracer.h, `progress` advanced by one per photon; may be null)
    // and builds the kd-tree. Validates the settings first.
    static CausticMap build(const Scene& scene, const CausticSettings& settings,
                            Progress* progress);

    // Radiance (cd/m² per channel) the surface at `hit` reflects towards wo from the caustic
    // photons, with `bsdf` the BSDF at the hit (Scene::bsdf) and wo the unit direction towards
    // the viewer. Only the non-delta lobes take part (Bsdf::f), or the rough glossy ones alone
    // (for a tracer whose radiosity solution holds the Lambertian layer's share). Thread-safe.
    Color radiance(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                   ReflectingLobes lobes = ReflectingLobes::All) const;

    // The stored photons, in the kd-tree's storage.
    std::span<const Photon> photons() const;
    // The tracer's counts and powers (its photon list is empty: photons() has them).
    const PhotonTraceResult& trace() const;
    const CausticSettings& settings() const;
    float maxRadius() const;
    double seconds() const;  // to trace the photons and build the tree

    // Photons shot and stored, the fraction stored, the fraction whose first surface was
    // specular, stored power / emitted power, kernel, k, radius, time (s) and memory (MiB).
    PassStats stats() const;

  private:
    struct Data;
    explicit CausticMap(std::unique_ptr<Data> data);
    std::unique_ptr<Data> data_;
};

}  // namespace penumbra
