// Chooses which light a next-event estimate samples: in proportion to emitted power
// (luminance of the flux), with an alias table for O(1) selection.
#pragma once

#include "core/light.h"
#include "core/sampling.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace penumbra {

class PowerLightSampler {
  public:
    explicit PowerLightSampler(std::span<const std::unique_ptr<Light>> lights);
    // Among the lights for which `includes(index)` holds alone; the others are never chosen and
    // their pmf() is 0.
    PowerLightSampler(std::span<const std::unique_ptr<Light>> lights,
                      const std::function<bool(size_t)>& includes);

    // Index of the chosen light and its probability; nothing when there is no light with power.
    struct Choice {
        uint32_t light;
        float pmf;
    };
    std::optional<Choice> sample(float u) const;
    float pmf(uint32_t light) const { return table_.empty() ? 0.0f : table_.pmf(light); }

  private:
    AliasTable table_;
};

// How next-event estimation chooses lights when the lights are split into sets and each estimate
// draws one light from every set, by power within the set: a render that files its light by
// light group (core/light_groups.h) samples each group as a render of that group alone would, so
// that no group's layer is noisier for sharing the render with the others. The estimate is the
// sum of one sample per set; multiple importance sampling weighs a light by its pmf() within its
// set (Veach 1997, Eq. 9.13, with the set's selection as the light strategy).
class LightSelection {
  public:
    LightSelection() = default;
    // setOf[i]: the set of light i, from 0 to the number of sets less one, or kNoSet for a light
    // no set draws (whose caller samples it otherwise).
    LightSelection(std::span<const std::unique_ptr<Light>> lights, std::vector<uint32_t> setOf);
    static constexpr uint32_t kNoSet = UINT32_MAX;

    size_t sets() const { return samplers_.size(); }
    const PowerLightSampler& set(size_t s) const { return samplers_[s]; }
    // The probability that light `light` is drawn by its set's sample; 0 in no set.
    float pmf(uint32_t light) const {
        return setOf_[light] == kNoSet ? 0.0f : samplers_[setOf_[light]].pmf(light);
    }

  private:
    std::vector<uint32_t> setOf_;
    std::vector<PowerLightSampler> samplers_;
};

}  // namespace penumbra
