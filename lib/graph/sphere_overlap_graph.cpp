#include "graph/sphere_overlap_graph.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/overlap_big_splats.h"
#include "graph/overlap_candidates.h"
#include "graph/overlap_grid.h"
#include "graph/release_pages.h"
#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit::graph {
namespace {

using namespace overlap;

constexpr std::size_t kCellBlock = 1024;  // cells per task
// Splats ahead (in cell order) whose row offset is prefetched: the rows are far apart in memory.
constexpr std::size_t kAhead = 16;
// A grid whose cells hold more than this many cell-mates per splat on average (sum of the
// squared cell sizes over the splat count) is left to the kd-tree.
constexpr uint64_t kMaxCellMates = 1024;

void check(std::span<const Vec3f> positions, std::span<const float> radii) {
  if (radii.size() != positions.size())
    throw std::invalid_argument("sphere_overlap_graph: need one radius per position");
  if (positions.size() > std::size_t{0xFFFFFFFEu})
    throw std::invalid_argument("sphere_overlap_graph: more than 2^32 - 2 splats");
  auto bad = [&](std::size_t i) {
    const Vec3f& p = positions[i];
    return !(radii[i] >= 0) || !std::isfinite(radii[i]) || !std::isfinite(p.x) ||
           !std::isfinite(p.y) || !std::isfinite(p.z);
  };
  // The first bad splat, found in parallel chunks (the same one for any thread count).
  const std::size_t n = positions.size(), chunks = chunk_count(n, kChunk);
  std::vector<std::size_t> first_bad(chunks, n);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (bad(i)) {
        first_bad[c] = i;
        return;
      }
  });
  std::size_t i = n;
  for (std::size_t f : first_bad) i = std::min(i, f);
  if (i == n) return;
  if (!(radii[i] >= 0) || !std::isfinite(radii[i]))
    throw std::invalid_argument("sphere_overlap_graph: radii must be finite and >= 0");
  throw Error(ErrorKind::kBadInput, "splat " + std::to_string(i) + " has a non-finite coordinate");
}

// Whether the cells are so full that each splat would test more candidates than the kd-tree
// visits: a bulk wider than 2^21 cells, or far clusters too large for the grid's box to leave
// out (overlap_grid.h), put thousands of splats into one cell.
bool crowded(const Sorted& s) {
  uint64_t mates = 0;
  for (std::size_t c = 0; c + 1 < s.cell_start.size(); ++c) {
    const uint64_t count = s.cell_start[c + 1] - s.cell_start[c];
    mates += count * count;
  }
  return mates > kMaxCellMates * s.n;
}

// offsets[i] += offsets[i - 1] for all i, in parallel over fixed chunks (the same sums for any
// thread count: integer addition).
void prefix_sum(std::vector<uint64_t>& v) {
  const std::size_t chunks = chunk_count(v.size(), kChunk);
  std::vector<uint64_t> carry(chunks + 1, 0);
  for_each_chunk(v.size(), kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    uint64_t sum = 0;
    for (std::size_t i = begin; i < end; ++i) sum += v[i];
    carry[c + 1] = sum;
  });
  for (std::size_t c = 0; c < chunks; ++c) carry[c + 1] += carry[c];
  for_each_chunk(v.size(), kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    uint64_t sum = carry[c];
    for (std::size_t i = begin; i < end; ++i) v[i] = sum += v[i];
  });
}

// Writes row `id`: its small neighbours `base` merged with its entries in `pairs`.
void write_row(uint32_t id, std::span<const uint32_t> base, std::size_t extra,
               const std::vector<uint64_t>& pairs, uint32_t* out) {
  if (extra == 0) {
    for (uint32_t v : base) *out++ = v;  // rows are short: no memmove call
    return;
  }
  auto e = std::lower_bound(pairs.begin(), pairs.end(), uint64_t{id} << 32);
  auto b = base.begin();
  for (std::size_t left = extra; left > 0 || b != base.end();) {
    if (left > 0 && (b == base.end() || uint32_t(*e) < *b)) {
      *out++ = uint32_t(*e++);
      --left;
    } else {
      *out++ = *b++;
    }
  }
}

// One edge flag per entry of row i, set where the edge is sharp (normals from the caller, in
// original order): for the rows the grid does not find by itself. Returns whether any is.
bool mark_sharp_row(uint32_t i, std::span<const uint32_t> row, const SharpEdges& sharp,
                    uint8_t* flags) {
  bool any = false;
  for (std::size_t k = 0; k < row.size(); ++k) {
    const bool is_sharp = !(dot(sharp.normals[i], sharp.normals[row[k]]) >= sharp.threshold);
    flags[k] = is_sharp ? sharp.flag : 0;
    any = any || is_sharp;
  }
  return any;
}

