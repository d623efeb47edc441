#include "core/portals.h"

#include "core/sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace penumbra {

namespace {

// The rational map of a plane coordinate X in (-inf, inf) to the unit interval (the header's).
float toUnit(float x) {
    return 0.5f * (x / (1.0f + std::abs(x)) + 1.0f);
}

// The direction of rectified point `uv` on side `sigma` (+1 or -1) of the frame, and the solid
// angle per unit area of the square there (the header's formula).
struct RectifiedDirection {
    Vec3 direction;
    float solidAnglePerArea;
};
std::optional<RectifiedDirection> rectifiedDirection(const Vec3& unit1, const Vec3& unit2,
                                                     const Vec3& normal, float sinAngle,
                                                     float sigma, Vec2 uv) {
    const float s = 2.0f * uv.x - 1.0f, t = 2.0f * uv.y - 1.0f;
    const float restS = 1.0f - std::abs(s), restT = 1.0f - std::abs(t);
    if (!(restS > 0.0f) || !(restT > 0.0f))
        return std::nullopt;
    const Vec3 w = (s / restS) * unit1 + (t / restT) * unit2 + sigma * normal;
    const float length = glm::length(w);
    return RectifiedDirection{w / length,
                              4.0f * sinAngle / (length * length * length * sqr(restS * restT))};
}

// The n x n image as kCoarseResolution² cells, each the mean of the cells it holds.
WindowedDistribution2D coarsened(const std::vector<float>& values, int n) {
    constexpr int m = PortalSet::kCoarseResolution;
    const int block = n / m;
    std::vector<float> coarse(size_t(m) * m);
    for (int y = 0; y < m; ++y)
        for (int x = 0; x < m; ++x) {
            double sum = 0.0;
            for (int j = 0; j < block; ++j)
                for (int i = 0; i < block; ++i)
                    sum += values[size_t(y * block + j) * n + size_t(x * block + i)];
            coarse[size_t(y) * m + x] = float(sum / double(block * block));
        }
    return WindowedDistribution2D(std::move(coarse), m, m);
}

}  // namespace

std::array<glm::dvec3, 3> parsePortalCorners(const std::string& text) {
    std::vector<double> values;
    std::stringstream fields(text);
    for (std::string field; std::getline(fields, field, ',');) {
        char* end = nullptr;
        const double value = std::strtod(field.c_str(), &end);
        if (field.empty() || *end != '\0' || !std::isfinite(value)) {
            values.clear();
            break;
        }
        values.push_back(value);
    }
    if (values.size() != 9) {
        throw std::invalid_argument("portal \"" + text +
                                    "\": expected nine numbers X0,Y0,Z0,X1,Y1,Z1,X2,Y2,Z2 (a "
                                    "corner and its two neighbours, metres)");
    }
    std::array<glm::dvec3, 3> corners;
    for (int i = 0; i < 3; ++i)
        corners[size_t(i)] =
            glm::dvec3(values[size_t(3 * i)], values[size_t(3 * i + 1)], values[size_t(3 * i + 2)]);
    if (!(glm::length(glm::cross(corners[1] - corners[0], corners[2] - corners[0])) > 0.0))
        throw std::invalid_argument("portal \"" + text + "\": its corners span no area");
    return corners;
}

PortalSet::PortalSet(std::vector<Portal> portals,
                     const std::function<float(const Vec3&)>& luminance, int resolution,
                     int supersampling) {
    if (resolution < kCoarseResolution || resolution % kCoarseResolution != 0 || supersampling < 1)
        throw std::invalid_argument(
            "PortalSet: the resolution must be a multiple of "
            "kCoarseResolution and the supersampling positive");
    for (const Portal& p : portals) {
        const float area = p.area();
        if (!(area > 0.0f) || !std::isfinite(area))
            throw std::invalid_argument("a portal needs two edges that span an area");
        Rectified r;
        r.portal = p;
        r.normal = glm::cross(p.edge1, p.edge2) / area;
        r.length1 = glm::length(p.edge1);
        r.length2 = glm::length(p.edge2);
        r.unit1 = p.edge1 / r.length1;
        r.unit2 = p.edge2 / r.length2;
        r.sinAngle = area / (r.length1 * r.length2);
        // (q x edge2) . N / |N|² and (edge1 x q) . N / |N|² with N = edge1 x edge2, as q . dual.
        const Vec3 along = glm::cross(p.edge1, p.edge2);
        r.dual1 = glm::cross(p.edge2, along) / glm::dot(along, along);
        r.dual2 = glm::cross(along, p.edge1) / glm::dot(along, along);
        rectified_.push_back(std::move(r));
    }

    // Each side's image: the luminance times the solid angle per unit area, averaged over
    // supersampling² points of each cell, so that sampling the image by its values draws
    // directions in proportion to the luminance.
    const int n = resolution, k = supersampling;
    for (Rectified& r : rectified_) {
        for (int side = 0; side < 2; ++side) {
            std::vector<float> values(size_t(n) * size_t(n));
            tbb::parallel_for(0, n, [&](int y) {
                for (int x = 0; x < n; ++x) {
                    double sum = 0.0;
                    for (int j = 0; j < k; ++j)
                        for (int i = 0; i < k; ++i) {
                            const Vec2 uv((float(x) + (float(i) + 0.5f) / float(k)) / float(n),
                                          (float(y) + (float(j) + 0.5f) / float(k)) / float(n));
                            const std::optional<RectifiedDirection> d =
                                rectifiedDirection(r.unit1, r.unit2, r.normal, r.sinAngle,
                                                   side == 0 ? 1.0f : -1.0f, uv);
                            if (d)
                                sum += double(luminance(d->direction)) * d->solidAnglePerArea;
                        }
                    values[size_t(y) * n + size_t(x)] = float(sum / double(k * k));
                }
            });
            r.coarse[side] = coarsened(values, n);
            r.sides[side] = WindowedDistribution2D(std::move(values), n, n);
        }
    }
}

