// Scenes with a participating medium for the in-process tests of the tracers that render one
// (tests/raytrace/), and the independent quadrature of the light a point light scatters once
// into a ray (the airlight integral), their oracle.
#pragma once

#include "core/medium.h"
#include "core/phase_function.h"
#include "core/scene.h"
#include "tests/support/gltf_builder.h"

#include <functional>
#include <memory>
#include <string>

namespace penumbra::test {

// A density as a function of a point in the file's frame, and the lattice it is sampled on.
struct DensityField {
    std::function<double(const Vec3&)> at;
    glm::ivec3 nodes;
};

// The scene of `builder` with `medium` in it (its box in the file's frame, moved as the loader
// moved the geometry), scaled by `density` sampled over that box when one is given.
std::unique_ptr<Scene> withMedium(const GltfBuilder& builder, const std::string& name,
                                  MediumDesc medium, const DensityField* density = nullptr);

// A heterogeneous density: two Gaussian puffs on a thin background, sampled on 20 x 10 x 20
// nodes over its medium's box.
extern const DensityField kPuffs;

// The smoky room: the closed box [-1, 1]^3 of grey walls (albedo 0.6), a point lamp "Lamp" of
// 2 cd at (0.3, 0.5, -0.2), and kLowSmoke, chromatic smoke in its lower half only, half a metre
// and more below the lamp, so that the estimators' light samples from the smoke stay bounded (a
// point light inside a medium gives each of them a heavy tail, 1 / r^2 at events near it); and
// kIntoTheSmoke, a ray from the front down into the smoke.
GltfBuilder smokyRoom();
extern const MediumDesc kLowSmoke;
extern const Ray kIntoTheSmoke;

// Thermal equilibrium (Kirchhoff's law): the closed box [-1, 1]^3 of walls that reflect rho and
// emit (1 - rho) Le, and a medium in it that absorbs, scatters (g = 0.5) and emits with Le, give
// the radiance Le everywhere, in every direction: what each part absorbs of a field of radiance
// Le, it emits again.
GltfBuilder equilibriumBox(float rho, const Color& Le);
MediumDesc glowingMedium(const Color& Le);

// A point lamp of kLampIntensity candela at the origin and, to have something to load, a black
// quad far below, out of the medium and the rays' way.
constexpr float kLampIntensity = 10.0f;
GltfBuilder lampAtTheOrigin();

// A panel of kPanelRadiance cd/m² at z = -5 facing +z (towards a camera at the origin), and a
// slab of medium that absorbs `sigmaA` and emits `emission`, 1.5 m thick between them (from
// z = -3.5 to z = -2, 20 m wide).
constexpr float kPanelRadiance = 3.0f;
GltfBuilder panelAtFiveMetres();
MediumDesc slabBetween(const Color& sigmaA, const Color& emission = Color(0.0f));

// An affine density (the homogeneous medium's is 1): its integral along a segment is the
// segment's length times the density at its midpoint.
using AffineDensity = std::function<double(const glm::dvec3&)>;

// The airlight integral: the radiance a point light of intensity I at the origin scatters once
// into a ray from o along d (unit), over the ray's span [0, tEnd] in the medium of density rho,
//     L = int sigma_s rho(x) p(cos theta(t)) I / r(t)^2 exp(-sigma_t (D(0, x) + D(o, x))) dt,
// x = o + t d, r = |x|, D the optical length, theta(t) the angle between the light's way from
// the lamp to the point and -d; by Simpson's rule in double precision over 200 000 intervals
// (Sun, Ramamoorthi, Narasimhan and Nayar 2005, "A Practical Analytic Single Scattering Model
// for Real Time Rendering", Eq. 1, computed apart).
double airlight(
    const Vec3& o, const Vec3& d, double tEnd, double I, double sigmaS, double sigmaT,
    const HenyeyGreenstein& phase,
    const AffineDensity& density = [](const glm::dvec3&) { return 1.0; });

}  // namespace penumbra::test
