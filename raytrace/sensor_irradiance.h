// Illuminance at calculation points: what a lighting designer's light meter reads, estimated by
// the same estimators that form images.
#pragma once

#include "core/math.h"
#include "core/scene.h"
#include "raytrace/radiance_estimator.h"

#include <cstdint>
#include <vector>

namespace penumbra {

class Sampler;
struct PathCounters;

// A flat sensor at p facing the unit normal n: it measures the light that arrives from the
// hemisphere n points into (a sensor lying on a surface reads the light above it, not the surface
// it lies on).
struct Sensor {
    Vec3 p{0.0f};
    Vec3 n{0.0f, 1.0f, 0.0f};
};

// One sample of the irradiance E = integral of L(w) cos(w, n) dw at the sensor, in lux per
// linear-sRGB channel. The sensor is a white Lambertian surface, whose reflected radiance is
// E / pi, so the estimator is pi times the reflected radiance at a first vertex:
//  - the light arriving directly (lights, emissive surfaces, the environment), by next-event
//    estimation and a cosine-weighted direction weighted against each other by the power heuristic
//    (estimateDirectLight, Veach 1997, Eq. 9.13);
//  - the light arriving after one or more scatterings, by what `incoming` estimates along a
//    second cosine-weighted direction, less what it sees directly there (its emission component,
//    which the first term holds).
// `incoming` is the estimator an image-forming pass takes camera rays with (the path tracer, the
// hybrid's reusing tracer, the radiosity view): the sensor reads the scene as that pass does, and
// is unbiased when it is.
Color sampleSensorIrradiance(const Scene& scene, const RadianceEstimator& incoming,
                             const Sensor& sensor, Sampler& sampler, PathCounters& counters);

}  // namespace penumbra

namespace penumbra {

class Progress;

struct IlluminanceSettings {
    int samples = 1024;      // per sensor, >= 2 (the target when timeLimit is set)
    uint32_t seed = 0;       // same seed, same results, whatever the thread count
    double timeLimit = 0.0;  // seconds, 0 = none: stop after a whole round of samples
};

struct SensorReading {
    double lux = 0.0;            // mean illuminance: Rec. 709 luminance Y of the irradiance
    double standardError = 0.0;  // of the mean, from the samples' variance
    int samples = 0;             // finite samples taken (non-finite ones are dropped)
    int dropped = 0;             // non-finite samples, a bug if ever non-zero
};

// Takes samples of sampleSensorIrradiance at every sensor, in parallel over the sensors, in
// rounds that double the count so far (the first round 16, or fewer if the target is smaller),
// until settings.samples or until the next round would end past settings.timeLimit (predicted
// from the rounds so far; at least two samples are always taken). Sample k of sensor i is the
// sampler's sample k of "pixel" (i, 0), so every sensor sees a stratified sequence.
std::vector<SensorReading> measureIlluminance(const Scene& scene, const RadianceEstimator& incoming,
                                              const std::vector<Sensor>& sensors,
                                              const IlluminanceSettings& settings,
                                              Progress* progress = nullptr);

}  // namespace penumbra
