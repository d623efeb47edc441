// The sources' direct light at a point of a meshed surface, exactly where no shadow falls: what
// the shown solution (shown_direct.h) puts at the corners of its elements, so that the pool of
// light under a downlight or beside a wall-washer is not the mean of an element around it.
//
// D(x) = E(x) / pi, an irradiance divided by pi (cd/m²), on the side of x facing n:
//  - each punctual light (point, spot, directional): E = I cos(theta) T / d² or E_perp cos(theta)
//    T, T the shadow ray's transmittance (pbrt-v4's direct lighting of delta lights);
//  - the environment: environmentD() (environment_direct.h) with kEnvironmentDirections
//    directions of each strategy, the same directions at every point, so that the field is
//    smooth (its error is one of the directions' set, shared by neighbouring points);
//  - each emissive patch j of the mesh (Le_j, one-sided unless two-sided): Le_j F(x -> j), F the
//    point-to-polygon form factor by Lambert's contour integral (form_factor.h), exact and clipped
//    to the hemisphere over x, times the visible fraction of the patch's light (scene mesh) j is
//    part of. That fraction is a ratio estimator over fixed points of the light (the same for
//    every x, so that neighbouring points see the same samples and the field stays smooth):
//    sum_k w_k T_k / sum_k w_k, with w_k the unoccluded kernel cos(theta_x) cos(theta_k) / r_k²
//    of point k, so that it is exactly 1 for an unshadowed light and 0 for a hidden one (the
//    estimator of Wallace, Elmquist and Haines 1989, "A Ray Tracing Algorithm for Progressive
//    Radiosity", with the analytic form factor in place of their disc approximation). A point
//    casts kRaysPerPoint rays in all, shared among the lights in proportion to their unoccluded
//    light there (at least kMinRays each): the lamps of a hall do not each need sixteen rays
//    from every wall.
//  - a light that gives at least 1/kPenumbraShare of the point's unoccluded light and whose rays
//    disagree (a penumbra) is estimated by parts instead: the light is cut into cells (its
//    patches split 1:4, at least kMinCells in all), and D sums each cell's exact form factor
//    times the visible fraction of its own points (the light's fraction where it has none), so
//    that only the cells on the occluder's outline are estimated at all. It gets kPenumbraRays
//    rays, then twice as many at a time until D changes by less than kSettled of the point's
//    unoccluded light, or it runs out of points. One ratio over a whole light was 13 % low
//    beside a block in a furnace box whose walls are the lights (a large light, the same value
//    whichever of its parts are hidden); by parts, within 0.5 %. Rays that all find such a light
//    hidden are checked with kConfirmRays before it is taken as dark: four points of a wall had
//    all fallen behind a block that hid 37 % of it.
//  - the fixed points are point k of a (0,2)-sequence over the light's cells by area, so that
//    every prefix a point traces is spread over the whole light.
//  Far from a patch (more than kFarField times its circumradius) its form factor is the point
//  kernel A cos cos / (pi r²), within 1 % there (form_factor.h's measurements of the disc
//  approximation: 0.16 % at 16 times the element's size) and without the contour's trigonometry.
//  Caustic photons and other deposited flux are not in D: they stay the elements'
//  (deposited_flux.h).
#pragma once

#include "core/math.h"
#include "radiosity/element_sampling.h"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace penumbra {

class Light;
class RadiosityMesh;
class Scene;

class PointDirect {
  public:
    static constexpr int kLightPoints = 256;
    static constexpr size_t kMinCells = 64;
    static constexpr int kRaysPerPoint = 32;
    static constexpr size_t kMinRays = 4;
    static constexpr float kPenumbraShare = 16.0f;
    static constexpr size_t kConfirmRays = 16;
    static constexpr size_t kPenumbraRays = 32;
    static constexpr float kSettled = 0.01f;
    static constexpr float kFarField = 10.0f;
    static constexpr uint32_t kEnvironmentDirections = 64;
    static constexpr float kEnvironmentDistance = 1.0f / 8.0f;
    static constexpr uint32_t kEnvironmentSeed = 0x656e76u;

    // Both must outlive it. The emitters are the mesh's emissive patches as they are now, each
    // side that emits and is exposed(patch, front) (not hidden by a coincident face: a wall
    // modelled twice emits once).
    PointDirect(const Scene& scene, const RadiosityMesh& mesh,
                const std::function<bool(int element, bool front)>& exposed);

    // D at the point x on the side its normal n faces (x.n or -x.n), cd/m², in three parts: the
    // punctual lights', the environment's and the emitters'. Adds the shadow rays it casts to
    // `rays`.
    struct Parts {
        Color punctual{0.0f}, environment{0.0f}, emitters{0.0f};
        Color total() const { return punctual + environment + emitters; }
    };
    Parts D(const ElementSample& x, const Vec3& n, uint64_t& rays) const;
    // Whether there is any source to evaluate.
    bool empty() const { return punctual_.empty() && lights_.empty() && !scene_.environment(); }
    // Distance (m) from p to the nearest point or spot light or emissive patch (to its
    // circumscribed sphere: a lower bound), infinite with none of them. The environment, which
    // lies at no distance, counts as a source kEnvironmentDistance times the scene's bounding
    // radius away: its light varies at the shadows of the openings it comes through, whose size
    // goes with the scene's (elements down to 3 cm along them in a room 10 m across).
    float nearestSource(const Vec3& p) const;

  private:
    struct Patch {
        std::array<Vec3, 3> corners;
        Vec3 normal, centroid;
        float area, radius;  // radius: the circumradius about the centroid
        Color Le;
        bool front, back;  // which sides emit
    };
    // The unoccluded form factor from the differential area at x (normal n) to the patch.
    static float formFactor(const Vec3& x, const Vec3& n, const Patch& patch);
    // One emissive scene mesh: its patches, their cells, and the fixed points of its visible
    // fraction, in an order whose every prefix is spread over the light.
    struct AreaLight {
        std::vector<Patch> patches, cells;
        std::vector<uint32_t> cellPatch;  // the index in `patches` of each cell's patch
        std::vector<ElementSample> points;
        std::vector<uint32_t> pointCell;  // the index in `cells` of each point's cell
        bool twoSided = false;
    };
    class LightRays;
    // A light's D at x, its unoccluded part given, `total` the unoccluded D of every light.
    Color emitted(const AreaLight& light, const ElementSample& x, const Vec3& n,
                  const Color& unoccluded, float total, uint64_t& rays) const;
    static Patch makePatch(const std::array<Vec3, 3>& corners, const Vec3& normal, const Color& Le,
                           bool front, bool back);
    static void placePoints(const Scene& scene, const RadiosityMesh& mesh,
                            const std::vector<int>& patches, uint32_t sceneMesh, AreaLight& light);

    const Scene& scene_;
    std::vector<const Light*> punctual_;
    std::vector<AreaLight> lights_;
};

}  // namespace penumbra
