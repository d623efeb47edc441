// Image-space reconstruction of the hybrid's correction (raytrace/path_tracer.h,
// PathTracerSettings::correctionProbability): the per-pixel mean of (T - S) / q, the difference
// between what the path tracer traces past a reuse vertex and what the radiosity solution says,
// is unbiased but noisy, and it is smooth where the solution's error is (a fraction of a smooth
// field, except across the edges of objects). So it is averaged over neighbouring pixels of the
// same surface, as Rousselle, Jarosz and Novák (2016, "Image-space Control Variates for
// Rendering") reconstruct the difference between an image and its control variate, with a
// cross-bilateral filter (Tomasi and Manduchi 1998; guided by the normal, depth and albedo of
// the first diffuse vertex, as Schied et al. 2017 guide SVGF) whose width shrinks as samples
// accumulate: sigma(N) = sigma_1 N^(-1/6). With the filter's bias growing as sigma² (the
// correction's curvature) and its variance falling as 1 / (N sigma²), that rate balances the
// squared bias against the variance (minimising sigma^4 + 1 / (N sigma²)), the argument that sets
// the radius schedule of progressive photon mapping (Hachisuka, Ogaki and Jensen 2008): both vanish
// as N grows, so the image converges to the unbiased one (consistency).
#pragma once

#include "core/image.h"

namespace penumbra {

// What the filter compares two pixels by: the first visible surface's shading normal (X, Y, Z;
// zero where nothing was hit), its distance from the camera (Z) and its albedo (R, G, B), each
// the mean over the pixel's samples.
struct FilterGuide {
    const Image& normal;
    const Image& depth;
    const Image& albedo;
};

// The filter's standard deviation in pixels after `samplesPerPixel` samples, from its value at one
// sample per pixel: sigma_1 N^(-1/6).
float correctionFilterSigma(float sigmaAtOneSample, double samplesPerPixel);

// Every channel of `image` averaged over the pixels within 2 sigma, each weighted by a Gaussian of
// its distance (sigma, pixels) and by how alike its guide features are; the pixel itself has
// weight 1. Below sigma 0.25 the image is returned as it is.
Image filterCorrection(const Image& image, const FilterGuide& guide, float sigma);

}  // namespace penumbra
