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
// as N grows, so the image converges to the unbiased one (consistency). The constant of that
// balance (the correction's curvature against its variance) differs from pixel to pixel: smooth
// over a wall, sharp where a glossy floor reflects it. So each pixel takes the multiple of sigma
// that an unbiased estimate of its squared error prefers (chooseFilterWidths).
#pragma once

#include "core/image.h"

#include <vector>

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
// The same with a width of its own for each pixel (`widths`, row by row).
Image filterCorrection(const Image& image, const FilterGuide& guide,
                       const std::vector<float>& widths);

// A per-pixel mean and the variance of that mean (each channel; negative where it is unknown, a
// pixel of fewer than two samples).
struct NoisyImage {
    const Image& mean;
    const Image& varianceOfMean;
};

// Each pixel's filter width, chosen among 0, sigma / 2, sigma and 2 sigma (the last no wider than
// kWidestChosenSigma unless sigma is) by the smallest estimate of its squared error. The
// squared error of a linear filter F of independent pixels y_j of variance v_j is estimated
// without the true image by Stein's unbiased risk estimate (Stein 1981), which Li, Wu and Chuang
// (2012, "SURE-based Optimization for Adaptive Sampling and Reconstruction") use to choose among
// cross-bilateral filters per pixel: SURE_i = |F(y)_i - y_i|^2 + 2 v_i dF_i/dy_i - v_i, where
// dF_i/dy_i = 1 / (the pixel's sum of weights). One pixel's estimate is itself noisy, so it is
// averaged over the pixel's surface with the widest candidate's filter before the choice (with
// sigma's instead, noise over a constant took the widest width in 82 % of the interior pixels,
// not 94 %, and the hybrid's relMSE on the modern hall at 256 spp was 3-5 % higher). Every
// candidate is a fixed multiple of sigma, so the widths still vanish as sigma does (the image
// stays consistent). A pixel with no known variance near it keeps sigma.
std::vector<float> chooseFilterWidths(const NoisyImage& image, const FilterGuide& guide,
                                      float sigma);
// The widest of the candidates above when sigma is narrower than it: the default width at one
// sample per pixel (PathPass's correction_sigma), so a wider choice costs no more per pixel than
// the default filter after the first sample.
constexpr float kWidestChosenSigma = 8.0f;

// What reconstructing a width x height correction at filter width sigma costs, for a renderer
// under a time limit to leave time for it: the pixel pairs it weighs, chooseFilterWidths' two
// sweeps over its widest candidate's window and then `layers` filterCorrection sweeps, counted
// over that widest window too (an upper bound: most pixels choose a narrower width), each
// window clipped at the image's borders. Zero below the filter's smallest width.
double reconstructionVisits(int width, int height, float sigma, int layers);
// Seconds per pixel pair of reconstructionVisits on this machine: a reconstruction of a small
// image timed once, on the first call, and kept.
double secondsPerReconstructionVisit();

}  // namespace penumbra
