// Settings shared by every image-forming pass, resolved from the command line or a pass script.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace penumbra {

struct RenderSettings {
    int width = 0, height = 0;  // resolved image size (chooseImageSize in camera.h)
    std::string camera;         // camera name, empty = the scene's first (or a framing one)
    int spp = 64;               // samples per pixel (the target when a time limit is set)
    uint32_t seed = 0;
    int threads = 0;         // 0 = all hardware threads
    double timeLimit = 0.0;  // seconds, 0 = none; stops at whole passes of samples
    int maxDepth = -1;       // maximum number of scattering events, -1 = unlimited
    std::string filter = "box";
    std::vector<std::string> aovs;  // extra layers: albedo, normal, depth, spp
    // Adaptive sampling: a pixel whose relative standard error (Film::relativeStandardError)
    // falls below this after kAdaptiveMinSpp samples takes no more; 0 = off.
    float noiseThreshold = 0.0f;
    static constexpr int kAdaptiveMinSpp = 16;
    // File the image by light group (core/light_groups.h) in this one render, a layer per group:
    // asked of the passes that can (Pass::splitsLightGroups).
    bool lightGroups = false;
    bool quiet = false;
};

}  // namespace penumbra
