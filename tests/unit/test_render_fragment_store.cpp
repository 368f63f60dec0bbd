// FragmentStore under overflow: the fragments kept are the K least (depth, splat index) whatever
// the arrival order, equal depths included, and fragments beyond the depth window of the final
// nearest one change nothing (what lets occlusion culling drop splats hidden that far behind).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "render/fragment_store.h"

namespace splatkit::render {
namespace {

struct Frag {
  float depth, weight;
  uint32_t splat;
};

// The (depth, splat, weight) of the fragments stored at pixel 0, sorted.
std::vector<std::tuple<float, uint32_t, float>> stored(const std::vector<Frag>& frags, int capacity,
                                                       float window) {
  FragmentStore store;
  store.reset(1, capacity, window);
  for (const Frag& f : frags) store.add(0, f.depth, f.weight, f.splat);
  std::vector<std::tuple<float, uint32_t, float>> out;
  const float limit = store.nearest(0) + window;
  for (int k = 0; k < store.count(0); ++k)
    if (store.depths(0)[k] <= limit)
      out.emplace_back(store.depths(0)[k], store.splats(0)[k], store.weights(0)[k]);
  std::sort(out.begin(), out.end());
  return out;
}

TEST(RenderFragmentStore, OverflowKeepsTheLeastDepthAndIndexInAnyOrder) {
  std::mt19937 rng(7);
  const int capacity = 4;
  const float window = 1.0f;
  for (int round = 0; round < 200; ++round) {
    // Many fragments on few distinct depths (ties), near 10, and some far behind the window.
    std::vector<Frag> front, far;
    std::uniform_int_distribution<int> level(0, 3), count(5, 12), far_count(1, 4);
    const int n = count(rng);
    for (int i = 0; i < n; ++i)
      front.push_back({10.0f + 0.1f * level(rng), float(i + 1), uint32_t(2 * i)});
    for (int i = 0, m = far_count(rng); i < m; ++i)
      far.push_back({10.0f + 0.3f + 2.0f * window + i, 0.5f, uint32_t(2 * i + 1)});
    const auto expect = stored(front, capacity, window);
    ASSERT_EQ(expect.size(), std::size_t(capacity));
    // The least keys, whatever the order, with or without the far fragments anywhere in it.
    std::vector<Frag> keys(front);
    std::sort(keys.begin(), keys.end(), [](const Frag& a, const Frag& b) {
      return std::tie(a.depth, a.splat) < std::tie(b.depth, b.splat);
    });
    for (int k = 0; k < capacity; ++k) {
      EXPECT_EQ(std::get<0>(expect[k]), keys[k].depth);
      EXPECT_EQ(std::get<1>(expect[k]), keys[k].splat);
    }
    for (int shuffle = 0; shuffle < 5; ++shuffle) {
      std::vector<Frag> all(front);
      all.insert(all.end(), far.begin(), far.end());
      std::shuffle(all.begin(), all.end(), rng);
      EXPECT_EQ(stored(all, capacity, window), expect) << "round " << round;
      std::vector<Frag> some(front);
      std::shuffle(some.begin(), some.end(), rng);
      EXPECT_EQ(stored(some, capacity, window), expect) << "round " << round;
    }
  }
}

// Ring fragments (negative weights) have kRingSlots slots of their own: they never push out a
// disc fragment nor a disc fragment them, losing one does not flag the pixel, and they do not set
// the nearest depth the window counts from. Whatever the arrival order.
TEST(RenderFragmentStore, RingFragmentsHaveSlotsOfTheirOwn) {
  std::vector<Frag> frags{{2.0f, 0.5f, 3}, {2.5f, 0.4f, 4}, {3.0f, 0.3f, 5}};
  for (uint32_t k = 0; k < kRingSlots + 2; ++k) frags.push_back({1.0f + 0.1f * k, -0.1f, 10 + k});
  std::vector<Frag> order(frags);
  std::mt19937 rng(7);
  for (int round = 0; round < 20; ++round) {
    std::shuffle(order.begin(), order.end(), rng);
    FragmentStore store;
    store.reset(1, 3, 10.0f);
    for (const Frag& f : order) store.add(0, f.depth, f.weight, f.splat);
    EXPECT_EQ(store.nearest(0), 2.0f);
    EXPECT_FALSE(store.overflowed(0));
    ASSERT_EQ(store.count(0), 3);
    ASSERT_EQ(store.ring_count(0), kRingSlots);
    std::vector<uint32_t> discs(store.splats(0), store.splats(0) + 3);
    std::vector<uint32_t> rings(store.splats(0) + store.ring_offset(),
                                store.splats(0) + store.ring_offset() + kRingSlots);
    std::sort(discs.begin(), discs.end());
    std::sort(rings.begin(), rings.end());
    EXPECT_EQ(discs, (std::vector<uint32_t>{3, 4, 5}));
    std::vector<uint32_t> nearest_rings;
    for (uint32_t k = 0; k < kRingSlots; ++k) nearest_rings.push_back(10 + k);
    EXPECT_EQ(rings, nearest_rings);
  }
  // A fourth disc fragment overflows the disc slots: flagged.
  FragmentStore store;
  store.reset(1, 3, 10.0f);
  for (const Frag& f : frags) store.add(0, f.depth, f.weight, f.splat);
  store.add(0, 2.2f, 0.6f, 6);
  EXPECT_TRUE(store.overflowed(0));
}

}  // namespace
}  // namespace splatkit::render
