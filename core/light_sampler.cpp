#include "core/light_sampler.h"

namespace penumbra {

PowerLightSampler::PowerLightSampler(std::span<const std::unique_ptr<Light>> lights) {
    std::vector<float> weights;
    weights.reserve(lights.size());
    for (const auto& light : lights)
        weights.push_back(glm::max(luminance(light->power()), 0.0f));
    table_ = AliasTable(weights);
}

std::optional<PowerLightSampler::Choice> PowerLightSampler::sample(float u) const {
    if (table_.empty())
        return std::nullopt;
    const uint32_t index = table_.sample(u);
    return Choice{index, table_.pmf(index)};
}

}  // namespace penumbra
