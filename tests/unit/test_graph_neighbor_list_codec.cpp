// neighbor_list_codec: pinned bytes, round trips, and each hostile-input case.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/neighbor_list_codec.h"
#include "splatkit/error.h"

namespace splatkit::graph {
namespace {

// 0:{1,3} 1:{0,2} 2:{1} 3:{0}
const std::vector<uint64_t> kOffsets{0, 2, 4, 5, 6};
const std::vector<uint32_t> kNeighbors{1, 3, 0, 2, 1, 0};

NeighborLists decode(const std::vector<uint8_t>& bytes, uint64_t rows, NeighborListMode mode) {
  return decode_neighbor_lists(bytes, rows, mode, "g.splk");
}

std::string error_of(const std::vector<uint8_t>& bytes, uint64_t rows,
                     NeighborListMode mode = NeighborListMode::kFull) {
  try {
    decode(bytes, rows, mode);
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    return e.what();
  }
  return "<no error>";
}

TEST(GraphNeighborListCodec, PinnedBytesFull) {
  // Row: degree, zigzag(first - i), gaps - 1. Row 1: zigzag(-1) = 1; row 3: zigzag(-3) = 5.
  const std::vector<uint8_t> expected{2, 2, 1, 2, 1, 1, 1, 1, 1, 5};
  EXPECT_EQ(encode_neighbor_lists(kOffsets, kNeighbors, NeighborListMode::kFull), expected);
  const auto back = decode(expected, 4, NeighborListMode::kFull);
  EXPECT_EQ(back.offsets, kOffsets);
  EXPECT_EQ(back.neighbors, kNeighbors);
}

TEST(GraphNeighborListCodec, PinnedBytesUpper) {
  // Only j > i: 0:{1,3} -> 2, 0, 1; 1:{2} -> 1, 0; 2:{} -> 0; 3:{} -> 0.
  const std::vector<uint8_t> expected{2, 0, 1, 1, 0, 0, 0};
  EXPECT_EQ(encode_neighbor_lists(kOffsets, kNeighbors, NeighborListMode::kUpper), expected);
  const auto back = decode(expected, 4, NeighborListMode::kUpper);
  EXPECT_EQ(back.offsets, kOffsets);
  EXPECT_EQ(back.neighbors, kNeighbors);
}

TEST(GraphNeighborListCodec, MultiByteVarints) {
  // 0:{300} and 300:{0} in 301 rows: upper row 0 codes 299 = 0xAB 0x02.
  std::vector<uint64_t> offsets(302, 1);
  offsets[0] = 0;
  offsets[301] = 2;
  const std::vector<uint32_t> neighbors{300, 0};
  const auto bytes = encode_neighbor_lists(offsets, neighbors, NeighborListMode::kUpper);
  ASSERT_EQ(bytes.size(), 3u + 300u);
  EXPECT_EQ(bytes[0], 1);
  EXPECT_EQ(bytes[1], 0xAB);
  EXPECT_EQ(bytes[2], 0x02);
  const auto back = decode(bytes, 301, NeighborListMode::kUpper);
  EXPECT_EQ(back.offsets, offsets);
  EXPECT_EQ(back.neighbors, neighbors);
}

// A random symmetric graph: each point linked to points within `span` indices, plus a few far.
NeighborLists random_graph(uint32_t n, uint32_t span, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::set<uint32_t>> rows(n);
  for (uint32_t i = 0; i < n; ++i) {
    for (int e = 0; e < 6; ++e) {
      uint32_t j = (rng() % 50 == 0) ? rng() % n : i + 1 + rng() % span;
      if (j >= n || j == i) continue;
      rows[i].insert(j);
      rows[j].insert(i);
    }
  }
  NeighborLists g;
  g.offsets.push_back(0);
  for (const auto& r : rows) {
    g.neighbors.insert(g.neighbors.end(), r.begin(), r.end());
    g.offsets.push_back(g.neighbors.size());
  }
  return g;
}

// A graph of n rows, each linked to its two neighbours on either side and, past 6 rows, row
// i < n/2 to i + n/2 (rows of up to 5 ascending entries, some deltas of several bytes).
NeighborLists lattice(uint32_t n) {
  NeighborLists g;
  g.offsets.push_back(0);
  const uint32_t half = n > 6 ? n / 2 : n;
  for (uint32_t i = 0; i < n; ++i) {
    if (i >= half) g.neighbors.push_back(i - half);
    for (uint32_t j = i >= 2 ? i - 2 : 0; j <= i + 2 && j < n; ++j)
      if (j != i) g.neighbors.push_back(j);
    if (i + half < n) g.neighbors.push_back(i + half);
    g.offsets.push_back(g.neighbors.size());
  }
  return g;
}

// The encoder that releases the rows it has coded writes the same bytes, over several of its
// windows of rows, after what `out` held, and leaves the rows empty.
TEST(GraphNeighborListCodec, ReleasingEncoderWritesTheSameBytes) {
  for (uint32_t n : {0u, 1u, 5u, 600001u}) {
    const NeighborLists g = lattice(n);
    for (auto mode : {NeighborListMode::kFull, NeighborListMode::kUpper}) {
      std::vector<uint8_t> expected{7, 7};
      const std::vector<uint8_t> bytes = encode_neighbor_lists(g.offsets, g.neighbors, mode);
      expected.insert(expected.end(), bytes.begin(), bytes.end());
      std::vector<uint32_t> rows = g.neighbors;
      std::vector<uint8_t> out{7, 7};
      append_neighbor_lists(g.offsets, std::move(rows), mode, out, 3);
      EXPECT_TRUE(rows.empty());
      EXPECT_EQ(out, expected) << n;
      EXPECT_GE(out.capacity(), out.size() + 3);
      EXPECT_EQ(decode(bytes, n, mode).neighbors, g.neighbors) << n;
    }
  }
}

TEST(GraphNeighborListCodec, RoundTripsRandomGraphs) {
  for (uint32_t n : {1u, 2u, 17u, 1000u, 70000u}) {
    const auto g = random_graph(n, 40, n);
    for (auto mode : {NeighborListMode::kFull, NeighborListMode::kUpper}) {
      const auto bytes = encode_neighbor_lists(g.offsets, g.neighbors, mode);
      const auto back = decode(bytes, n, mode);
      EXPECT_EQ(back.offsets, g.offsets) << n;
      EXPECT_EQ(back.neighbors, g.neighbors) << n;
    }
  }
  // Upper mode stores each edge once: well under 2 bytes per undirected edge here.
  const auto g = random_graph(70000, 40, 5);
  const auto bytes = encode_neighbor_lists(g.offsets, g.neighbors, NeighborListMode::kUpper);
  EXPECT_LT(double(bytes.size()) / (g.neighbors.size() / 2.0), 2.0);
}

// Upper mode with a byte per stored entry: each byte lands at both ends of its edge, and a
// stream with another number of entries leaves the values empty.
TEST(GraphNeighborListCodec, UpperValuesAreMirroredWithTheirEdges) {
  for (uint32_t n : {1u, 17u, 1000u, 70000u}) {
    const auto g = random_graph(n, 40, n + 1);
    const auto bytes = encode_neighbor_lists(g.offsets, g.neighbors, NeighborListMode::kUpper);
    // The value of edge (i, j) is a function of both ends, the same whichever end stores it.
    auto value_of = [](uint64_t i, uint64_t j) {
      return uint8_t((std::min(i, j) * 7 + std::max(i, j) * 13) % 251);
    };
    std::vector<uint8_t> stored;
    for (uint64_t i = 0; i < n; ++i)
      for (uint64_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k)
        if (g.neighbors[k] > i) stored.push_back(value_of(i, g.neighbors[k]));
    std::vector<uint8_t> values;
    const auto back =
        decode_neighbor_lists(bytes, n, NeighborListMode::kUpper, "g.splk", stored, &values);
    ASSERT_EQ(back.neighbors, g.neighbors) << n;
    ASSERT_EQ(values.size(), g.neighbors.size()) << n;
    for (uint64_t i = 0; i < n; ++i)
      for (uint64_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k)
        ASSERT_EQ(values[k], value_of(i, g.neighbors[k])) << n << ": row " << i << " entry " << k;
    if (stored.empty()) continue;
    stored.pop_back();
    decode_neighbor_lists(bytes, n, NeighborListMode::kUpper, "g.splk", stored, &values);
    EXPECT_TRUE(values.empty()) << n;
  }
}

// The upper-mode decoder runs over tasks of rows in parallel and places the mirrored entries as
// they come: every thread count gives the original rows and values, here with hubs (rows of
// thousands of entries, stored by many tasks) beside a random graph over many tasks.
TEST(GraphNeighborListCodec, UpperDecodeIsTheSameOnAnyThreadCount) {
  const uint32_t n = 120000;
  NeighborLists g = random_graph(n, 40, 3);
  std::vector<std::set<uint32_t>> rows(n);
  for (uint32_t i = 0; i < n; ++i)
    rows[i].insert(g.neighbors.begin() + g.offsets[i], g.neighbors.begin() + g.offsets[i + 1]);
  for (uint32_t hub : {0u, 777u, n - 1}) {
    for (uint32_t j = 5; j < n; j += 11) {
      if (j == hub) continue;
      rows[hub].insert(j);
      rows[j].insert(hub);
    }
  }
  g = {};
  g.offsets.push_back(0);
  for (const auto& r : rows) {
    g.neighbors.insert(g.neighbors.end(), r.begin(), r.end());
    g.offsets.push_back(g.neighbors.size());
  }
  ASSERT_GT(g.offsets[778] - g.offsets[777], 10000u);
  const auto bytes = encode_neighbor_lists(g.offsets, g.neighbors, NeighborListMode::kUpper);
  std::vector<uint8_t> stored;
  for (uint64_t i = 0; i < n; ++i)
    for (uint64_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k)
      if (g.neighbors[k] > i) stored.push_back(uint8_t((i * 31 + g.neighbors[k]) % 253));
  for (int threads : {1, 2, 5}) {
    std::vector<uint8_t> values;
    const NeighborLists back = tbb::task_arena(threads).execute([&] {
      return decode_neighbor_lists(bytes, n, NeighborListMode::kUpper, "g.splk", stored, &values);
    });
    ASSERT_EQ(back.offsets, g.offsets) << threads;
    ASSERT_EQ(back.neighbors, g.neighbors) << threads;
    ASSERT_EQ(values.size(), g.neighbors.size()) << threads;
    for (uint64_t i = 0; i < n; ++i)
      for (uint64_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k) {
        const uint64_t a = std::min<uint64_t>(i, g.neighbors[k]), b = std::max<uint64_t>(i, g.neighbors[k]);
        ASSERT_EQ(values[k], uint8_t((a * 31 + b) % 253)) << threads << ": row " << i;
      }
  }
}

TEST(GraphNeighborListCodec, EmptyGraphs) {
  EXPECT_TRUE(encode_neighbor_lists(std::vector<uint64_t>{0}, {}, NeighborListMode::kFull).empty());
  EXPECT_TRUE(decode({}, 0, NeighborListMode::kFull).neighbors.empty());
  const std::vector<uint64_t> three{0, 0, 0, 0};
  const auto bytes = encode_neighbor_lists(three, {}, NeighborListMode::kUpper);
  EXPECT_EQ(bytes, (std::vector<uint8_t>{0, 0, 0}));
  EXPECT_EQ(decode(bytes, 3, NeighborListMode::kUpper).offsets, three);
}

TEST(GraphNeighborListCodec, HostileInputsEachHaveTheirOwnMessage) {
  using M = NeighborListMode;
  EXPECT_NE(error_of({1}, 2).find("2 rows cannot fit in 1 bytes"), std::string::npos);
  EXPECT_NE(error_of({0x80}, 1).find("row 0: byte 0: truncated varint"), std::string::npos);
  EXPECT_NE(error_of({1, 0x80}, 1).find("byte 1: truncated varint"), std::string::npos);
  const std::vector<uint8_t> too_long{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02};
  EXPECT_NE(error_of(too_long, 1).find("overflows 64 bits"), std::string::npos);
  EXPECT_NE(error_of({0x80, 0x00}, 1).find("not in shortest form"), std::string::npos);
  EXPECT_NE(error_of({5, 2, 0}, 3).find("degree 5 exceeds the 2 bytes left"), std::string::npos);
  // Row 0 of 4: zigzag 16 = +8, out of range.
  EXPECT_NE(error_of({1, 16, 0, 0, 0}, 4).find("neighbour index 8 out of range (rows: 4)"),
            std::string::npos);
  // Row 1: zigzag 3 = -2: below 0.
  EXPECT_NE(error_of({0, 1, 3}, 3).find("row 1: byte 2: neighbour index overflow"),
            std::string::npos);
  EXPECT_NE(error_of({1, 0, 0}, 2).find("row lists its own index"), std::string::npos);
  // Found by fuzzing: row 1 = {0, 1}, its own index as a later entry.
  EXPECT_NE(error_of({2, 2, 1, 2, 1, 0, 1, 2, 1, 5}, 4).find("row 1: byte 5: row lists its own"),
            std::string::npos);
  // A gap of 2^64 - 1 after index 1 would wrap back to 1: must be out of range, not a repeat.
  const std::vector<uint8_t> wrap{2,    2,    0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                  0xFF, 0xFF, 0xFF, 0x01, 0,    0,    0};
  EXPECT_NE(error_of(wrap, 4).find("row 0: byte 2: neighbour index overflow"), std::string::npos);
  EXPECT_NE(error_of({0, 0, 7}, 2).find("byte 2: 1 trailing bytes after the last row"),
            std::string::npos);
  EXPECT_NE(error_of({1, 3, 0, 0}, 4, M::kUpper).find("neighbour index 4 out of range"),
            std::string::npos);
  EXPECT_NE(error_of({0}, 1, static_cast<M>(9)).find("unknown neighbour list mode 9"),
            std::string::npos);
  // Every message names the file.
  EXPECT_EQ(error_of({0x80}, 1).rfind("g.splk: ", 0), 0u);
}

TEST(GraphNeighborListCodec, EncoderRejectsBrokenLayouts) {
  using M = NeighborListMode;
  auto bad = [](std::vector<uint64_t> o, std::vector<uint32_t> n) {
    EXPECT_THROW(encode_neighbor_lists(o, n, M::kFull), std::invalid_argument);
  };
  bad({}, {});                // no offsets
  bad({1, 1}, {0});           // not starting at 0
  bad({0, 1}, {0});           // own index
  bad({0, 2, 2}, {1, 1});     // duplicate
  bad({0, 2, 2, 2}, {2, 1});  // descending
  bad({0, 1, 1}, {2});        // out of range
  bad({0, 1, 2}, {1});        // does not end at the neighbour count
}

}  // namespace
}  // namespace splatkit::graph
