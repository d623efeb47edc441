// A chi-square goodness-of-fit test of a direction sampler against the density it claims, as
// pbrt-v4's bsdfs_test.cpp, Mitsuba 3's chi2.py and Nori's chi2test do it: directions are binned
// in (cos theta, phi) over the whole sphere, the expected count of each bin is the sample count
// times the integral of pdf() over the bin, bins expecting fewer than 5 samples are pooled, and
// the statistic's p-value is compared with a Sidak-corrected significance level.
#pragma once

#include "core/math.h"

#include <functional>
#include <optional>
#include <string>

namespace penumbra {

struct Chi2Options {
    int thetaBins = 10;  // bins in cos(theta) over [-1, 1]
    int phiBins = 20;    // bins in phi over [0, 2 pi)
    int sampleCount = 200000;
    uint32_t seed = 1;
    double minExpected = 5.0;  // cells expecting fewer samples are pooled (Cochran's rule)
    double significance = 0.01;
    int testCount = 1;  // tests in the family: the level is Sidak-corrected over them
};

struct Chi2Result {
    bool passed = false;
    double statistic = 0.0;
    int dof = 0;
    double pValue = 0.0;
    double level = 0.0;  // Sidak-corrected significance the p-value is compared with
    std::string report;  // why it failed, with the observed and expected tables
};

// sample(u) maps three uniform numbers to a direction, or to nothing (a rejected sample, or one
// that pdf() does not describe, such as a delta lobe: their share is the missing mass of pdf(),
// and it forms one more cell). pdf(w) is per unit solid angle.
Chi2Result chi2Test(const std::function<std::optional<Vec3>(const Vec3& u)>& sample,
                    const std::function<float(const Vec3& w)>& pdf, const Chi2Options& options);

// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a); the p-value of
// a chi-square statistic X with k degrees of freedom is Q(k / 2, X / 2).
double regularizedGammaQ(double a, double x);

}  // namespace penumbra
