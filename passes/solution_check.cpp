#include "passes/solution_check.h"

#include "core/progress.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "core/scene.h"
#include "radiosity/element_exposure.h"
#include "radiosity/radiosity_mesh.h"
#include "radiosity/radiosity_solution.h"
#include "raytrace/path_tracer.h"
#include "raytrace/sensor_irradiance.h"

#include <tbb/parallel_for.h>

#include <cmath>

namespace penumbra {

namespace {

// A point uniform over the leaves' area: a leaf by its area, then a point uniform in it.
struct DrawnPoint {
    int element = -1;
    Vec3 b{0.0f};  // barycentric weights in the element's scene triangle
};

DrawnPoint drawPoint(const RadiosityMesh& mesh, const std::vector<int>& leaves,
                     const std::vector<double>& cdf, Sampler& sampler) {
    const CdfEntry entry = invertCdf(cdf, sampler.get1D());
    const int element = leaves[entry.index];
    const Vec3 w = sampleUniformTriangle(sampler.get2D());
    const auto& corners = mesh.barycentrics(element);
    return {element, w.x * corners[0] + w.y * corners[1] + w.z * corners[2]};
}

// A point drawn inside a closed object (the floor under a block standing on it) or under a
// coincident face is seen by nothing: it is drawn again, up to this many times.
constexpr uint32_t kDrawAttempts = 16;

}  // namespace

SolutionCheck checkSolution(const Scene& scene, const RadiosityMesh& mesh,
                            const RadiositySolution& solution,
                            const SolutionCheckSettings& settings, Progress* progress) {
    const std::vector<int> leaves = mesh.leafElements();
    std::vector<double> areas(leaves.size());
    for (size_t i = 0; i < leaves.size(); ++i)
        areas[i] = mesh.area(leaves[i]);
    std::vector<double> cdf(leaves.size() + 1);
    SolutionCheck check;
    if (leaves.empty() || !(fillCdf(areas, cdf) > 0.0))
        return check;

    // The reference path tracer, as `illuminance --pipeline reference` reads a sensor.
    const PathTracer tracer(scene, PathTracerSettings{});
    const RadianceEstimator incoming = [&](const Ray& ray, Sampler& sampler, FirstHit* firstHit,
                                           PathCounters& counters) {
        return tracer.Li(ray, sampler, firstHit, counters);
    };
    // Covered points, as the solver tells them (radiosity/element_exposure.h).
    const ElementExposure exposure(scene, mesh);
    std::vector<CheckedPoint> drawnPoints(size_t(settings.points));
    tbb::parallel_for(0, settings.points, [&](int i) {
        Sampler sampler(settings.seed);
        // Where the point is: a "pixel" row of its own, apart from its samples', and a later
        // sample of it for each redraw of a covered point.
        DrawnPoint drawn;
        SurfaceHit surface;
        uint64_t rays = 0;
        for (uint32_t attempt = 0; attempt < kDrawAttempts; ++attempt) {
            sampler.startPixelSample(IVec2(i, 1), attempt);
            drawn = drawPoint(mesh, leaves, cdf, sampler);
            surface = scene.surfaceAt(mesh.sceneMesh(drawn.element),
                                      mesh.sceneTriangle(drawn.element), drawn.b);
            const ElementSample x{surface.p, surface.pError, mesh.normal(drawn.element)};
            if (!exposure.covered(drawn.element, x, x.n, rays))
                break;
            drawn.element = -1;
        }
        if (drawn.element < 0) {
            if (progress)
                progress->advance();
            return;  // a point of a surface that is everywhere covered: not counted
        }
        const uint32_t sceneMesh = mesh.sceneMesh(drawn.element);
        const uint32_t triangle = mesh.sceneTriangle(drawn.element);
        CheckedPoint& point = drawnPoints[size_t(i)];
        point.counted = true;
        point.p = surface.p;
        point.n = surface.ng;
        point.solution = luminance(solution.radiance(sceneMesh, triangle, drawn.b, false, true));
        // rho E / pi: the light a Lambertian surface of the solver's reflectance reflects.
        const Color rhoOverPi = mesh.rho(drawn.element) / kPi;
        const Sensor sensor{surface.p, surface.ng};
        // Two independent halves (two scrambles of the sequence: "pixels" (i, 0) and (i, 2)).
        PathCounters counters;
        const auto halfMean = [&](int row) {
            double sum = 0.0;
            int count = 0;
            for (int k = 0; k < settings.samples / 2; ++k) {
                sampler.startPixelSample(IVec2(i, row), uint32_t(k));
                const double L = luminance(
                    rhoOverPi * sampleSensorIrradiance(scene, incoming, sensor, sampler, counters));
                if (std::isfinite(L)) {
                    sum += L;
                    ++count;
                }
            }
            return count > 0 ? sum / count : 0.0;
        };
        const double first = halfMean(0), second = halfMean(2);
        point.traced = 0.5 * (first + second);
        point.tracedVariance = 0.25 * (first - second) * (first - second);
        if (progress)
            progress->advance();
    });

    for (const CheckedPoint& p : drawnPoints) {
        if (p.counted)
            check.points.push_back(p);
    }
    if (check.points.empty())
        return check;
    const double n = double(check.points.size());
    double traced = 0.0, error = 0.0, squaredError = 0.0, variance = 0.0;
    for (const CheckedPoint& p : check.points) {
        traced += p.traced;
        error += p.solution - p.traced;
        squaredError += (p.solution - p.traced) * (p.solution - p.traced);
        variance += p.tracedVariance;
    }
    check.meanTraced = traced / n;
    if (!(check.meanTraced > 0.0))
        return check;
    const double meanError = error / n;
    check.bias = meanError / check.meanTraced;
    if (n > 1.0) {
        const double spread = std::max(0.0, (squaredError - n * meanError * meanError) / (n - 1.0));
        check.biasStandardError = std::sqrt(spread / n) / check.meanTraced;
    }
    check.rmsError = std::sqrt(std::max(0.0, (squaredError - variance) / n)) / check.meanTraced;
    check.noise = std::sqrt(variance / n) / check.meanTraced;
    return check;
}

}  // namespace penumbra