std::optional<std::pair<int, Window>> PortalSet::window(const Rectified& r, const Vec3& from) {
    // Side 0 (+n) for a point behind the plane, which looks through it along +n.
    const Vec3 q = from - r.portal.corner;
    const float height = glm::dot(q, r.normal);
    const float h = std::abs(height);
    if (!(h > 0.0f))
        return std::nullopt;
    // The point's coordinates in units of the edges (q's normal part drops out).
    const float a = glm::dot(q, r.dual1), b = glm::dot(q, r.dual2);
    const Window w{Vec2(toUnit(-a * r.length1 / h), toUnit(-b * r.length2 / h)),
                   Vec2(toUnit((1.0f - a) * r.length1 / h), toUnit((1.0f - b) * r.length2 / h))};
    return std::make_pair(height < 0.0f ? 0 : 1, w);
}

double PortalSet::luminanceShown(const Vec3& from) const {
    double total = 0.0;
    for (const Rectified& r : rectified_)
        if (const auto w = window(r, from))
            total += r.coarse[w->first].integral(w->second);
    return total;
}

std::optional<Vec3> PortalSet::sample(const Vec3& from, Vec2 u, double shown) const {
    if (!(shown > 0.0))
        return std::nullopt;
    // The portal whose share of `shown` holds u.x, u.x then rescaled within it.
    const double target = double(u.x) * shown;
    double before = 0.0;
    for (const Rectified& r : rectified_) {
        const auto w = window(r, from);
        if (!w)
            continue;
        const double mine = r.coarse[w->first].integral(w->second);
        if (!(mine > 0.0) || before + mine <= target) {
            before += mine;
            continue;
        }
        const float uPortal = float(std::clamp((target - before) / mine, 0.0, 1.0));
        const auto point = r.sides[w->first].sample(Vec2(uPortal, u.y), w->second);
        if (!point)
            return std::nullopt;
        const auto d = rectifiedDirection(r.unit1, r.unit2, r.normal, r.sinAngle,
                                          w->first == 0 ? 1.0f : -1.0f, point->point);
        if (!d)
            return std::nullopt;
        return d->direction;
    }
    return std::nullopt;
}

float PortalSet::pdf(const Vec3& from, const Vec3& towards, double shown) const {
    if (!(shown > 0.0))
        return 0.0f;
    double density = 0.0;
    for (const Rectified& r : rectified_) {
        // Whether the ray crosses the portal, first: most do not, and their windows are not needed.
        const float height = glm::dot(from - r.portal.corner, r.normal);
        const float sigma = height < 0.0f ? 1.0f : -1.0f;
        const float cosine = sigma * glm::dot(towards, r.normal);
        if (!(cosine > 0.0f) || height == 0.0f)
            continue;
        const Vec3 q = from + (std::abs(height) / cosine) * towards - r.portal.corner;
        const float a = glm::dot(q, r.dual1), b = glm::dot(q, r.dual2);
        if (!(a >= 0.0f && a <= 1.0f && b >= 0.0f && b <= 1.0f))
            continue;
        const auto w = window(r, from);
        if (!w)
            continue;
        // The rectified point of `towards`: its crossing of the plane one unit ahead, by the
        // dual basis of the unit edges.
        const Vec3 inPlane = towards / cosine - sigma * r.normal;
        const float x = glm::dot(glm::cross(inPlane, r.unit2), r.normal) / r.sinAngle;
        const float y = glm::dot(glm::cross(r.unit1, inPlane), r.normal) / r.sinAngle;
        const Vec2 uv(toUnit(x), toUnit(y));
        const Window& window = w->second;
        const auto d = rectifiedDirection(r.unit1, r.unit2, r.normal, r.sinAngle, sigma, uv);
        if (!d || !(d->solidAnglePerArea > 0.0f))
            continue;
        // Chosen with probability coarse / shown, then the image's density value / integral over
        // the window per unit area, over the solid angle per unit area.
        const WindowedDistribution2D& image = r.sides[w->first];
        const double integral = image.integral(window);
        if (!(integral > 0.0))
            continue;
        const double chosen = r.coarse[w->first].integral(window) / shown;
        density += chosen * double(image.value(uv)) / (integral * double(d->solidAnglePerArea));
    }
    return float(density);
}

}  // namespace penumbra