// Per-chunk lists of rows (any order of chunks) joined, ascending.
std::vector<uint32_t> joined(const std::vector<std::vector<uint32_t>>& chunk_rows) {
  std::vector<uint32_t> rows;
  for (const auto& r : chunk_rows) rows.insert(rows.end(), r.begin(), r.end());
  std::sort(rows.begin(), rows.end());
  return rows;
}

void join_rows(const std::vector<std::vector<uint32_t>>& chunk_rows, SharpEdgeMarks& marks) {
  marks.rows = joined(chunk_rows);
}

void mark_sharp_rows(const NeighborGraph& graph, const SharpEdges& sharp, SharpEdgeMarks& marks) {
  const std::size_t n = graph.num_points(), chunk = kChunk / 16;
  marks.flags.assign(graph.neighbors.size(), 0);
  std::vector<std::vector<uint32_t>> rows(chunk_count(n, chunk));
  for_each_chunk(n, chunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (mark_sharp_row(uint32_t(i), graph.row(i), sharp, marks.flags.data() + graph.offsets[i]))
        rows[c].push_back(uint32_t(i));
  });
  join_rows(rows, marks);
}

// The sharp entries found while the rows are written, one bit per entry (set with an atomic OR:
// rows of different tasks share words), and the rows merged with big splats' pairs, which are
// marked afterwards from the normals in splat order (they may be lent out meanwhile).
struct SharpFound {
  std::vector<uint64_t> bits;
  std::vector<uint32_t> rows;    // rows with a sharp entry among the bits
  std::vector<uint32_t> merged;  // rows to mark afterwards
};

// The graph in two passes over the cells, so that no rows are stored twice: the row lengths
// (small neighbours plus the big splats' pairs) give the offsets, then each row is found again
// and written in place, merged with its pairs. With `sharp`, `found` gets the marks as the rows
// are written.
// The most row entries a graph of n splats may have: a mean of 1024 neighbours per splat (ten
// times more than splats sized to their neighbourhood have, and more memory than such a cloud of
// a few million splats could fill).
std::size_t max_entries(std::size_t n) { return 1024 * n + (std::size_t{1} << 20); }

