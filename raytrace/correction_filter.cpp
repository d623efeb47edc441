#include "raytrace/correction_filter.h"

#include "core/math.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace penumbra {

namespace {

// How alike two pixels' surfaces must be to share their correction. The correction is
// continuous along one smooth surface and jumps across edges: a crease (normals 15 degrees
// apart weigh exp(-(1 - cos 15°) / 0.01) = 0.03), a depth step (relative to the distance and to
// how far apart the pixels are, so a slanted wall still counts as one surface) or a change of
// material (albedo).
constexpr float kNormalScale = 0.01f;   // on 1 - cos(angle)
constexpr float kDepthScale = 0.03f;    // relative depth change per pixel of distance
constexpr float kAlbedoScale = 0.05f;   // on the largest channel difference
constexpr float kMinimumSigma = 0.25f;  // below: a Gaussian of one pixel, nothing to average

Vec3 pixel3(const Image& image, int x, int y) {
    return Vec3(image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2));
}

// A pixel's mean normal made unit again (the mean of its samples' normals is shorter at an edge),
// or zero where nothing was hit.
Vec3 unitNormal(const Image& normal, int x, int y) {
    const Vec3 n = pixel3(normal, x, y);
    const float length = glm::length(n);
    return length > 0.0f ? n / length : Vec3(0.0f);
}

// 1 - cos of the angle between two unit normals; two pixels that hit nothing are alike.
float normalGap(const Vec3& a, const Vec3& b) {
    const bool hitA = a != Vec3(0.0f), hitB = b != Vec3(0.0f);
    if (!hitA || !hitB)
        return hitA == hitB ? 0.0f : 1.0f;
    return 1.0f - glm::dot(a, b);
}

}  // namespace

float correctionFilterSigma(float sigmaAtOneSample, double samplesPerPixel) {
    return sigmaAtOneSample *
           static_cast<float>(std::pow(std::max(samplesPerPixel, 1.0), -1.0 / 6.0));
}

Image filterCorrection(const Image& image, const FilterGuide& guide, float sigma) {
    if (sigma < kMinimumSigma)
        return image;
    const int width = image.width(), height = image.height(), channels = image.channels();
    const int reach = static_cast<int>(std::ceil(2.0f * sigma));
    const float spatial = -0.5f / (sigma * sigma);
    // The guide's normals made unit once, not once per neighbour.
    std::vector<Vec3> normals(static_cast<size_t>(width) * height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            normals[static_cast<size_t>(y) * width + x] = unitNormal(guide.normal, x, y);
    Image filtered(width, height, image.channelNames());
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        std::vector<double> sum(static_cast<size_t>(channels));
        for (int y = rows.begin(); y < rows.end(); ++y) {
            for (int x = 0; x < width; ++x) {
                const Vec3& n = normals[static_cast<size_t>(y) * width + x];
                const float z = guide.depth.at(x, y, 0);
                const Vec3 a = pixel3(guide.albedo, x, y);
                std::fill(sum.begin(), sum.end(), 0.0);
                double weightSum = 0.0;
                for (int qy = std::max(y - reach, 0); qy <= std::min(y + reach, height - 1); ++qy) {
                    for (int qx = std::max(x - reach, 0); qx <= std::min(x + reach, width - 1);
                         ++qx) {
                        const float d2 = float(sqr(qx - x) + sqr(qy - y));
                        const float angleGap =
                            normalGap(n, normals[static_cast<size_t>(qy) * width + qx]);
                        const float depthGap =
                            std::abs(guide.depth.at(qx, qy, 0) - z) /
                            (kDepthScale * std::max(z, 1e-6f) * std::max(std::sqrt(d2), 1.0f));
                        const float albedoGap =
                            maxComponent(glm::abs(pixel3(guide.albedo, qx, qy) - a)) / kAlbedoScale;
                        const float w = std::exp(d2 * spatial - angleGap / kNormalScale - depthGap -
                                                 sqr(albedoGap));
                        weightSum += w;
                        for (int c = 0; c < channels; ++c)
                            sum[size_t(c)] += double(w) * image.at(qx, qy, c);
                    }
                }
                // weightSum >= 1: the pixel itself (d2 0, no gap) weighs exp(0).
                for (int c = 0; c < channels; ++c)
                    filtered.at(x, y, c) = float(sum[size_t(c)] / weightSum);
            }
        }
    });
    return filtered;
}

}  // namespace penumbra
