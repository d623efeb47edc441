#include "core/microfacet.h"

namespace penumbra {

// Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), Listing 1: stretch
// wo into the configuration where alpha = 1, sample the projected hemisphere seen from there
// (a disk whose far half is squashed by (1 + cos) / 2), and unstretch the normal.
Vec3 GgxDistribution::sampleVisibleNormal(const Vec3& wo, Vec2 u) const {
    // Section 3.2: the view direction in the hemisphere configuration.
    const Vec3 vh = glm::normalize(Vec3(alpha_ * wo.x, alpha_ * wo.y, wo.z));
    // Section 4.1: orthonormal basis around vh (any basis when vh is the pole).
    const float lenSq = vh.x * vh.x + vh.y * vh.y;
    const Vec3 t1 = lenSq > 0.0f ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lenSq) : Vec3(1, 0, 0);
    const Vec3 t2 = glm::cross(vh, t1);
    // Section 4.2: uniform point on the disk, its far half rescaled to the projected area.
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    const float s = 0.5f * (1.0f + vh.z);
    const float p2 = (1.0f - s) * safeSqrt(1.0f - p1 * p1) + s * r * std::sin(phi);
    // Section 4.3: reproject onto the hemisphere.
    const Vec3 nh = p1 * t1 + p2 * t2 + safeSqrt(1.0f - p1 * p1 - p2 * p2) * vh;
    // Section 3.4: back to the ellipsoid configuration.
    return glm::normalize(Vec3(alpha_ * nh.x, alpha_ * nh.y, glm::max(nh.z, 0.0f)));
}

}  // namespace penumbra
