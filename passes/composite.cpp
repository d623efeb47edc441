#include "passes/composite.h"

#include "core/image_luminance.h"
#include "core/stats.h"
#include "raytrace/image_renderer.h"

#include <algorithm>
#include <chrono>

namespace penumbra {

void compositeContributions(PassContext& context) {
    const RenderSettings& s = context.settings;
    context.layers["beauty"] = Image(s.width, s.height, {"R", "G", "B"});
    for (const std::string& name : context.contributions)
        context.addToLayer("beauty", context.layers.at(name));
    // Requested layers no pass made (every image-forming pass skipped) are black, so that the
    // output has every layer it was asked for.
    const std::vector<std::string>& aovs = s.aovs;
    if (std::find(aovs.begin(), aovs.end(), "luminance") != aovs.end())
        context.layers["luminance"] = luminanceImage(context.layers.at("beauty"));
    const std::vector<AovSpec> specs = aovSpecs(aovs);
    for (size_t a = 0; a < aovs.size(); ++a) {
        if (!context.layers.contains(aovs[a]))
            context.layers[aovs[a]] = Image(s.width, s.height, specs[a].channels);
    }
}

bool CompositePass::run(PassContext& context) {
    const auto start = std::chrono::steady_clock::now();
    compositeContributions(context);
    std::string layers;
    for (const std::string& name : context.contributions)
        layers += (layers.empty() ? "" : " + ") + name;
    stats_ = {{"beauty", layers.empty() ? "black (no pass contributed)" : layers},
              {"seconds", formatStat(secondsSince(start))}};
    return true;
}

}  // namespace penumbra
