// Unidirectional Monte Carlo path tracing: the `reference` estimator of the radiance arriving at
// the camera, against which every other pass is measured. Unbiased: no clamping, no depth cut
// unless the user sets one, Russian roulette that reweights what survives.
//
// Light transport: all paths L (D|S|V)* E, i.e. emission seen directly, direct light, indirect
// diffuse and glossy light, specular reflection and refraction, caustics, and the light a
// participating medium attenuates and scatters (core/medium.h): volumetric path tracing, each
// segment's free flight drawn from the medium's transmittance, ending either at the surface or
// at a scattering event (a V vertex), where next-event estimation and the next direction use
// the phase function (Pharr, Jakob and Humphreys, "Physically Based Rendering", 4th ed.,
// chapter 14; Novak et al. 2018, "Monte Carlo methods for volumetric light transport
// simulation", section 4). Shadow rays take the medium's transmittance (Scene::transmittance).
// The direct light of point-like lights along each segment is also drawn by equiangular
// sampling (Kulla and Fajardo 2012), weighed against the free flight's events by MIS.
//
// The hybrid pipeline (the seed's three-pass method) narrows it in two ways, each a setting:
// - reuse of a radiosity solution: a path that reaches a second diffuse vertex (after the first
//   one and any specular ones between) takes the solution's reflected radiance there (light paths
//   L D+ ending there, emission excluded: that is counted by the emission step and MIS);
//   next-event estimation at the first diffuse vertex takes all its lobes. The solution
//   reflects with the whole non-delta reflectance, rough glossy lobes spread as Lambertian: the
//   reuse vertex takes the Lambertian layer's share of it (matteShare), and its rough glossy
//   lobes go on as at any vertex (next-event estimation and a bounce weighed by fGlossy alone),
//   so that a glossy surface two bounces from the eye reflects in its own direction. The
//   solution holds what arrives from diffuse surfaces and lights, not through specular ones (it
//   treats a mirror as black, solid glass as opaque), so the Lambertian layer's part of a
//   non-delta bounce goes on as far as the next surface's delta lobes; behind that specular
//   chain, the next diffuse vertex is a reuse vertex again, and a light found at the chain's
//   end lights the reuse vertex through it (a caustic there, L S+ D). With a caustic
//   photon map as well, each reuse vertex takes the map's estimate of those caustics instead of
//   the light found by chance: indirect caustics (L S+ D D+ ...) are then counted one bounce
//   deep. When the solution itself took the map's photons (causticsInRadiosity: it holds
//   L S+ D+ too), its Lambertian share holds those caustics and their further bounces, and the
//   reuse vertex's rough glossy lobes trace what they reflect of them (the map is not read).
//   When the solution also carried its own light through specular surfaces
//   (specularInRadiosity), it holds everything the Lambertian layer receives: no part of that
//   layer goes on past the reuse vertex, only the glossy lobes do.
// - correction of the reused solution (correctionProbability q > 0, the `hybrid` pipeline's
//   default): at each reuse vertex the path also goes on through the Lambertian layer with
//   probability q, traced as by the path tracer from there on, and adds what it traces less the
//   solution's value, divided by q. The solution's error then costs noise, not bias: the
//   estimate is the path tracer's in expectation, and the light paths are the path tracer's
//   (docs/light-paths.md, "The hybrid's correction"). The caustic map's estimate at the reuse
//   vertex, read only when the solution took no photons, is not corrected. In a participating
//   medium a scattering event counts as a diffuse vertex (the first one may be in the medium)
//   and is never a reuse vertex: no solution holds the medium's scattered light, which the
//   correction traces after a reuse vertex (tracesMedia).
// - caustic exclusion: emission reached from the first diffuse vertex through one or more
//   specular vertices (L S+ D S* E, the caustic pass's share) is dropped.
// A vertex is diffuse or specular by the lobe it is left through (a plastic's diffuse base and
// smooth coat make it either); next-event estimation and the radiosity term are taken at any
// vertex with a non-delta lobe, in its diffuse role. lightPaths() gives the resulting set.
//
// Each contribution is filed under its component (core/path_components.h) by the vertices its
// path scatters at and the lobe the first one was left through.
//
// Asked to file its light by group (core/light_groups.h: LightGroupSplit), the tracer without
// reuse draws one light from each group and one direction from each part of the environment
// (its map, its sun) at every next-event estimate (the sum over groups of each group's estimate,
// Veach's MIS weights taken within the group or the part), and adds each contribution to its
// light's group too (PathRadiance::groups).
#pragma once

