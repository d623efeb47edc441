// The bookkeeping over a batch of pending links (radiosity/pending_links.h) against the plain
// sequential algorithms it replaces: a scan with a hash map of the first link of each direction
// for the reverse pairs, and appending each kept link to its receiver's list in batch order.
#include "radiosity/pending_links.h"

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>
#include <unordered_map>
#include <vector>

namespace penumbra::test {
namespace {

// A batch over a few nodes, so that both directions of a pair, repeats and self-pairs occur;
// negative ids stand for clusters, as in the solver.
std::vector<PendingLink> randomBatch(size_t size, int nodes, uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_int_distribution<int> node(-nodes / 4, nodes - 1);
    std::vector<PendingLink> batch(size);
    for (PendingLink& link : batch) {
        link.receiver = node(random);
        link.source = node(random);
    }
    return batch;
}

bool eligible(const PendingLink& link) {
    return (link.receiver + 2 * link.source) % 7 != 0;
}

// The sequential scan: each link looks up the first earlier link in the opposite direction and
// pairs with it if that one is unpaired; otherwise it is remembered as the first of its own.
ReversePairs sequentialPairs(const std::vector<PendingLink>& batch) {
    ReversePairs pairs{std::vector<int>(batch.size(), -1), std::vector<char>(batch.size(), 1)};
    std::map<std::pair<int, int>, int> first;
    for (size_t i = 0; i < batch.size(); ++i) {
        if (!eligible(batch[i]))
            continue;
        const auto it = first.find({batch[i].source, batch[i].receiver});
        if (it != first.end() && pairs.reverse[static_cast<size_t>(it->second)] < 0) {
            pairs.reverse[static_cast<size_t>(it->second)] = static_cast<int>(i);
            pairs.reverse[i] = it->second;
            pairs.primary[i] = 0;
        } else {
            first.emplace(std::make_pair(batch[i].receiver, batch[i].source), static_cast<int>(i));
        }
    }
    return pairs;
}

TEST(PendingLinks, ReversePairsAreTheSequentialScans) {
    for (const uint32_t seed : {1u, 2u, 3u}) {
        for (const auto& [size, nodes] :
             {std::pair<size_t, int>{0, 4}, {1, 4}, {2000, 8}, {50000, 40}, {200000, 2000}}) {
            const std::vector<PendingLink> batch = randomBatch(size, nodes, seed);
            const ReversePairs expected = sequentialPairs(batch);
            const ReversePairs pairs = pairReverses(batch, eligible);
            EXPECT_EQ(pairs.reverse, expected.reverse) << size << " links, seed " << seed;
            EXPECT_EQ(pairs.primary, expected.primary) << size << " links, seed " << seed;
        }
    }
    // The small batches do pair something, and self-pairs pair with a repeat of themselves.
    const std::vector<PendingLink> self{{3, 3, {}}, {3, 3, {}}, {3, 3, {}}};
    const ReversePairs pairs = pairReverses(self, [](const PendingLink&) { return true; });
    EXPECT_EQ(pairs.reverse, (std::vector<int>{1, 0, -1}));
    EXPECT_EQ(pairs.primary, (std::vector<char>{1, 0, 1}));
}

TEST(PendingLinks, ReceiverGroupsAreTheKeptLinksOfOneReceiverInBatchOrder) {
    const std::vector<PendingLink> batch = randomBatch(100000, 3000, 7);
    const auto kept = [&](size_t i) { return i % 3 != 1; };
    // Appending each kept link to its receiver's list, in batch order.
    std::unordered_map<int, std::vector<uint32_t>> lists;
    for (size_t i = 0; i < batch.size(); ++i) {
        if (kept(i))
            lists[batch[i].receiver].push_back(static_cast<uint32_t>(i));
    }
    const ReceiverGroups groups(batch, kept);
    ASSERT_EQ(groups.size(), lists.size());
    std::set<int> seen;
    for (size_t g = 0; g < groups.size(); ++g) {
        const std::span<const uint32_t> members = groups.members(g);
        ASSERT_FALSE(members.empty());
        const int receiver = batch[members.front()].receiver;
        EXPECT_TRUE(seen.insert(receiver).second) << "receiver " << receiver << " split";
        EXPECT_EQ(std::vector<uint32_t>(members.begin(), members.end()), lists[receiver]);
    }
    EXPECT_EQ(ReceiverGroups(batch, [](size_t) { return false; }).size(), 0u);
}

}  // namespace
}  // namespace penumbra::test
