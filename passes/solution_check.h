// How far a radiosity solution is from the light it stands for, measured where a walkthrough
// shows it: at points drawn uniformly over the area of the meshed surfaces, the solution's
// reflected radiance against an independent estimate of the same quantity by the path tracer,
// rho E / pi, with E the irradiance that a sensor lying on the surface reads
// (raytrace/sensor_irradiance.h) and rho the reflectance the solver reflects with. `penumbra
// bake` reports it as the bake's expected error (docs/cli.md).
//
// The path tracer's estimate is noisy, and the squared error reported has its variance taken out:
// E[(b - t)^2] = (b - E[t])^2 + Var[t], t the traced mean, b the solution's value. Var[t] comes
// from two independent halves of the samples (two scramblings of the sampler's sequence), as
// (t_1 - t_2)^2 / 4, the replicate estimate of randomised quasi-Monte Carlo's variance (Owen 1997,
// "Scrambled net variance for integrals of smooth functions"; L'Ecuyer and Lemieux 2002): the
// samples' own variance would overstate it, as they are stratified (under a uniform sky it was 1.6
// times the true spread, and took the whole error out).
#pragma once

#include "core/math.h"

#include <cstdint>
#include <vector>

namespace penumbra {

class Progress;
class RadiosityMesh;
class RadiositySolution;
class Scene;

struct SolutionCheckSettings {
    int points = 256;   // drawn uniformly over the meshed area, > 0
    int samples = 256;  // path-traced sensor samples per point, >= 2 (two halves)
    uint32_t seed = 0;
};

// One point checked: luminances (cd/m²) of the reflected radiance.
struct CheckedPoint {
    Vec3 p{0.0f};
    Vec3 n{0.0f};                 // the element's front: the sensor faces it
    double solution = 0.0;        // what the solution shows there
    double traced = 0.0;          // the path tracer's mean
    double tracedVariance = 0.0;  // of that mean
    bool counted = false;         // drawn where something can see it
};

struct SolutionCheck {
    std::vector<CheckedPoint> points;  // the counted ones
    double meanTraced = 0.0;  // over the points: the lit surfaces' mean reflected luminance
    // The solution's mean error over the points, relative to meanTraced (negative: dark), and the
    // standard error of that figure, from the errors' spread over the points (which holds the
    // path tracer's noise and the draw of the points).
    double bias = 0.0, biasStandardError = 0.0;
    // The root mean square of the solution's error over the points, the traced noise taken out,
    // relative to meanTraced; and the noise's own share, sqrt(mean variance) / meanTraced.
    double rmsError = 0.0, noise = 0.0;
};

// Checks `solution` (on `mesh`, the mesh it was solved on) against the path tracer, on the front
// of each element, the side a bake shows (radiosity/bake.h). A point nothing can see (covered, as
// the floor under a block standing on it) is drawn again, up to 16 times, and left out after
// that; points holds those counted.
// Sample k of point i's halves is the sampler's sample k of "pixels" (i, 0) and (i, 2), so the
// result is the same whatever the thread count.
SolutionCheck checkSolution(const Scene& scene, const RadiosityMesh& mesh,
                            const RadiositySolution& solution,
                            const SolutionCheckSettings& settings, Progress* progress = nullptr);

}  // namespace penumbra