NeighborGraph small_rows(const Sorted& s, const Grid& g, const std::vector<uint64_t>& pairs,
                         SimdLevel simd, const SharpEdges* sharp, SharpFound* found) {
  const std::size_t n = s.n;
  const float R = s.small_radius;
  const std::size_t cells = s.cell_key.size(), blocks = (cells + kCellBlock - 1) / kCellBlock;
  // fn(b, c0, c1, candidates) for the blocks of cells, in parallel; the candidates carry the
  // normals when with_normals.
  auto for_each_block = [&](bool with_normals, auto&& fn) {
    tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
      Candidates cand;
      cand.simd = simd;
      cand.sharp = with_normals;
      cand.threshold = sharp ? sharp->threshold : 0;
      fn(b, b * kCellBlock, std::min(cells, (b + 1) * kCellBlock), cand);
    });
  };
  NeighborGraph graph;
  sized_in_parallel(graph.offsets, n + 1);
  graph.offsets[0] = 0;
  for_each_block(false, [&](std::size_t, std::size_t c0, std::size_t c1, Candidates& cand) {
    for_each_cell(s, g, c0, c1, [&](std::size_t c, const Runs& runs) {
      const bool any = cand.gather(s, c, runs);
      for (uint32_t p = s.cell_start[c]; p < s.cell_start[c + 1]; ++p) {
        __builtin_prefetch(&graph.offsets[s.id[std::min<std::size_t>(p + kAhead, n - 1)]], 1);
        graph.offsets[std::size_t{s.id[p]} + 1] = any && s.r[p] <= R ? cand.count(s, p) : 0;
      }
    });
  });
  for (uint64_t pair : pairs) ++graph.offsets[(pair >> 32) + 1];
  prefix_sum(graph.offsets);
  if (graph.offsets[n] > max_entries(n))
    throw_too_many_overlaps(max_entries(n), n, *std::max_element(s.r.begin(), s.r.end()));
  sized_in_parallel(graph.neighbors, graph.offsets[n]);
  uint64_t* bits = nullptr;
  if (found) {
    sized_in_parallel(found->bits, (graph.offsets[n] + 63) / 64);
    bits = found->bits.data();
  }
  std::vector<std::vector<uint32_t>> sharp_rows(blocks), merged_rows(blocks);
  for_each_block(
      sharp != nullptr, [&](std::size_t b, std::size_t c0, std::size_t c1, Candidates& cand) {
        for_each_cell(s, g, c0, c1, [&](std::size_t c, const Runs& runs) {
          const bool any = cand.gather(s, c, runs);
          for (uint32_t p = s.cell_start[c]; p < s.cell_start[c + 1]; ++p) {
            __builtin_prefetch(&graph.offsets[s.id[std::min<std::size_t>(p + kAhead, n - 1)]]);
            const uint64_t soon = graph.offsets[s.id[std::min<std::size_t>(p + kAhead / 4, n - 1)]];
            __builtin_prefetch(graph.neighbors.data() + soon, 1);
            const uint32_t id = s.id[p];
            const uint64_t at = graph.offsets[id], length = graph.offsets[std::size_t{id} + 1] - at;
            std::span<const uint32_t> row;
            if (any && s.r[p] <= R)
              row = cand.row(s, p);  // (and its sharp ids)
            else
              cand.sharp_ids.clear();
            // Both passes test with the same float operations; a row that grew would overrun.
            if (row.size() > length)
              throw std::logic_error("sphere_overlap_graph: a row differs between the passes");
            uint32_t* out = graph.neighbors.data() + at;
            write_row(id, row, length - row.size(), pairs, out);
            if (!bits) continue;
            if (length != row.size()) {  // merged with pairs: marked afterwards
              merged_rows[b].push_back(id);
              continue;
            }
            for (uint32_t j : cand.sharp_ids) {  // (always in the row: found by the same test)
              const uint64_t e =
                  at + uint64_t(std::lower_bound(row.begin(), row.end(), j) - row.begin());
              std::atomic_ref<uint64_t>(bits[e / 64])
                  .fetch_or(uint64_t{1} << (e % 64), std::memory_order_relaxed);
            }
            if (!cand.sharp_ids.empty()) sharp_rows[b].push_back(id);
          }
        });
      });
  if (found) {
    found->rows = joined(sharp_rows);
    found->merged = joined(merged_rows);
  }
  return graph;
}

// The flags from the bits, then the merged rows marked from the normals in splat order.
void expand_marks(const NeighborGraph& graph, SharpFound& found, const SharpEdges& sharp,
                  SharpEdgeMarks& marks) {
  const std::size_t entries = graph.neighbors.size();
  marks.flags.clear();
  sized_in_parallel(marks.flags, entries);
  // Eight entries at a time: each byte of the bits spread to eight bytes of 0 or 1 (a table whose
  // entry holds bit k in its k-th byte in memory), times the flag (no carries: flag <= 255).
  // Chunks start at multiples of 64.
  static_assert(kChunk % 64 == 0);
  static const std::array<uint64_t, 256> spread = [] {
    std::array<uint64_t, 256> t{};
    for (unsigned b = 0; b < 256; ++b) {
      uint8_t bytes[8];
      for (unsigned k = 0; k < 8; ++k) bytes[k] = uint8_t((b >> k) & 1);
      std::memcpy(&t[b], bytes, 8);
    }
    return t;
  }();
  const uint64_t times = sharp.flag;
  for_each_chunk(entries, kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
    std::size_t e = begin;
    for (; e + 8 <= end; e += 8) {
      const uint64_t v = spread[(found.bits[e / 64] >> (e % 64)) & 0xFF] * times;
      std::memcpy(marks.flags.data() + e, &v, 8);
    }
    for (; e < end; ++e) marks.flags[e] = (found.bits[e / 64] >> (e % 64)) & 1 ? sharp.flag : 0;
  });
  std::vector<uint64_t>().swap(found.bits);
  marks.rows = std::move(found.rows);
  for (uint32_t i : found.merged)
    if (mark_sharp_row(i, graph.row(i), sharp, marks.flags.data() + graph.offsets[i]))
      marks.rows.push_back(i);
  std::sort(marks.rows.begin(), marks.rows.end());
}

