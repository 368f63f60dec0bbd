// Candidates: the small splats that can overlap a small splat of one grid cell, copied together,
// and the tests of the cell's splats against them — sphere_overlap_graph's inner loop.
//
// A cell's candidates are the small splats of the 27 surrounding cells whose distance to the
// bounding box of the cell's small splats is below r_cell + r_q (r_cell their largest radius).
// For a splat p of the cell every splat left out has d² >= (r_p + r_q)²: float subtraction,
// squares and sums are monotonic, so the box distance computed like the pair's distance is never
// larger. Padded with NaN coordinates (never a hit) to a multiple of 16.
//
// Three paths, bit for bit the same answers (the same float operations lane by lane): portable
// (overlap_candidates.cpp, the one to read), AVX2 (8 candidates at a time, rows sorted by
// ranking, overlap_candidates_avx2.cpp) and AVX-512 (16 at a time, rows of up to 16 compressed
// and sorted in one register, overlap_candidates_avx512.cpp); `simd` picks one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "graph/overlap_grid.h"
#include "splatkit/simd_level.h"

namespace splatkit::graph::overlap {

// Rows up to this long are sorted by ranking (quadratic, branch-free), longer ones by std::sort.
constexpr uint32_t kRankLimit = 64;

struct Candidates {
  std::vector<float> x, y, z, r;
  std::vector<float> nx, ny, nz;  // with sharp edges: the normals
  std::vector<uint32_t> id;
  std::vector<uint32_t> hits;       // one row before sorting
  std::vector<uint32_t> sorted;     // the row sorted (16 spare slots)
  std::vector<uint32_t> sharp_ids;  // the row's sharp neighbours, in no order (with sharp edges)
  SimdLevel simd = SimdLevel::kPortable;  // the vector code in use (AVX2, AVX-512 or none)
  bool sharp = false;                     // find the sharp edges (the sorted splats have normals)
  float threshold = 0;                    // an edge is sharp iff !(n_i·n_j >= threshold)
  uint32_t size = 0;

  // Collects cell c's candidates from the splats of `runs` (its 27 cells); false when the cell
  // has no small splat.
  bool gather(const Sorted& s, std::size_t c, const Runs& runs);

  // The neighbours of small splat p (sorted position) among the candidates, ascending; with
  // sharp edges, the sharp ones also in sharp_ids.
  std::span<const uint32_t> row(const Sorted& s, uint32_t p);

  // The number of neighbours of small splat p (sorted position) among the candidates.
  uint32_t count(const Sorted& s, uint32_t p);

 private:
  // kRow: the hits in `hits` (and the sharp ones in sharp_ids); else only their number.
  template <bool kRow>
  uint32_t hits_portable(const Sorted& s, uint32_t p);
  // Appends to sharp_ids the ids of candidates j + l for the bits l of `lanes`.
  void add_sharp(unsigned lanes, std::size_t j);

#if defined(__x86_64__)
  // gather's copy and test, eight splats at a time (the arrays are padded; lanes past a run's
  // end are masked off).
  __attribute__((target("avx2"))) uint32_t copy_avx2(const Sorted& s, const Runs& runs,
                                                     const float lo[3], const float hi[3],
                                                     float r_cell);
  // hits_portable eight candidates at a time, the hits packed into `hits`.
  template <bool kRow>
  __attribute__((target("avx2"))) uint32_t hits_avx2(const Sorted& s, uint32_t p);
  // hits[0, m) ascending, in `sorted` (rank_sort_avx2).
  __attribute__((target("avx2"))) std::span<const uint32_t> sorted_avx2(uint32_t m);

  // gather's copy and test, sixteen splats at a time.
  __attribute__((target("avx512f"))) uint32_t copy_avx512(const Sorted& s, const Runs& runs,
                                                          const float lo[3], const float hi[3],
                                                          float r_cell);
  // The number of hits of p, sixteen candidates at a time (row_avx512's test).
  __attribute__((target("avx512f"))) uint32_t count_avx512(const Sorted& s, uint32_t p);
  // The hits of p ascending in `sorted` (16 slots written); the count, or 17 when p has more
  // than 16 hits (then `sorted` holds nothing useful).
  __attribute__((target("avx512f"))) uint32_t row_avx512(const Sorted& s, uint32_t p);
#endif
};

}  // namespace splatkit::graph::overlap
