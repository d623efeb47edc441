#include "passes/composite.h"

#include "core/stats.h"

#include <chrono>
#include <stdexcept>

namespace penumbra {

void compositeContributions(PassContext& context) {
    const RenderSettings& s = context.settings;
    Image beauty(s.width, s.height, {"R", "G", "B"});
    for (const std::string& name : context.contributions) {
        const Image& layer = context.layers.at(name);
        if (layer.width() != beauty.width() || layer.height() != beauty.height() ||
            layer.channels() != beauty.channels()) {
            throw std::logic_error("composite: layer " + name + " has another size or channels");
        }
        const auto in = layer.pixels();
        auto out = beauty.pixels();
        for (size_t i = 0; i < out.size(); ++i)
            out[i] += in[i];
    }
    context.layers["beauty"] = std::move(beauty);
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
