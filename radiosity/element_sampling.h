// Ray-traced quantities of radiosity elements that every radiosity solver needs: points on an
// element, the visible fraction between two elements and the direct light of the punctual
// lights. Free functions over (Scene, RadiosityMesh), so that the hierarchical and the
// progressive solver estimate them the same way.
//
// Units: positions in metres; D is an irradiance divided by pi, i.e. a radiance (cd/m²), so that
// rho D is the radiance a Lambertian element reflects.
#pragma once

#include "core/math.h"
#include "core/scene.h"

#include <array>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

namespace penumbra {

class CoincidentFaces;
class Light;
class RadiosityMesh;

// A point on an element, with what a shadow ray needs to leave it robustly.
struct ElementSample {
    Vec3 p, pError, n;  // n: the element's front normal
};

// Points on one element (any element, leaf or not), placed as a ray hit there would be
// (Scene::surfaceAt), with their error bounds for robust shadow rays. The element's triangle and
// corners are looked up once: a link's shadow rays place up to 64 points on each of its ends.
class ElementSampler {
  public:
    ElementSampler(const Scene& scene, const RadiosityMesh& mesh, int element);
    // The point with barycentric weights w of the element's corners.
    ElementSample at(const Vec3& w) const;
    // Corner k (0, 1 or 2) moved inward by insetWeights(): where a value "at the corner" is
    // evaluated.
    ElementSample insetCorner(size_t k) const;

  private:
    Scene::Triangle triangle_;
    std::array<Vec3, 3> corners_;  // in the scene triangle's barycentric coordinates
    Vec3 n_;
};

// Barycentric weights w moved a thousandth of the way to the element's centroid: where values
// shown "at a corner" (or an edge) are evaluated, so that an element beside a discontinuity of
// the light (a shadow's edge, a contact line along one of its edges) takes the limit from its own
// side.
inline Vec3 insetWeights(const Vec3& w) {
    constexpr float kInset = 1e-3f;
    return (1.0f - kInset) * w + Vec3(kInset / 3.0f);
}

// The point with uniform-map coordinates u in [0, 1)^2 on the element: ElementSampler's point at
// sampleUniformTriangle(u) (Heitz's area-preserving map: uniform in area).
ElementSample sampleElement(const Scene& scene, const RadiosityMesh& mesh, int element, Vec2 u);

// Stratified points on an element, out.size() of them: point k is sampleElement() at point k of
// an Owen-scrambled (0,2)-sequence (core/sampler.h) of the sampler seeded by `seed` at "pixel"
// `key`, so that the first 2^m points of a power-of-2 count are stratified over the element.
// `key` names the element (and whatever else should decorrelate the set, e.g. a shot), so that
// the points are reproducible whatever the thread or the order of the calls.
// With `children` (as many as `out`), also the child each point lies in (RadiosityMesh::childAt).
void stratifiedElementSamples(const Scene& scene, const RadiosityMesh& mesh, int element,
                              uint32_t seed, IVec2 key, std::span<ElementSample> out,
                              std::span<uint8_t> children = {});

// Visible fraction between two elements from paired points on each (a[k] with b[k], equal
// counts, at least one): the mean transmittance of the shadow rays between them
// (Scene::transmittance, so thin glass tints and passes light). With stratified points on both
// elements this is the estimate of HSA91 and of Cohen and Wallace 1993, "Radiosity and Realistic
// Image Synthesis", chapter 4: rays between jittered points of the two elements.
Color meanTransmittance(const Scene& scene, std::span<const ElementSample> a,
                        std::span<const ElementSample> b);

// Whether the point x is covered on the side of normal n (x.n or -x.n): whether every one of five
// probe rays into that side's hemisphere (the normal, and four at 60 degrees from it) is blocked,
// by an opaque surface (one the radiosity mesh holds) closer than `gap` metres (the ceiling above
// a lamp that hangs a tenth of a millimetre under it), or from behind a surface whose material is
// one-sided (glTF's doubleSided false: its back is not meant to be seen, so the ray is inside a
// closed object, as from the floor under a box standing on it). A covered point sees nothing and
// is seen by nothing. Adds the rays it casts to `rays`: one for most exposed points, five for a
// covered one.
// A probe that meets a side hidden by a coincident face (coincident_faces.h) meets the side that
// replaces it instead.
bool isCovered(const Scene& scene, const RadiosityMesh& mesh, const CoincidentFaces& coincident,
               const ElementSample& x, const Vec3& n, float gap, uint64_t& rays);

// Whether side `front` of the element is hidden at its point x by a coincident patch
// (coincident_faces.h). The tolerance is twice the point's ray offset, the distance below which
// isCovered's probes, which start that far above the surface, cannot see a surface.
bool hiddenByCoincident(const CoincidentFaces& coincident, const RadiosityMesh& mesh, int element,
                        bool front, const ElementSample& x);

// Stratified points of an element (stratifiedElementSamples with `seed`, "pixel" (element, 0)),
// each with the child of the element it lies in (RadiosityMesh::childAt) and whether each side is
// exposed there: a point is covered on a side when isCovered says so or the side is hidden there
// by a coincident patch. Drawn once per partly covered element, they stand for its points
// wherever its covered part must be told from its exposed part.
struct CoverSamples {
    static constexpr int kMaxPoints = 65536;
    std::vector<ElementSample> points;
    std::vector<uint8_t> child;
    std::vector<uint8_t> sides;                    // per point: bit 0 front exposed, bit 1 back
    std::array<std::vector<uint16_t>, 2> exposed;  // [front, back]: the points exposed there

