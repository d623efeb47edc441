#include "tests/support/region_means.h"

#include <gtest/gtest.h>

#include <cstdio>

namespace penumbra::test {

std::vector<int> regionMask(const Scene& scene, const Camera& camera, int width, int height) {
    std::vector<int> mask(static_cast<size_t>(width) * height, -1);
    const std::array<Vec2, 5> offsets = {Vec2{0.5f, 0.5f}, Vec2{0.0f, 0.0f}, Vec2{1.0f, 0.0f},
                                         Vec2{0.0f, 1.0f}, Vec2{1.0f, 1.0f}};
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            int region = -2;
            for (const Vec2& o : offsets) {
                const auto hit = scene.intersect(camera.generateRay(Vec2(x, y) + o));
                const int mesh = hit ? static_cast<int>(hit->mesh) : -1;
                region = (region == -2 || region == mesh) ? mesh : -1;
            }
            mask[static_cast<size_t>(y) * width + x] = region;
        }
    }
    return mask;
}

std::vector<int> regionMask(const Scene& scene, int width, int height) {
    const CameraDesc desc = chooseCamera(scene.description().cameras, "", scene.bounds());
    return regionMask(scene, Camera(desc, width, height), width, height);
}

RegionMeans regionMeans(const Image& image, const std::vector<int>& mask) {
    RegionMeans means;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x) {
            const int region = mask[static_cast<size_t>(y) * image.width() + x];
            if (region < 0)
                continue;
            auto& sum = means.sums[region];
            for (int c = 0; c < 3; ++c)
                sum[c] += image.at(x, y, c);
            ++means.pixels[region];
        }
    }
    return means;
}

int expectRegionMeansNear(const Scene& scene, const RegionMeans& test, const RegionMeans& reference,
                          int minPixels, const std::string& label,
                          const std::function<double(const std::string& mesh)>& tolerance) {
    int regions = 0;
    for (const auto& [mesh, pixels] : reference.pixels) {
        if (pixels < minPixels)
            continue;
        ++regions;
        const std::string& name = scene.meshes()[mesh].name;
        for (int c = 0; c < 3; ++c) {
            const double ratio = test.mean(mesh, c) / reference.mean(mesh, c);
            std::printf("%-22s channel %d  pixels %5d  %s %9.4f  reference %9.4f  ratio %.4f\n",
                        name.c_str(), c, pixels, label.c_str(), test.mean(mesh, c),
                        reference.mean(mesh, c), ratio);
            EXPECT_NEAR(ratio, 1.0, tolerance(name)) << name << " channel " << c;
        }
    }
    return regions;
}

}  // namespace penumbra::test
