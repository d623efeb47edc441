// Chooses which light a next-event estimate samples: in proportion to emitted power
// (luminance of the flux), with an alias table for O(1) selection.
#pragma once

#include "core/light.h"
#include "core/sampling.h"

#include <memory>
#include <span>
#include <vector>

namespace penumbra {

class PowerLightSampler {
  public:
    explicit PowerLightSampler(std::span<const std::unique_ptr<Light>> lights);

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

}  // namespace penumbra
