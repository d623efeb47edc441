#include "core/portals.h"

#include "core/sampling.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace penumbra {

namespace {

// Below this |cos| between the direction and a portal's normal, the point lies in the portal's
// plane and the density would be unbounded: such a direction is neither drawn nor counted.
constexpr float kGrazingCosine = 1e-6f;

// Where the ray from `from` along unit `d` crosses the portal: its distance, or nothing.
std::optional<float> crossing(const Portal& portal, const Vec3& from, const Vec3& d) {
    const Vec3 n = glm::cross(portal.edge1, portal.edge2);
    const float denominator = glm::dot(d, n);
    const float nn = glm::dot(n, n);
    if (!(std::abs(denominator) > kGrazingCosine * std::sqrt(nn)))
        return std::nullopt;
    const float t = glm::dot(portal.corner - from, n) / denominator;
    if (!(t > 0.0f))
        return std::nullopt;
    // The parallelogram's coordinates of the crossing, by the dual basis of its edges.
    const Vec3 q = from + t * d - portal.corner;
    const float a = glm::dot(glm::cross(q, portal.edge2), n) / nn;
    const float b = glm::dot(glm::cross(portal.edge1, q), n) / nn;
    if (a < 0.0f || a > 1.0f || b < 0.0f || b > 1.0f)
        return std::nullopt;
    return t;
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

PortalSet::PortalSet(std::vector<Portal> portals) : portals_(std::move(portals)) {
    std::vector<float> areas;
    for (const Portal& p : portals_) {
        const float area = p.area();
        if (!(area > 0.0f) || !std::isfinite(area))
            throw std::invalid_argument("a portal needs two edges that span an area");
        areas.push_back(area);
        totalArea_ += area;
    }
    areaCdf_.resize(portals_.size() + 1);
    if (!portals_.empty())
        fillCdf(std::span<const float>(areas), areaCdf_);
}

std::optional<Vec3> PortalSet::sample(const Vec3& from, Vec2 u) const {
    if (portals_.empty())
        return std::nullopt;
    const CdfEntry chosen = invertCdf(std::span<const float>(areaCdf_), u.x);
    const Portal& portal = portals_[chosen.index];
    const Vec3 point = portal.corner + float(chosen.remainder) * portal.edge1 + u.y * portal.edge2;
    const Vec3 toward = point - from;
    const float distance = glm::length(toward);
    if (!(distance > 0.0f))
        return std::nullopt;
    const Vec3 d = toward / distance;
    const Vec3 n = glm::normalize(glm::cross(portal.edge1, portal.edge2));
    if (!(std::abs(glm::dot(d, n)) > kGrazingCosine))
        return std::nullopt;
    return d;
}

float PortalSet::pdf(const Vec3& from, const Vec3& towards) const {
    float density = 0.0f;
    for (const Portal& portal : portals_) {
        const std::optional<float> t = crossing(portal, from, towards);
        if (!t)
            continue;
        const float area = portal.area();
        const float cosine =
            std::abs(glm::dot(towards, glm::cross(portal.edge1, portal.edge2))) / area;
        // Chosen with probability area / total, then uniform over the area: 1 / total per m².
        density += sqr(*t) / (totalArea_ * cosine);
    }
    return density;
}

}  // namespace penumbra
