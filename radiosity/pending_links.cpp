#include "radiosity/pending_links.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <array>

namespace penumbra {

namespace {

// A node id as the high or low half of a 64-bit key (cluster ids are negative; only equality
// and a fixed order matter).
uint64_t half(int node) {
    return static_cast<uint32_t>(node);
}

}  // namespace

ReversePairs pairReverses(std::span<const PendingLink> pending,
                          const std::function<bool(const PendingLink&)>& eligible) {
    const size_t n = pending.size();
    ReversePairs result{std::vector<int>(n, -1), std::vector<char>(n, 1)};
    // The eligible links sorted by their unordered pair of ends, then by index: a pair's two
    // directions end up next to each other, in batch order.
    struct Entry {
        uint64_t ends;  // min(receiver, source), max(...) as unsigned halves
        uint32_t index;
        bool eligible;
    };
    std::vector<Entry> entries(n);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
        const uint64_t r = half(pending[i].receiver), s = half(pending[i].source);
        entries[i] = {r < s ? (r << 32) | s : (s << 32) | r, static_cast<uint32_t>(i),
                      eligible(pending[i])};
    });
    tbb::parallel_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        if (a.eligible != b.eligible)
            return a.eligible;
        return a.ends != b.ends ? a.ends < b.ends : a.index < b.index;
    });
    // Within a run of one unordered pair, the scan in batch order: a link pairs with the first
    // link of the opposite direction if that one is unpaired; otherwise it becomes the first of
    // its own direction unless there is one. A link from a node to itself is its own opposite.
    size_t begin = 0;
    while (begin < n && entries[begin].eligible) {
        size_t end = begin;
        while (end < n && entries[end].eligible && entries[end].ends == entries[begin].ends)
            ++end;
        std::array<int, 2> first{-1, -1};  // the first link of each direction
        for (size_t k = begin; k < end; ++k) {
            const PendingLink& link = pending[entries[k].index];
            const int i = static_cast<int>(entries[k].index);
            const size_t direction = half(link.receiver) < half(link.source) ? 0 : 1;
            const size_t opposite = link.receiver == link.source ? direction : 1 - direction;
            const int j = first[opposite];
            if (j >= 0 && result.reverse[static_cast<size_t>(j)] < 0) {
                result.reverse[static_cast<size_t>(j)] = i;
                result.reverse[static_cast<size_t>(i)] = j;
                result.primary[static_cast<size_t>(i)] = 0;
            } else if (first[direction] < 0) {
                first[direction] = i;
            }
        }
        begin = end;
    }
    return result;
}

ReceiverGroups::ReceiverGroups(std::span<const PendingLink> pending,
                               const std::function<bool(size_t)>& kept) {
    const size_t n = pending.size();
    // Keys: the receiver in the high half, the index in the low one; the links not kept last.
    constexpr uint64_t kDropped = ~uint64_t(0);
    std::vector<uint64_t> keys(n);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
        keys[i] = kept(i) ? (half(pending[i].receiver) << 32) | i : kDropped;
    });
    tbb::parallel_sort(keys.begin(), keys.end());
    starts_.push_back(0);
    for (const uint64_t key : keys) {
        if (key == kDropped)
            break;
        const auto index = static_cast<uint32_t>(key);
        if (!order_.empty() && (key >> 32) != (half(pending[order_.back()].receiver)))
            starts_.push_back(order_.size());
        order_.push_back(index);
    }
    if (!order_.empty())
        starts_.push_back(order_.size());
}

}  // namespace penumbra
