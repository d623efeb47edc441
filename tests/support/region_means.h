// Mean radiance of each visible surface of a scene in a rendered image: the region comparisons of
// the Cornell box tests (each wall and block face is one mesh there).
#pragma once

#include "core/camera.h"
#include "core/image.h"
#include "core/scene.h"

#include <array>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace penumbra::test {

// Per pixel of a width x height image: the scene mesh seen through the whole pixel, or -1 where
// the pixel straddles an edge or sees nothing. A pixel counts for a region only when its centre
// and its four corners all see the same mesh, so that the pixel filter's average over the pixel
// belongs to one surface in every image compared.
std::vector<int> regionMask(const Scene& scene, const Camera& camera, int width, int height);
// The same through the scene's default camera (its first, else one framing its bounds), as
// `penumbra render` chooses it.
std::vector<int> regionMask(const Scene& scene, int width, int height);

struct RegionMeans {
    std::map<int, std::array<double, 3>> sums;  // by mesh: sum of R, G, B over its pixels
    std::map<int, int> pixels;                  // by mesh: pixel count

    double mean(int mesh, int channel) const { return sums.at(mesh)[channel] / pixels.at(mesh); }
};

RegionMeans regionMeans(const Image& image, const std::vector<int>& mask);

// Every region seen through at least minPixels whole pixels in the reference: prints the test's
// and the reference's mean per channel (`label` names the test image) and expects their ratio
// within tolerance(mesh name) of 1. Returns the number of such regions.
int expectRegionMeansNear(const Scene& scene, const RegionMeans& test, const RegionMeans& reference,
                          int minPixels, const std::string& label,
                          const std::function<double(const std::string& mesh)>& tolerance);

}  // namespace penumbra::test
