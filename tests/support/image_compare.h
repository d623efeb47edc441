// Noise-aware comparison of a low-sample render with a converged reference, for image
// regression tests (docs/testing.md). Two checks, both needed:
//
//  * Bias (the mean is wrong): multi-scale block z-tests. For every channel and every block of
//    K x K, 2K x 2K, ... pixels up to the whole image, the mean of d = test - reference over the
//    block is tested against 0. Its standard error comes from a per-pixel variance image stored
//    with the reference: the variance of one pixel of a render at the test's spp, measured once
//    over many independent renders (scripts/update-references). Pixels are independent (each
//    has its own scrambled sample sequence), so SE^2 = sum of the block's variances / n^2,
//    widened by a measured allowance for the noise's heavy tail (tailAllowance below).
//    Small blocks catch local errors, the large ones small errors spread over a region or the
//    whole image. The tests form one family, so each is run at the Sidak level
//    1 - (1 - alpha)^(1/m) for m tests (Sidak 1967), like tests/support/chi2.h. This is Mitsuba 3's
//    per-pixel z-test against a stored variance image (test_renders.py) applied to block means,
//    as Jung, Hanika and Dachsbacher test regions ("Detecting Bias in Monte Carlo Renderers
//    using Welch's t-test", JCGT 9(2), 2020): a block of n pixels has n times the samples.
//    Why not the block's own spread: path-tracing noise is skewed, so a block that drew few of
//    the rare bright paths has both a low mean and a small spread; its t is then far too large
//    (measured: 4 of 18 correct Cornell-box renders failed at alpha = 0.01 that way).
//  * Noise (the variance is wrong: fireflies, a broken sampler, a lost strategy) and bias over
//    the whole image: the relative MSE, mean over pixels (or K x K block means) and channels of
//    (t - r)^2 / (r^2 + eps), must stay below a bound derived from its expected value for a
//    correct render. `penumbra diff --fail-above relmse=T` applies that bound (the regression
//    tests gate on its exit status); expectedRelativeMse() computes the expectation from the
//    same variance image.
#pragma once

#include "core/image.h"

#include <string>
#include <vector>

namespace penumbra::test {

struct ImageCompareOptions {
    int blockSize = 8;           // finest block side K; then 2K, 4K, ... up to the whole image
    double significance = 0.01;  // family-wise probability of failing a correct render
    // Multiplies each block's noise standard error: an allowance for the heavy right tail of
    // path-tracing noise. Where rare bright paths carry much of a channel (red on the green
    // wall: colour bleeding), block means are skewed and z exceeds the normal's Sidak level far
    // more often than it should. Measured on the Cornell box at 64 spp (docs/testing.md): with
    // 1, 4 of 80 correct renders failed; with 1.5, none did, the largest |z| being 3.6 against
    // a threshold of 4.4.
    double tailAllowance = 1.5;
    // Variance of the reference's pixels relative to the test's (test spp / reference spp); the
    // reference's own noise is added to each block's variance in this proportion.
    double referenceVarianceRatio = 0.0;
    // Systematic error allowed in a block mean, relative to the reference's mean: the float16
    // storage of the reference rounds every value by up to 2^-11 = 4.9e-4 relative.
    double relativeTolerance = 1e-3;
    double absoluteTolerance = 1e-6;  // the same in absolute terms, for black blocks
};

// One block test: the block [x, x + size) x [y, y + size) (clipped) of one channel.
struct BlockTest {
    int x = 0, y = 0, size = 0, channel = 0;
    std::string channelName;
    double testMean = 0.0, referenceMean = 0.0;
    double standardError = 0.0;  // of testMean - referenceMean, tolerances included
    double z = 0.0;              // (testMean - referenceMean) / standardError
    double pValue = 1.0;         // two-sided, standard normal
};

struct ImageCompareResult {
    bool passed = false;
    std::string reason;  // empty when passed; otherwise what failed, with the worst blocks

    int testCount = 0;              // block tests in the family (all scales and channels)
    double level = 0.0;             // Sidak-corrected significance of each block test
    BlockTest worst;                // the block with the smallest p-value
    std::vector<BlockTest> failed;  // blocks whose p-value is below level, worst first

    // Whole image, per channel: (test mean / reference mean) - 1.
    std::vector<double> relativeBias;

    // A few lines with the statistics above, for test logs.
    std::string summary() const;
};

// Compares `test` with `reference`; `variance` holds the variance of each pixel of a render made
// like `test` (same spp). The three must have the same size and channel names, else passed =
// false with the reason. A non-finite test pixel fails its blocks.
ImageCompareResult compareImages(const Image& test, const Image& reference, const Image& variance,
                                 const ImageCompareOptions& options);

// eps of the relative MSE for a regression scene: (0.1 x the mean of the reference's values)^2,
// so that pixels darker than a tenth of the image mean do not dominate the statistic, whatever
// the scene's units or exposure (penumbra diff's fixed default, 0.01, suits values near 1 only).
double relativeMseEpsilon(const Image& reference);

// Mean and standard deviation of the relative MSE that `penumbra diff --downsample K --epsilon
// eps` reports for a correct render, from the variance of one pixel of such a render. A K x K
// block mean has the variance sum(var) / n^2 (independent pixels), plus the reference's own
// noise in the proportion referenceVarianceRatio (test spp / reference spp); each term of the
// relMSE has the expectation var_b / (R_b^2 + eps), R_b the reference's block mean. The
// standard deviation assumes normal block means (a term is then var_b / (R_b^2 + eps) x
// chi^2_1, whose variance is 2 x its mean squared) and independent terms; path-tracing noise has
// a heavier tail, which the threshold rule allows for (docs/testing.md).
struct ExpectedRelativeMse {
    double mean = 0.0, standardDeviation = 0.0;
};
ExpectedRelativeMse expectedRelativeMse(const Image& reference, const Image& variance,
                                        double referenceVarianceRatio, int blockSize,
                                        double epsilon);

}  // namespace penumbra::test
