#include "tests/support/image_compare.h"

#include "core/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace penumbra::test {
namespace {

std::string describe(const BlockTest& block) {
    const double relative =
        block.referenceMean != 0.0 ? 100.0 * (block.testMean / block.referenceMean - 1.0) : 0.0;
    char buffer[256];
    std::snprintf(buffer, sizeof buffer,
                  "channel %s, %dx%d block at (%d, %d): test %.5g, reference %.5g (%+.2f %%), "
                  "z = %.2f, p = %.3g",
                  block.channelName.c_str(), block.size, block.size, block.x, block.y,
                  block.testMean, block.referenceMean, relative, block.z, block.pValue);
    return buffer;
}

// One block of one channel: the z-score of the mean of d = test - reference.
BlockTest testBlock(const Image& test, const Image& reference, const Image& variance, int channel,
                    int x0, int y0, int size, const ImageCompareOptions& options) {
    const int x1 = std::min(x0 + size, test.width()), y1 = std::min(y0 + size, test.height());
    double sumT = 0.0, sumR = 0.0, sumVariance = 0.0;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            sumT += test.at(x, y, channel);
            sumR += reference.at(x, y, channel);
            sumVariance += std::max(0.0f, variance.at(x, y, channel));
        }
    }
    const double n = double(x1 - x0) * double(y1 - y0);
    BlockTest block;
    block.x = x0;
    block.y = y0;
    block.size = size;
    block.channel = channel;
    block.channelName = test.channelNames()[size_t(channel)];
    block.testMean = sumT / n;
    block.referenceMean = sumR / n;
    // Variance of the mean of n independent pixels, plus the reference's own noise, widened by
    // the tail allowance; the storage tolerances are added in quadrature.
    const double noise = options.tailAllowance * options.tailAllowance * sumVariance / (n * n) *
                         (1.0 + options.referenceVarianceRatio);
    const double tolerance = options.relativeTolerance * std::abs(block.referenceMean);
    block.standardError = std::sqrt(noise + tolerance * tolerance +
                                    options.absoluteTolerance * options.absoluteTolerance);
    const double difference = block.testMean - block.referenceMean;
    // A non-finite pixel is a failure, never a NaN that would break the sorting below.
    if (!std::isfinite(difference))
        block.z = std::numeric_limits<double>::infinity();
    else if (block.standardError > 0.0)
        block.z = difference / block.standardError;
    else
        block.z = difference == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
    // Two-sided p-value of the standard normal distribution.
    block.pValue = std::erfc(std::abs(block.z) / std::sqrt(2.0));
    return block;
}

// Smaller p-value first; among p-values that underflow to the same value, larger |z| first.
bool moreSignificant(const BlockTest& a, const BlockTest& b) {
    if (a.pValue != b.pValue)
        return a.pValue < b.pValue;
    return std::abs(a.z) > std::abs(b.z);
}

}  // namespace

