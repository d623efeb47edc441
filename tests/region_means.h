// Mean radiance of each visible surface of a scene in a rendered image: the region comparisons of
// the Cornell box tests (each wall and block face is one mesh there).
#pragma once

#include "core/camera.h"
#include "core/image.h"
#include "core/scene.h"

#include <array>
#include <map>
#include <vector>

namespace penumbra::test {

// Per pixel of a width x height image: the scene mesh seen through the whole pixel, or -1 where
// the pixel straddles an edge or sees nothing. A pixel counts for a region only when its centre
// and its four corners all see the same mesh, so that the pixel filter's average over the pixel
// belongs to one surface in every image compared.
std::vector<int> regionMask(const Scene& scene, const Camera& camera, int width, int height);

struct RegionMeans {
    std::map<int, std::array<double, 3>> sums;  // by mesh: sum of R, G, B over its pixels
    std::map<int, int> pixels;                  // by mesh: pixel count

    double mean(int mesh, int channel) const { return sums.at(mesh)[channel] / pixels.at(mesh); }
};

RegionMeans regionMeans(const Image& image, const std::vector<int>& mask);

}  // namespace penumbra::test
