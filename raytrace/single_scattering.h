// Single scattering from the lights along a ray segment through the participating medium, by ray
// marching with shadow rays: the first pass of the seed's two-pass method for media (Rushmeier
// and Torrance 1987; the "single scattering approximation" of Pharr, Jakob and Humphreys,
// "Physically Based Rendering", 4th ed., section 14.1), for the preview tracers (Whitted's),
// which trace no bounce in the medium.
#pragma once

#include "core/medium.h"
#include "core/scene.h"

namespace penumbra {

class Sampler;
struct PathCounters;

// The light the medium scatters once towards ray.o from the span [t0, t1] of `ray` in it:
//     int_t0^t1 T(t0, t) sigma_s(t) Ls(t) dt,
// Ls the direct light the phase function scatters at t (estimateInScattering: a light sample and
// a phase sample, weighed against each other). Stratified: one point drawn uniformly in each of
// `steps` equal parts of the span, each weighted by the part's length (unbiased for the integral
// above, with the variance of a stratified estimate). Multiple scattering is left out.
Color marchSingleScattering(const Scene& scene, const Medium& medium, const Ray& ray,
                            const Medium::Span& span, int steps, Sampler& sampler,
                            PathCounters& counters);

}  // namespace penumbra