ImageCompareResult compareImages(const Image& test, const Image& reference, const Image& variance,
                                 const ImageCompareOptions& options) {
    ImageCompareResult result;
    for (const Image* image : {&reference, &variance}) {
        if (image->width() != test.width() || image->height() != test.height() ||
            image->channelNames() != test.channelNames()) {
            char buffer[200];
            std::snprintf(buffer, sizeof buffer,
                          "the test image (%dx%d, %d channels), the reference (%dx%d, %d "
                          "channels) and the variance image (%dx%d, %d channels) do not match",
                          test.width(), test.height(), test.channels(), reference.width(),
                          reference.height(), reference.channels(), variance.width(),
                          variance.height(), variance.channels());
            result.reason = buffer;
            return result;
        }
    }
    if (options.blockSize < 1) {
        result.reason = "blockSize must be positive";
        return result;
    }

    // Every block at every scale, every channel.
    std::vector<BlockTest> blocks;
    const int largest = std::max(test.width(), test.height());
    for (int size = options.blockSize;; size *= 2) {
        for (int channel = 0; channel < test.channels(); ++channel) {
            for (int y = 0; y < test.height(); y += size) {
                for (int x = 0; x < test.width(); x += size)
                    blocks.push_back(
                        testBlock(test, reference, variance, channel, x, y, size, options));
            }
        }
        if (size >= largest)
            break;
    }
    result.testCount = int(blocks.size());
    // Sidak: each of the m tests at level 1 - (1 - alpha)^(1/m) keeps the family-wise rate at
    // alpha for independent tests, and below it for the positively dependent nested blocks.
    result.level = -std::expm1(std::log1p(-options.significance) / result.testCount);
    std::sort(blocks.begin(), blocks.end(), moreSignificant);
    result.worst = blocks.front();
    for (const BlockTest& block : blocks) {
        if (block.pValue >= result.level)
            break;
        result.failed.push_back(block);
    }

    // Whole-image bias per channel.
    for (int channel = 0; channel < test.channels(); ++channel) {
        double t = 0.0, r = 0.0;
        for (int y = 0; y < test.height(); ++y) {
            for (int x = 0; x < test.width(); ++x) {
                t += test.at(x, y, channel);
                r += reference.at(x, y, channel);
            }
        }
        result.relativeBias.push_back(r != 0.0 ? t / r - 1.0 : 0.0);
    }

    // The verdict, with the worst blocks.
    std::string reason;
    if (!result.failed.empty()) {
        char buffer[160];
        std::snprintf(buffer, sizeof buffer,
                      "%zu of %d block means differ from the reference (p below the "
                      "Sidak-corrected level %.3g); the worst:\n",
                      result.failed.size(), result.testCount, result.level);
        reason += buffer;
        for (size_t i = 0; i < std::min<size_t>(result.failed.size(), 8); ++i)
            reason += "  " + describe(result.failed[i]) + "\n";
    }
    result.reason = reason;
    result.passed = reason.empty();
    return result;
}

std::string ImageCompareResult::summary() const {
    if (testCount == 0)
        return reason;
    char buffer[200];
    std::snprintf(buffer, sizeof buffer,
                  "%d block z-tests at level %.3g, %zu failed; smallest p-value %.3g (z = %.2f, "
                  "channel %s, %dx%d block at (%d, %d))\nrelative bias per channel:",
                  testCount, level, failed.size(), worst.pValue, worst.z, worst.channelName.c_str(),
                  worst.size, worst.size, worst.x, worst.y);
    std::string text = buffer;
    for (const double bias : relativeBias) {
        std::snprintf(buffer, sizeof buffer, " %+.3f %%", 100.0 * bias);
        text += buffer;
    }
    return text;
}

double relativeMseEpsilon(const Image& reference) {
    double sum = 0.0;
    for (const float r : reference.pixels())
        sum += r;
    const double floor = 0.1 * sum / double(reference.pixels().size());
    return floor * floor;
}

ExpectedRelativeMse expectedRelativeMse(const Image& reference, const Image& variance,
                                        double referenceVarianceRatio, int blockSize,
                                        double epsilon) {
    // Block means of the reference and of the pixel variances: the variance of a block mean of
    // n independent pixels is (mean pixel variance) / n.
    const Image means = downsampleBlocks(reference, blockSize);
    const Image variances = downsampleBlocks(variance, blockSize);
    double sum = 0.0, sumSquares = 0.0;
    size_t terms = 0;
    for (int y = 0; y < means.height(); ++y) {
        const int rows = std::min(blockSize, reference.height() - y * blockSize);
        for (int x = 0; x < means.width(); ++x) {
            const int n = rows * std::min(blockSize, reference.width() - x * blockSize);
            for (int c = 0; c < means.channels(); ++c) {
                const double r = means.at(x, y, c);
                const double blockVariance =
                    std::max(0.0f, variances.at(x, y, c)) / n * (1.0 + referenceVarianceRatio);
                const double term = blockVariance / (r * r + epsilon);
                sum += term;
                sumSquares += term * term;
                ++terms;
            }
        }
    }
    ExpectedRelativeMse expected;
    expected.mean = sum / double(terms);
    expected.standardDeviation = std::sqrt(2.0 * sumSquares) / double(terms);
    return expected;
}

}  // namespace penumbra::test
