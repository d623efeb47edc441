#include "raytrace/sensor_irradiance.h"

#include "core/bsdf.h"
#include "core/progress.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/stats.h"
#include "raytrace/direct_light.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace penumbra {

namespace {

// The sensor's surface: a point with no triangle behind it. Its error bound keeps rays leaving a
// sensor placed on a scene surface clear of that surface: one part in 10^5 of the point's
// distance from the origin, a tenth of a millimetre for a room of 10 m, well above float rounding
// of the surface (a part in 10^7) and below any detail a sensor grid resolves.
SurfaceHit sensorSurface(const Sensor& sensor) {
    SurfaceHit hit;
    hit.p = sensor.p;
    const float extent =
        std::max({std::abs(sensor.p.x), std::abs(sensor.p.y), std::abs(sensor.p.z)});
    hit.pError = Vec3(1e-5f * (extent + 1.0f));
    hit.ng = sensor.n;
    hit.ns = sensor.n;
    hit.barycentric = Vec3(1.0f, 0.0f, 0.0f);
    return hit;
}

// A white Lambertian reflector (specular 0: no dielectric layer), f = 1 / pi.
Bsdf whiteLambertian(const Vec3& n) {
    ShadingParams white;
    white.baseColor = Color(1.0f);
    white.specular = 0.0f;
    white.roughness = 1.0f;
    return Bsdf(white, Frame::fromNormal(n), n);
}

}  // namespace

Color sampleSensorIrradiance(const Scene& scene, const RadianceEstimator& incoming,
                             const Sensor& sensor, Sampler& sampler, PathCounters& counters) {
    const SurfaceHit hit = sensorSurface(sensor);
    const Bsdf bsdf = whiteLambertian(sensor.n);
    const Color direct = estimateDirectLight(scene, hit, bsdf, sensor.n, sampler, counters);

    // Cosine-weighted: L cos / pdf = pi L.
    const Vec3 wi = Frame::fromNormal(sensor.n).toWorld(sampleCosineHemisphere(sampler.get2D()));
    const PathRadiance arriving = incoming(Scene::spawnRay(hit, wi), sampler, nullptr, counters);
    const Color scattered = arriving.total() - arriving[PathComponent::Emission];
    return kPi * (direct + scattered);
}

}  // namespace penumbra

namespace penumbra {

namespace {

// Running sums of one sensor's luminance samples.
struct SampleSums {
    double sum = 0.0;
    double sumOfSquares = 0.0;
    int count = 0;
    int dropped = 0;
};

void takeSamples(const Scene& scene, const RadianceEstimator& incoming, const Sensor& sensor,
                 int index, uint32_t seed, int first, int count, SampleSums& sums) {
    Sampler sampler(seed);
    PathCounters counters;
    for (int k = first; k < first + count; ++k) {
        sampler.startPixelSample(IVec2(index, 0), uint32_t(k));
        const double lux =
            luminance(sampleSensorIrradiance(scene, incoming, sensor, sampler, counters));
        if (!std::isfinite(lux)) {
            ++sums.dropped;
            continue;
        }
        sums.sum += lux;
        sums.sumOfSquares += lux * lux;
        ++sums.count;
    }
}

SensorReading reading(const SampleSums& sums) {
    SensorReading r;
    r.samples = sums.count;
    r.dropped = sums.dropped;
    if (sums.count == 0)
        return r;
    const double n = sums.count;
    r.lux = sums.sum / n;
    if (sums.count > 1) {
        const double variance = std::max(0.0, (sums.sumOfSquares - n * r.lux * r.lux) / (n - 1.0));
        r.standardError = std::sqrt(variance / n);
    }
    return r;
}

}  // namespace

std::vector<SensorReading> measureIlluminance(const Scene& scene, const RadianceEstimator& incoming,
                                              const std::vector<Sensor>& sensors,
                                              const IlluminanceSettings& settings,
                                              Progress* progress) {
    std::vector<SampleSums> sums(sensors.size());
    const auto start = std::chrono::steady_clock::now();
    int taken = 0;
    while (taken < settings.samples) {
        int round = std::min(settings.samples - taken, std::max(16, taken));
        if (settings.timeLimit > 0.0 && taken >= 2) {
            const double elapsed = secondsSince(start);
            const double perSample = elapsed / taken;
            const int affordable = int((settings.timeLimit - elapsed) / perSample);
            if (affordable < 1)
                break;
            round = std::min(round, affordable);
        }
        tbb::parallel_for(size_t(0), sensors.size(), [&](size_t i) {
            takeSamples(scene, incoming, sensors[i], int(i), settings.seed, taken, round, sums[i]);
            if (progress)
                progress->advance(uint64_t(round));
        });
        taken += round;
    }
    std::vector<SensorReading> readings;
    readings.reserve(sums.size());
    for (const SampleSums& s : sums)
        readings.push_back(reading(s));
    return readings;
}

}  // namespace penumbra
