// Stochastic progressive photon mapping (SPPM; Hachisuka and Jensen 2009, "Stochastic Progressive
// Photon Mapping", SIGGRAPH Asia) for the caustic paths L S+ D, so that the caustic converges to
// the right answer as iterations are added, not to a blurred one.
//
// Each measurement (a pixel, say) keeps statistics across iterations: a radius R, an accumulated
// photon count N and an accumulated flux tau. Every iteration the caller supplies a new visible
// point per measurement (the first D vertex of a new eye path through the pixel, with the path's
// throughput beta); a new batch of M_e photons is shot (the next part of one sample sequence,
// photon_tracer.h) and each visible point gathers the M photons within R that pass the leak tests
// (photon_kdtree.h), Phi = beta sum f(wo, wi_p) Phi_p. Then (radius reduction and flux correction
// of Hachisuka, Ogaki and Jensen 2008, "Progressive Photon Mapping", section 4, applied to the
// statistics SPPM shares between a pixel's visible points):
//     N' = N + alpha M,   R' = R sqrt((N + alpha M) / (N + M)),   tau' = (tau + Phi) R'² / R²
// and the radiance estimate is L = tau / (pi R² K) after K iterations (each photon's power is
// already divided by its batch's count M_e). alpha in (0, 1) keeps that fraction of the new
// photons: the radius shrinks, so the bias vanishes while the variance still falls (2/3 is the
// paper's choice).
//
// What it contains: the same light paths as CausticMap (L S+ D), weighted by beta.
#pragma once

#include "caustics/photon_tracer.h"
#include "core/interaction.h"
#include "core/stats.h"

#include <cstdint>
#include <span>
#include <vector>

namespace penumbra {

class Progress;
class Scene;

// The parameters of progressive caustics (keys as in the caustic pass):
//   photons_per_iteration (integer, 100000): photons shot per iteration, in [1, 2^32 - 1];
//   initial_radius (number, 0): R of every measurement before the first iteration, m; 0 = 5 % of
//                               the scene's bounding radius (CausticSettings' max_radius default);
//   alpha (number, 2/3): fraction of new photons kept, in (0, 1);
//   seed (integer, 0).
struct ProgressiveCausticSettings {
    int64_t photonsPerIteration = 100000;
    float initialRadius = 0.0f;
    float alpha = 2.0f / 3.0f;
    uint32_t seed = 0;
};

// Throws UsageError naming the key ("caustics.alpha: expected ...") for a value out of range.
void validateProgressiveCausticSettings(const ProgressiveCausticSettings& settings);

// One measurement's visible point in the current iteration.
struct VisiblePoint {
    SurfaceHit hit;
    Vec3 wo{0.0f};     // unit direction towards the eye
    Color beta{0.0f};  // eye path throughput up to the point; zero = no point this iteration
};

class ProgressiveCaustics {
  public:
    // Validates the settings. The scene must outlive this object.
    ProgressiveCaustics(const Scene& scene, size_t measurements,
                        const ProgressiveCausticSettings& settings);

    // One iteration: shoots a batch of photons (progress, may be null, advanced by one per
    // photon), gathers it at `points` (one per measurement, in the same order every iteration)
    // and updates every measurement. Parallel with oneTBB; deterministic.
    void iterate(std::span<const VisiblePoint> points, Progress* progress);

    // Radiance (cd/m² per channel, including beta) of measurement i after the iterations so far.
    Color radiance(size_t i) const;
    float radius(size_t i) const { return measurements_[i].radius; }
    int iterations() const { return iterations_; }

    // Iterations, photons shot and gathered, mean and smallest radius, seconds.
    PassStats stats() const;

  private:
    struct Measurement {
        float radius;
        double count = 0.0;  // N
        Color tau{0.0f};
    };

    const Scene& scene_;
    ProgressiveCausticSettings settings_;
    std::vector<Measurement> measurements_;
    int iterations_ = 0;
    uint64_t photonsShot_ = 0;
    uint64_t photonsStored_ = 0;
    double seconds_ = 0.0;
};

}  // namespace penumbra
