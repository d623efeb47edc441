#include "core/specular_albedo.h"

#include "core/fresnel.h"
#include "core/microfacet.h"

#include <array>
#include <cmath>
#include <utility>

namespace penumbra {
namespace {

// Table resolution. Both axes are uniform in the square root of the variable: mu = cos(theta_o)
// at (i / (kMuSize - 1))^2 and roughness at (j / (kRoughSize - 1))^2, dense near grazing and near
// the mirror, where the albedo varies fastest (this halves the worst interpolation error of
// uniform nodes, to about 3e-3 for mu >= 0.03). Roughness 0 and 1 are exact rows.
constexpr int kMuSize = 32;
constexpr int kRoughSize = 32;
// Quadrature cells of the visible-normal domain per entry, in u1 and in half of u2. More do not
// change the table by more than 1e-4: the interpolation error dominates.
constexpr int kQuadratureU1 = 24;
constexpr int kQuadratureU2 = 16;
// Points of the midpoint rule that averages the interpolated rows over mu.
constexpr int kAverageSteps = 256;

// E(mu) for one (mu, alpha) by integrating over the distribution of visible normals: with
// h ~ D_wo and wi = reflect(wo, h), f cos(theta_i) / pdf(wi) = F(wo.h) G2 / G1(wo) (Heitz and
// d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible
// Normals"), so the albedo is the integral of that weight over the unit square of Heitz 2018's
// Listing 1. A midpoint rule does it, with two refinements:
// - u1 -> 1 maps to the rim of the projected disk, i.e. to GGX's long tail, where reflected
//   directions cross the horizon and the weight drops to 0. The u1 cells are graded towards 1
//   (edges 1 - (1 - k / n)^3) so that this drop is resolved; each cell is weighted by its width.
// - wo lies in the xz-plane, so the integrand is symmetric under h.y -> -h.y, which is
//   u2 -> 1/2 - u2 in Listing 1; only u2 in [1/4, 3/4] is integrated.
SchlickAlbedo integrateAlbedo(float mu, float alpha) {
    const GgxDistribution ggx(alpha);
    const Vec3 wo(safeSqrt(1.0f - mu * mu), 0.0f, mu);
    const float lambdaO = ggx.lambda(wo);
    double a = 0.0, b = 0.0;
    for (int k = 0; k < kQuadratureU1; ++k) {
        const double lo = 1.0 - std::pow(1.0 - double(k) / kQuadratureU1, 3.0);
        const double hi = 1.0 - std::pow(1.0 - double(k + 1) / kQuadratureU1, 3.0);
        const float u1 = float(0.5 * (lo + hi));
        for (int l = 0; l < kQuadratureU2; ++l) {
            const float u2 = 0.25f + 0.5f * (l + 0.5f) / kQuadratureU2;
            const Vec3 h = ggx.sampleVisibleNormal(wo, Vec2(u1, u2));
            const Vec3 wi = reflect(wo, h);
            if (wi.z <= 0.0f)
                continue;
            const double weight = (hi - lo) * (1.0f + lambdaO) / (1.0f + lambdaO + ggx.lambda(wi));
            a += weight;
            b += weight * schlickWeight(glm::dot(wo, h));
        }
    }
    return {float(a / kQuadratureU2), float(b / kQuadratureU2)};
}

class AlbedoTable {
  public:
    AlbedoTable() {
        for (int j = 0; j < kRoughSize; ++j) {
            const float roughness = sqr(float(j) / (kRoughSize - 1));
            for (int i = 0; i < kMuSize; ++i) {
                // wo on the horizon has G1 = 0; the limit is taken a little above it.
                const float mu = glm::max(sqr(float(i) / (kMuSize - 1)), 1e-4f);
                // A mirror reflects everything with F(mu): A = 1, B = (1 - mu)^5.
                entry(i, j) = j == 0 ? SchlickAlbedo{1.0f, schlickWeight(mu)}
                                     : integrateAlbedo(mu, roughness * roughness);
            }
            // Average of the interpolated row, by a midpoint rule much finer than the table.
            double a = 0.0, b = 0.0;
            for (int k = 0; k < kAverageSteps; ++k) {
                const float mu = (k + 0.5f) / kAverageSteps;
                const SchlickAlbedo e = lookupRow(mu, j);
                a += e.a * mu;
                b += e.b * mu;
            }
            average_[j] = {float(2.0 * a / kAverageSteps), float(2.0 * b / kAverageSteps)};
        }
    }

    // Bilinear in (sqrt(mu), sqrt(roughness)).
    SchlickAlbedo lookup(float mu, float roughness) const {
        const auto [j, t] = roughnessCell(roughness);
        return lerp(lookupRow(mu, j), lookupRow(mu, j + 1), t);
    }

    // The average is linear in the table entries, so interpolating the row averages gives the
    // exact average of the interpolated table.
    SchlickAlbedo average(float roughness) const {
        const auto [j, t] = roughnessCell(roughness);
        return lerp(average_[j], average_[j + 1], t);
    }

  private:
    static SchlickAlbedo lerp(const SchlickAlbedo& x, const SchlickAlbedo& y, float t) {
        return {x.a + t * (y.a - x.a), x.b + t * (y.b - x.b)};
    }

    // Lower row index and weight of the upper row.
    static std::pair<int, float> roughnessCell(float roughness) {
        const float y = safeSqrt(glm::min(roughness, 1.0f)) * (kRoughSize - 1);
        const int j = glm::min(int(y), kRoughSize - 2);
        return {j, y - float(j)};
    }

    SchlickAlbedo lookupRow(float mu, int j) const {
        const float x = safeSqrt(glm::min(mu, 1.0f)) * (kMuSize - 1);
        const int i = glm::min(int(x), kMuSize - 2);
        return lerp(entry(i, j), entry(i + 1, j), x - float(i));
    }

    SchlickAlbedo& entry(int i, int j) { return entries_[j * kMuSize + i]; }
    const SchlickAlbedo& entry(int i, int j) const { return entries_[j * kMuSize + i]; }

    std::array<SchlickAlbedo, kMuSize * kRoughSize> entries_;
    std::array<SchlickAlbedo, kRoughSize> average_;
};

// Built on first use; C++11 guarantees thread-safe initialisation of function-local statics.
const AlbedoTable& albedoTable() {
    static const AlbedoTable table;
    return table;
}

}  // namespace

SchlickAlbedo ggxSchlickAlbedo(float cosTheta, float roughness) {
    return albedoTable().lookup(cosTheta, roughness);
}

SchlickAlbedo ggxSchlickAlbedoAverage(float roughness) {
    return albedoTable().average(roughness);
}

}  // namespace penumbra