    bool isExposed(size_t point, bool front) const { return sides[point] & (front ? 1 : 2); }
    float exposedFraction(bool front) const {
        // 0 / 0 once made a plausible but wrong solve without a word.
        if (points.empty())
            throw std::logic_error("CoverSamples::exposedFraction: no points");
        return static_cast<float>(exposed[front ? 0 : 1].size()) /
               static_cast<float>(points.size());
    }
    // Whether a side is exposed at some points and covered at others.
    bool partlyCovered() const {
        for (const auto& side : exposed) {
            if (!side.empty() && side.size() < points.size())
                return true;
        }
        return false;
    }
};
// `samples` points, in [1, CoverSamples::kMaxPoints].
CoverSamples coverSamples(const Scene& scene, const RadiosityMesh& mesh, int element, int samples,
                          float gap, uint32_t seed, const CoincidentFaces& coincident,
                          uint64_t& rays);

// The scene's punctual (delta) lights: point, spot, directional.
std::vector<const Light*> punctualLights(const Scene& scene);

// The direct light of punctual lights and of the environment on both sides of an element.
struct PunctualDirect {
    // Mean irradiance / pi over the element, [front, back] (cd/m²); each light counts on the side
    // it lies on.
    std::array<Color, 2> D{Color(0.0f), Color(0.0f)};
    // max - min over the sample points of the largest channel of irradiance / pi, [front, back]:
    // how much D varies over the element (a light pool's falloff, a shadow boundary).
    std::array<float, 2> spread{0.0f, 0.0f};
    // The environment's part of D, [front, back].
    std::array<Color, 2> environment{Color(0.0f), Color(0.0f)};
    uint64_t rays = 0;  // shadow rays cast
};

// Samples `samples` stratified points of the element (seed `seed`, "pixel" (element, 0)) with one
// shadow ray per light each, but for the sides of points hidden by a coincident patch (if
// `coincident` is given), which get nothing: E = I cos(theta) T / d² for point and spot lights,
// E_perp cos(theta) T for directional ones (pbrt-v4's direct lighting for delta lights), T the
// transmittance of the shadow ray. A directional light's D is the mean of E over the points; a
// point or spot light's is Omega / A times the mean of E over the points weighted to solid angle,
// Omega the exact solid angle the element subtends at the light, so that it is exact for an
// unshadowed isotropic light however close and however large the element. Costs samples *
// lights.size() rays.
// The scene's environment light, whether or not `lights` is empty, adds to D on both sides the
// mean over the points of environmentD() (environment_direct.h), each point with
// kEnvironmentDirections directions of each strategy, point k taking directions
// [k n, (k + 1) n) of the element's sequences, so that they are stratified over the element. Its
// noise is left out of the spread, so that it does not drive refinement. samples >= 1.
constexpr uint32_t kEnvironmentDirections = 4;
PunctualDirect punctualDirect(const Scene& scene, const RadiosityMesh& mesh, int element,
                              std::span<const Light* const> lights, int samples, uint32_t seed,
                              const CoincidentFaces* coincident);

}  // namespace penumbra
