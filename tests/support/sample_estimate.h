// The running mean and standard error of one quantity over independent samples, for the
// statistical checks of in-process estimator tests (the furnace tests).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::test {

struct Estimate {
    double sum = 0.0, sumSquares = 0.0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    int n = 0;

    void add(double x) {
        sum += x;
        sumSquares += x * x;
        lo = std::min(lo, x);
        hi = std::max(hi, x);
        ++n;
    }
    double mean() const { return sum / n; }
    // The sample standard deviation over sqrt(n).
    double standardError() const {
        const double variance = (sumSquares - sum * sum / n) / (n - 1);
        return std::sqrt(std::max(variance, 0.0) / n);
    }
};

}  // namespace penumbra::test
