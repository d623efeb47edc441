// Caustic photons: light paths L S+ D traced from the lights (Jensen 2001, "Realistic Image
// Synthesis Using Photon Mapping", chapter 5, the caustic photon map).
//
// Emission. The lights are chosen in proportion to their power (Scene::lightSampler()). A photon
// only becomes a caustic photon if its first surface is specular, so it is aimed at the objects
// that can be (Jensen's "projection maps", chapter 5, with bounding spheres instead of a
// projection grid): from a point or spot light, or a point sampled on an area light, the
// direction is drawn uniformly inside the cone of one of the bounding spheres of the specular
// meshes, the sphere chosen in proportion to its cone's solid angle; for a directional light the
// origin is drawn on the spheres' discs projected onto its emission disc. Overlapping cones or
// discs are accounted for by evaluating the whole mixture's density, so the estimator stays
// unbiased: no direction that can reach a specular mesh is left out.
//
// Classification of a surface vertex (Heckbert's notation; core/bsdf.h): the vertex is S when
// the BSDF sample taken there comes from a delta lobe (kLobeSpecular: mirror, smooth glass, the
// smooth coat of a plastic), D otherwise. Thin-walled straight-through transmission and alpha
// cut-outs (Scene::straightTransmittance) are transparency, not a vertex: the photon continues
// unchanged, as shadow rays do.
//
// Storage rule. A photon is stored at a surface that has a non-delta lobe, when it has passed at
// least one S vertex and arrives on a side that reflects: the front face (counter-clockwise
// winding), or either face when the material is doubleSided. Photons arriving at the back face
// of a one-sided material are not stored (they would light the inside of a closed object or the
// back of a wall). After storing, the photon continues only if the surface's BSDF sample is again
// specular; a D sample ends it (the caustic map holds L S+ D paths only, never L S+ D S+ D).
//
// Power. Each stored photon carries flux (lm per linear-sRGB channel), its path's estimate
// divided by the number of photons shot: the sum over all stored photons estimates the flux the
// L S+ paths deliver to the receiving surfaces.
// Russian roulette at S vertices keeps the power of a photon near its emitted value (Jensen 2001,
// chapter 5), and is unbiased.
//
// Determinism: photon i uses sample index firstIndex + i of one Sampler sequence (core/sampler.h)
// and chunks are concatenated in order, so the photons are the same whatever the thread count.
//
// Other sources. tracePhotonsFromSurfaces() shoots the same photons from Lambertian surface points
// that a caller samples instead of from the lights: the light a radiosity solution's diffuse
// surfaces reflect, which the photons then carry through specular surfaces onto other diffuse
// ones (paths D S+ D: the seed's extended form factors for mirror-like surfaces, estimated by
// photons; Wallace, Cohen and Greenberg 1987 traced them with image form factors through planar
// mirrors, Sillion and Puech 1989 with rays). The aiming, the storage rule and the power are as
// above, the points' radiance in place of the lights'. For such a solution the photons may also
// take the sharp glossy lobes (a polished floor) as S vertices (PhotonTracerSettings::
// throughSharpGlossy): the solution then leaves those lobes out of its reflectance, and the
// photons, from its surfaces and from the lights, carry their reflection to where it lands.
#pragma once

#include "core/math.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace penumbra {

class Progress;
class Scene;

struct Photon {
    Vec3 p;       // position on the receiving surface, m
    Vec3 wi;      // unit direction towards where the photon came from (away from the surface)
    Color power;  // flux, lm per channel
    Vec3 n;       // unit geometric normal on the side the photon arrived from
    // Where it landed, for a radiosity solver that takes its flux onto its elements: the scene
    // triangle and the barycentric weights of its vertices.
    uint32_t mesh = 0;
    uint32_t triangle = 0;
    Vec3 barycentric{0.0f};
};

struct PhotonTracerSettings {
    uint64_t photons = 200000;  // photons shot (emitted), not stored
    uint32_t seed = 0;
    // Photon i uses sample index firstIndex + i of the sequence, so that successive batches
    // (progressive photon mapping) continue one sequence; indices wrap after 2^32.
    uint64_t firstIndex = 0;
    int maxSpecularBounces = 64;  // a bound on S vertices, after Russian roulette
    // Sharp glossy lobes (Bsdf::hasSharpGlossyLobe) carry a photon on as delta lobes do, each
    // such vertex an S vertex of the rules above, weighed by the glossy lobes alone (fGlossy
    // over the sample's pdf: the Lambertian layer's share is the surface's own, stored there);
    // their meshes are aimed at too. For a radiosity solution that does not spread them
    // (passes/specular_transfer.h); the caustic map holds L S+ D with delta lobes only.
    bool throughSharpGlossy = false;
    // With it, only photons that passed a sharp glossy vertex are stored: those from the lights
    // through delta lobes alone are the caustic pass's.
    bool onlyThroughSharpGlossy = false;
};

struct PhotonTraceResult {
    std::vector<Photon> photons;  // the stored caustic photons
    uint64_t shot = 0;            // photons emitted
    // Photons whose first scattering surface (after any transparency passed straight through)
    // has a delta lobe: those aimed well.
    uint64_t aimedAtSpecular = 0;
    int specularMeshes = 0;    // meshes with a delta (or sharp glossy) lobe, aimed at
    Color emittedPower{0.0f};  // total power of the lights, lm
    Color storedPower{0.0f};   // sum of the stored photons' power, lm
};

// Shoots settings.photons photons (in parallel with oneTBB), advancing `progress` (may be null)
// by one per photon. A scene without a specular mesh or without lights gives no photons and
// shoots none.
PhotonTraceResult tracePhotons(const Scene& scene, const PhotonTracerSettings& settings,
                               Progress* progress);

// A point of a Lambertian emitter: it sends radiance L (cd/m² per channel) into every direction
// of the hemisphere around n, none behind.
struct SurfaceEmission {
    Vec3 p, pError;  // position and its rounding error bound, to offset rays off the surface
    Vec3 n;          // unit normal of the emitting side
    Color L;
    float pdf = 0.0f;  // of choosing the point, per m² of the emitters' area (choice included)
};
// Draws an emission point from three uniform numbers (a choice, then a position), or nothing.
// Called concurrently: it must not change shared state.
using SurfaceEmitter = std::function<std::optional<SurfaceEmission>(float uChoice, Vec2 u)>;

// Shoots settings.photons photons from the points `emitter` draws (their total flux
// `emittedPower`, lm per channel, reported as PhotonTraceResult::emittedPower), aimed and stored
// as tracePhotons() does for area lights. Nothing without a specular mesh.
PhotonTraceResult tracePhotonsFromSurfaces(const Scene& scene, const SurfaceEmitter& emitter,
                                           const Color& emittedPower,
                                           const PhotonTracerSettings& settings,
                                           Progress* progress);

}  // namespace penumbra
