#include "core/light_sampler.h"

#include <algorithm>

namespace penumbra {

PowerLightSampler::PowerLightSampler(std::span<const std::unique_ptr<Light>> lights)
    : PowerLightSampler(lights, [](size_t) { return true; }) {}

PowerLightSampler::PowerLightSampler(std::span<const std::unique_ptr<Light>> lights,
                                     const std::function<bool(size_t)>& includes) {
    std::vector<float> weights;
    weights.reserve(lights.size());
    for (size_t i = 0; i < lights.size(); ++i)
        weights.push_back(includes(i) ? glm::max(luminance(lights[i]->power()), 0.0f) : 0.0f);
    table_ = AliasTable(weights);
}

std::optional<PowerLightSampler::Choice> PowerLightSampler::sample(float u) const {
    if (table_.empty())
        return std::nullopt;
    const uint32_t index = table_.sample(u);
    // A light of weight 0 is never drawn but for the alias table's rounding: not at all here.
    if (!(table_.pmf(index) > 0.0f))
        return std::nullopt;
    return Choice{index, table_.pmf(index)};
}

LightSelection::LightSelection(std::span<const std::unique_ptr<Light>> lights,
                               std::vector<uint32_t> setOf)
    : setOf_(std::move(setOf)) {
    uint32_t sets = 0;
    for (const uint32_t set : setOf_) {
        if (set != kNoSet)
            sets = std::max(sets, set + 1);
    }
    samplers_.reserve(sets);
    for (uint32_t s = 0; s < sets; ++s)
        samplers_.emplace_back(lights, [this, s](size_t i) { return setOf_[i] == s; });
}

}  // namespace penumbra