// The lent arrays filled again from the sorted copy (the same floats), which is released as it
// is read: each sorted array's pages are handed back block by block, then the array is freed.
// One array at a time, so that besides the copy at most one new array is held.
void give_back(Sorted& s, LentSplats& lent) {
  std::vector<uint64_t>().swap(s.cell_key);
  std::vector<uint32_t>().swap(s.cell_start);
  const std::size_t n = s.n;
  auto refill = [&](auto& out, std::initializer_list<std::vector<float>*> from, auto&& value) {
    sized_in_parallel(out, n);
    for_each_chunk(n, kChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) out[s.id[k]] = value(k);
      for (std::vector<float>* v : from) release_pages(v->data() + begin, v->data() + end);
    });
    for (std::vector<float>* v : from) std::vector<float>().swap(*v);
  };
  refill(lent.radii, {&s.r}, [&](std::size_t k) { return s.r[k]; });
  refill(lent.normals, {&s.nx, &s.ny, &s.nz}, [&](std::size_t k) {
    return Vec3f{s.nx[k], s.ny[k], s.nz[k]};
  });
  refill(lent.positions, {&s.x, &s.y, &s.z}, [&](std::size_t k) {
    return Vec3f{s.x[k], s.y[k], s.z[k]};
  });
}

NeighborGraph overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                            SimdLevel limit, const SharpEdges* sharp, SharpEdgeMarks* marks,
                            LentSplats* lent = nullptr) {
  const SimdLevel level = std::min(limit, simd_level());
  check(positions, radii);
  const std::size_t n = positions.size();
  // Graphs the grid does not build get their flags afterwards, from the caller's normals.
  auto marked = [&](NeighborGraph graph) {
    if (sharp) mark_sharp_rows(graph, *sharp, *marks);
    return graph;
  };
  if (n == 0) return marked(NeighborGraph{{0}, {}});
  const float r_small = small_radius(radii);
  if (!(r_small > 0)) {
    // All radii 0: (0 + 0)² is never > d². Otherwise almost all are 0 and a grid has no scale.
    if (*std::max_element(radii.begin(), radii.end()) == 0)
      return marked(NeighborGraph{std::vector<uint64_t>(n + 1, 0), {}});
    return marked(SpatialIndex(positions).sphere_overlaps(radii, max_entries(n)));
  }
  const Grid g = make_grid(positions, r_small, level == SimdLevel::kAvx512);
  Sorted s =
      sort_by_cell(positions, radii, sharp ? sharp->normals : std::span<const Vec3f>{}, g, r_small);
  std::vector<uint64_t> pairs;
  if (crowded(s) || !big_pairs(s, g, pairs))
    return marked(SpatialIndex(positions).sphere_overlaps(radii, max_entries(n)));
  SharpFound found;
  NeighborGraph graph;
  if (!lent) {
    graph = small_rows(s, g, pairs, level, sharp, sharp ? &found : nullptr);
  } else {
    // From here on the rows need only the sorted copy (positions, radii and normals dangle).
    std::vector<Vec3f>().swap(lent->positions);
    std::vector<float>().swap(lent->radii);
    std::vector<Vec3f>().swap(lent->normals);
    try {
      graph = small_rows(s, g, pairs, level, sharp, sharp ? &found : nullptr);
    } catch (...) {
      give_back(s, *lent);
      throw;
    }
    give_back(s, *lent);
  }
  if (sharp) {
    const SharpEdges now = lent ? SharpEdges{lent->normals, sharp->threshold, sharp->flag} : *sharp;
    expand_marks(graph, found, now, *marks);
  }
  return graph;
}

}  // namespace

NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                                   SimdLevel limit) {
  return overlap_graph(positions, radii, limit, nullptr, nullptr);
}

NeighborGraph sphere_overlap_graph(std::span<const Vec3f> positions, std::span<const float> radii,
                                   const SharpEdges& sharp, SharpEdgeMarks& marks,
                                   SimdLevel limit) {
  if (sharp.normals.size() != positions.size())
    throw std::invalid_argument("sphere_overlap_graph: need one normal per position");
  return overlap_graph(positions, radii, limit, &sharp, &marks);
}

NeighborGraph sphere_overlap_graph(LentSplats splats, float sharp_threshold, uint8_t flag,
                                   SharpEdgeMarks& marks, SimdLevel limit) {
  if (splats.normals.size() != splats.positions.size())
    throw std::invalid_argument("sphere_overlap_graph: need one normal per position");
  const SharpEdges sharp{splats.normals, sharp_threshold, flag};
  return overlap_graph(splats.positions, splats.radii, limit, &sharp, &marks, &splats);
}

}  // namespace splatkit::graph
