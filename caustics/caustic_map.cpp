// Parameters of the caustic pass (CausticSettings):
//
// | key        | type    | default   | meaning                                                    |
// | ---------- | ------- | --------- | ---------------------------------------------------------- |
// | photons    | integer | 200000    | photons shot from the lights, in [1, 2^32 - 1]             |
// | k          | integer | 50        | nearest photons per estimate, in [2, 10000]                |
// | max_radius | number  | 0         | largest search radius, m; 0 = 5 % of the bounding radius   |
// | kernel     | string  | "cone"    | cone, epanechnikov or gaussian (caustic_map.h)             |
// | seed       | integer | 0         | seed of the photons' sample sequence                       |
#include "caustics/caustic_map.h"

#include "caustics/photon_kdtree.h"
#include "core/errors.h"
#include "core/scene.h"
#include "core/stats.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

namespace penumbra {

namespace {

// The automatic maximum radius, as a fraction of the scene's bounding radius.
constexpr float kAutoRadiusFraction = 0.05f;
// Pavicic's Gaussian (Jensen 2001, chapter 7).
constexpr double kGaussianBeta = 1.953;

// The disc integral of the Gaussian kernel divided by pi r²:
// integral_0^1 W(sqrt(s)) ds = 1 - (1 - (2 / beta)(1 - e^(-beta/2))) / (1 - e^(-beta)).
double gaussianNormalization() {
    const double b = kGaussianBeta;
    return 1.0 - (1.0 - (2.0 / b) * (1.0 - std::exp(-b / 2.0))) / (1.0 - std::exp(-b));
}

// W(t) and c of caustic_map.h.
float kernelWeight(CausticKernel kernel, float t) {
    switch (kernel) {
        case CausticKernel::Cone:
            return 1.0f - t;
        case CausticKernel::Epanechnikov:
            return 1.0f - t * t;
        case CausticKernel::Gaussian: {
            const double b = kGaussianBeta;
            return static_cast<float>(1.0 -
                                      (1.0 - std::exp(-b * t * t / 2.0)) / (1.0 - std::exp(-b)));
        }
    }
    return 0.0f;
}

float kernelIntegral(CausticKernel kernel) {
    switch (kernel) {
        case CausticKernel::Cone:
            return 1.0f - 2.0f / 3.0f;
        case CausticKernel::Epanechnikov:
            return 0.5f;
        case CausticKernel::Gaussian:
            return static_cast<float>(gaussianNormalization());
    }
    return 1.0f;
}

}  // namespace

std::string kernelName(CausticKernel kernel) {
    switch (kernel) {
        case CausticKernel::Cone:
            return "cone";
        case CausticKernel::Epanechnikov:
            return "epanechnikov";
        case CausticKernel::Gaussian:
            return "gaussian";
    }
    return "?";
}

float CausticSettings::resolvedMaxRadius(const Scene& scene) const {
    if (maxRadius > 0.0f)
        return maxRadius;
    const float radius = scene.bounds().empty() ? 1.0f : scene.bounds().boundingRadius();
    return kAutoRadiusFraction * glm::max(radius, 1e-6f);
}

void validateCausticSettings(const CausticSettings& s) {
    const auto fail = [](const std::string& key, const std::string& expected, double got) {
        std::ostringstream out;
        out << "caustics." << key << ": expected " << expected << ", got " << got;
        throw UsageError(out.str());
    };
    if (s.photons < 1 || s.photons > int64_t{std::numeric_limits<uint32_t>::max()})
        fail("photons", "an integer in [1, 4294967295]", static_cast<double>(s.photons));
    if (s.k < 2 || s.k > 10000)
        fail("k", "an integer in [2, 10000]", s.k);
    if (!(s.maxRadius >= 0.0f) || !std::isfinite(s.maxRadius))
        fail("max_radius", "a length >= 0", s.maxRadius);
}

struct CausticMap::Data {
    CausticSettings settings;
    float maxRadius = 0.0f;
    PhotonTraceResult trace;  // counts only: the photons are in the tree
    std::optional<PhotonKdTree> tree;
    double seconds = 0.0;
    double memoryMiB = 0.0;
};

CausticMap::CausticMap(std::unique_ptr<Data> data) : data_(std::move(data)) {}
CausticMap::CausticMap(CausticMap&&) noexcept = default;
CausticMap& CausticMap::operator=(CausticMap&&) noexcept = default;
CausticMap::~CausticMap() = default;

CausticMap CausticMap::build(const Scene& scene, const CausticSettings& settings,
                             Progress* progress) {
    validateCausticSettings(settings);
    const auto start = std::chrono::steady_clock::now();
    auto data = std::make_unique<Data>();
    data->settings = settings;
    data->maxRadius = settings.resolvedMaxRadius(scene);

    PhotonTracerSettings tracer;
    tracer.photons = static_cast<uint64_t>(settings.photons);
    tracer.seed = settings.seed;
    data->trace = tracePhotons(scene, tracer, progress);
    data->tree.emplace(std::move(data->trace.photons));
    data->trace.photons = {};
    data->seconds = secondsSince(start);
    data->memoryMiB = static_cast<double>(data->tree->memoryBytes()) / (1024.0 * 1024.0);
    return CausticMap(std::move(data));
}

Color CausticMap::radiance(const SurfaceHit& hit, const Bsdf& bsdf, const Vec3& wo,
                           ReflectingLobes lobes) const {
    const Data& d = *data_;
    if (d.tree->photons().empty() || !bsdf.hasNonDeltaLobe())
        return Color(0.0f);
    const Vec3 n = glm::dot(wo, hit.ng) >= 0.0f ? hit.ng : -hit.ng;
    std::vector<PhotonNeighbour> nearest;
    d.tree->nearest(hit.p, n, d.settings.k, d.maxRadius, nearest);
    if (nearest.empty())
        return Color(0.0f);

    // With k photons the k-th sets the radius and is left out (caustic_map.h).
    const bool full = nearest.size() == static_cast<size_t>(d.settings.k);
    const float r2 = full ? nearest.back().dist2 : sqr(d.maxRadius);
    if (!(r2 > 0.0f))
        return Color(0.0f);
    const size_t counted = full ? nearest.size() - 1 : nearest.size();
    const float r = std::sqrt(r2);
    Color sum(0.0f);
    for (size_t i = 0; i < counted; ++i) {
        const Photon& p = d.tree->photons()[nearest[i].index];
        const float t = glm::min(std::sqrt(nearest[i].dist2) / r, 1.0f);
        sum += bsdf.f(wo, p.wi, lobes) * p.power * kernelWeight(d.settings.kernel, t);
    }
    return sum / (kernelIntegral(d.settings.kernel) * kPi * r2);
}

std::span<const Photon> CausticMap::photons() const {
    return data_->tree->photons();
}

const PhotonTraceResult& CausticMap::trace() const {
    return data_->trace;
}

const CausticSettings& CausticMap::settings() const {
    return data_->settings;
}

float CausticMap::maxRadius() const {
    return data_->maxRadius;
}

double CausticMap::seconds() const {
    return data_->seconds;
}

PassStats CausticMap::stats() const {
    const Data& d = *data_;
    const double shot = static_cast<double>(d.trace.shot);
    const double stored = static_cast<double>(d.tree->photons().size());
    const double emitted = luminance(d.trace.emittedPower);
    PassStats s;
    s.emplace_back("photons shot", std::to_string(d.trace.shot));
    s.emplace_back("photons stored", std::to_string(d.tree->photons().size()));
    s.emplace_back("fraction stored", formatStat(shot > 0.0 ? stored / shot : 0.0));
    s.emplace_back(
        "fraction first scattered by a specular surface",
        formatStat(shot > 0.0 ? static_cast<double>(d.trace.aimedAtSpecular) / shot : 0.0));
    s.emplace_back("specular meshes", std::to_string(d.trace.specularMeshes));
    s.emplace_back("stored / emitted power",
                   formatStat(emitted > 0.0 ? luminance(d.trace.storedPower) / emitted : 0.0));
    s.emplace_back("kernel", kernelName(d.settings.kernel));
    s.emplace_back("k", std::to_string(d.settings.k));
    s.emplace_back("max radius (m)", formatStat(d.maxRadius));
    s.emplace_back("seconds", formatStat(d.seconds));
    s.emplace_back("memory (MiB)", formatStat(d.memoryMiB));
    return s;
}

}  // namespace penumbra
