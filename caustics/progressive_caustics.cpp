#include "caustics/progressive_caustics.h"

#include "caustics/caustic_map.h"
#include "caustics/photon_kdtree.h"
#include "core/errors.h"
#include "core/scene.h"
#include "core/stats.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <limits>
#include <sstream>

namespace penumbra {

void validateProgressiveCausticSettings(const ProgressiveCausticSettings& s) {
    const auto fail = [](const std::string& key, const std::string& expected, double got) {
        std::ostringstream out;
        out << "caustics." << key << ": expected " << expected << ", got " << got;
        throw UsageError(out.str());
    };
    if (s.photonsPerIteration < 1 ||
        s.photonsPerIteration > int64_t{std::numeric_limits<uint32_t>::max()}) {
        fail("photons_per_iteration", "an integer in [1, 4294967295]",
             static_cast<double>(s.photonsPerIteration));
    }
    if (!(s.initialRadius >= 0.0f) || !std::isfinite(s.initialRadius))
        fail("initial_radius", "a length >= 0", s.initialRadius);
    if (!(s.alpha > 0.0f && s.alpha < 1.0f))
        fail("alpha", "a number in (0, 1)", s.alpha);
}

ProgressiveCaustics::ProgressiveCaustics(const Scene& scene, size_t measurements,
                                         const ProgressiveCausticSettings& settings)
    : scene_(scene), settings_(settings) {
    validateProgressiveCausticSettings(settings_);
    float radius = settings_.initialRadius;
    if (!(radius > 0.0f))
        radius = CausticSettings{}.resolvedMaxRadius(scene);  // the caustic map's default
    measurements_.assign(measurements, Measurement{radius});
}

void ProgressiveCaustics::iterate(std::span<const VisiblePoint> points, Progress* progress) {
    if (points.size() != measurements_.size()) {
        throw std::invalid_argument(
            "ProgressiveCaustics::iterate: " + std::to_string(points.size()) +
            " visible points for " + std::to_string(measurements_.size()) + " measurements");
    }
    const auto start = std::chrono::steady_clock::now();
    PhotonTracerSettings tracer;
    tracer.photons = static_cast<uint64_t>(settings_.photonsPerIteration);
    tracer.seed = settings_.seed;
    tracer.firstIndex = photonsShot_;
    PhotonTraceResult batch = tracePhotons(scene_, tracer, progress);
    photonsShot_ += tracer.photons;
    photonsStored_ += batch.photons.size();
    const PhotonKdTree tree(std::move(batch.photons));

    const float alpha = settings_.alpha;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size()), [&](const auto& range) {
        std::vector<PhotonNeighbour> found;
        for (size_t i = range.begin(); i != range.end(); ++i) {
            const VisiblePoint& v = points[i];
            Measurement& m = measurements_[i];
            if (maxComponent(v.beta) <= 0.0f || tree.photons().empty())
                continue;
            const Bsdf bsdf = scene_.bsdf(v.hit);
            if (!bsdf.hasNonDeltaLobe())
                continue;
            const Vec3 n = glm::dot(v.wo, v.hit.ng) >= 0.0f ? v.hit.ng : -v.hit.ng;
            tree.within(v.hit.p, n, m.radius, found);
            if (found.empty())
                continue;
            Color phi(0.0f);
            for (const PhotonNeighbour& neighbour : found) {
                const Photon& p = tree.photons()[neighbour.index];
                phi += bsdf.f(v.wo, p.wi) * p.power;
            }
            // Radius reduction and flux correction (progressive_caustics.h).
            const double M = static_cast<double>(found.size());
            const double kept = m.count + alpha * M;
            const float ratio2 = static_cast<float>(kept / (m.count + M));
            m.tau = (m.tau + v.beta * phi) * ratio2;
            m.radius *= std::sqrt(ratio2);
            m.count = kept;
        }
    });
    ++iterations_;
    seconds_ += secondsSince(start);
}

Color ProgressiveCaustics::radiance(size_t i) const {
    const Measurement& m = measurements_[i];
    if (iterations_ == 0 || !(m.radius > 0.0f))
        return Color(0.0f);
    return m.tau / (kPi * sqr(m.radius) * static_cast<float>(iterations_));
}

PassStats ProgressiveCaustics::stats() const {
    double sum = 0.0;
    float smallest = std::numeric_limits<float>::infinity();
    for (const Measurement& m : measurements_) {
        sum += m.radius;
        smallest = std::min(smallest, m.radius);
    }
    const double count = static_cast<double>(measurements_.size());
    PassStats s;
    s.emplace_back("iterations", std::to_string(iterations_));
    s.emplace_back("photons shot", std::to_string(photonsShot_));
    s.emplace_back("photons stored", std::to_string(photonsStored_));
    s.emplace_back("alpha", formatStat(settings_.alpha));
    s.emplace_back("mean radius (m)", formatStat(count > 0.0 ? sum / count : 0.0));
    s.emplace_back("smallest radius (m)", formatStat(count > 0.0 ? smallest : 0.0));
    s.emplace_back("seconds", formatStat(seconds_));
    return s;
}

}  // namespace penumbra