#include "core/light_groups.h"
#include "core/math.h"
#include "core/path_components.h"
#include "core/ray.h"
#include "core/scene.h"
#include "raytrace/radiance_estimator.h"
#include "raytrace/reused_light.h"

#include <cstdint>
#include <string>

namespace penumbra {

class Sampler;

struct PathTracerSettings {
    int maxDepth = -1;  // maximum number of scattering events; -1 = unlimited (roulette ends paths)
    bool reuseRadiosity = false;   // take a radiosity solution at the second diffuse vertex
    bool excludeCaustics = false;  // drop L S+ D S* E
    bool causticsAtReuse = false;  // with reuseRadiosity: add a caustic map at the second vertex
    // With causticsAtReuse: the solution holds the map's photons (L S+ D+), so the map is not
    // read at the second vertex; its glossy lobes trace the caustics they reflect.
    bool causticsInRadiosity = false;
    // With causticsInRadiosity: the solution also carried its own light through specular
    // surfaces (the radiosity pass's specular transfer), so it holds all the light that arrives
    // at a reuse vertex's Lambertian layer, through specular surfaces too (L S* D (S* D)*): that
    // layer's share goes on nowhere in the base, and the correction traces it through specular
    // chains as well.
    bool specularInRadiosity = false;
    // With reuseRadiosity: trace on from a reuse vertex to the specular surfaces it sees. Off
    // only for a scene with no delta lobe, where that ray would find none.
    bool specularAtReuse = true;
    // With reuseRadiosity: the probability q with which a path goes on past a reuse vertex
    // through its Lambertian layer too, correcting the solution there by (T - S) / q (see Li()).
    // 0 takes the solution as it is (biased by its error); any q in (0, 1] is unbiased, and
    // q = 1 traces every path as the path tracer does.
    float correctionProbability = kDefaultCorrectionProbability;
    // In a scattering medium: also draw, on every segment of a path through it, one distance by
    // equiangular sampling towards a point-like light for its direct light, weighted against the
    // free flight's events (raytrace/direct_light.h, sampleEquiangularInScattering). Off only to
    // compare the two estimators.
    bool equiangular = true;

    static constexpr float kDefaultCorrectionProbability = 0.5f;
};

// The light paths, in Heckbert's notation (core/light_paths.h), that a path tracer with these
// settings counts.
std::string pathTracerLightPaths(const PathTracerSettings& settings);

// Whether a tracer with these settings renders a participating medium: it counts every path
// (the corrected reuse does, in expectation: its correction traces what the solution lacks, the
// medium's light too) and reads no caustic map (its photons do not cross the medium).
bool tracesMedia(const PathTracerSettings& settings);

// Russian roulette (Arvo and Kirk 1990): the probability with which the path tracer ends a path
// after `depth` scattering events with throughput `beta` (survivors are divided by 1 - q); 0
// for the first few events, where no sampler dimension is drawn for it. Public so that the
// benchmarks' ray recorder (bench/cornell_fixture.cpp) ends paths as the tracer does.
float rouletteTerminationProbability(int depth, const Color& beta);

class PathTracer {
  public:
    // radiosity: the solution to reuse (raytrace/reused_light.h); required when
    // settings.reuseRadiosity, and then may be null only when the scene has no diffuse surface
    // (the planner skipped the radiosity pass: there is nothing to reflect).
    // causticMap: the caustic estimate; required when settings.causticsAtReuse.
    // groups: when given, Li() files its light by group too (PathRadiance::groups, one entry per
    // group of the split); only without settings.reuseRadiosity, whose solution holds the light
    // of every group together (std::logic_error otherwise).
    PathTracer(const Scene& scene, const PathTracerSettings& settings,
               const ReusedSolution* radiosity = nullptr,
               const ReusedCaustics* causticMap = nullptr, const LightGroupSplit* groups = nullptr);

    // Radiance (cd/m²) arriving along -ray.d at the ray's origin, estimated with one path.
    // The result may be non-finite only through a bug or broken input; callers drop such samples.
    PathRadiance Li(Ray ray, Sampler& sampler, FirstHit* firstHit, PathCounters& counters) const;

  private:
    const Scene& scene_;
    PathTracerSettings settings_;
    const ReusedSolution* radiosity_;
    const ReusedCaustics* causticMap_;
    const LightGroupSplit* groups_;
    // Equiangular sampling runs: asked for, in a scattering medium, with a point-like light.
    bool equiangular_ = false;
};

}  // namespace penumbra
