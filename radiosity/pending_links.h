// The links the refinement oracle has decided to make, before their form factors and visibility
// are evaluated (LinkRefiner::evaluateLinks), and the two pieces of bookkeeping over such a batch
// that would otherwise be serial: finding each link's reverse, and grouping the links by the
// receiver whose list they join. Both are sorts, so they run in parallel and their results do
// not depend on the thread count.
#pragma once

#include "radiosity/link_transfer.h"

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace penumbra {

struct PendingLink {
    int receiver, source;
    KernelSamples samples;
};

// Each link's reverse in the batch (-1 for none), and whether it is the one of its pair to be
// evaluated (the other takes its values). The pairing is that of a scan in batch order that
// pairs each link with the first earlier link in the opposite direction, if that one is still
// unpaired; links `eligible` rejects take no part.
struct ReversePairs {
    std::vector<int> reverse;
    std::vector<char> primary;
};
ReversePairs pairReverses(std::span<const PendingLink> pending,
                          const std::function<bool(const PendingLink&)>& eligible);

// The indices of the links `kept` accepts, grouped by receiver, in batch order within a group.
class ReceiverGroups {
  public:
    ReceiverGroups(std::span<const PendingLink> pending, const std::function<bool(size_t)>& kept);

    size_t size() const { return starts_.size() - 1; }
    std::span<const uint32_t> members(size_t group) const {
        return {order_.data() + starts_[group], starts_[group + 1] - starts_[group]};
    }

  private:
    std::vector<uint32_t> order_;
    std::vector<size_t> starts_;
};

}  // namespace penumbra
