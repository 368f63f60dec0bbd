// Void filling for streamed heightmaps, in two steps after the method of GDAL's FillNodata:
//  1. every void sample takes the inverse-distance-weighted mean of the nearest good samples in
//     its row (left, right) and column (above, and below within a look-ahead of rows): a convex
//     combination, so a filled sample never lies outside the heights around the void;
//  2. `smoothing` passes of a 3×3 mean over the filled samples only (good samples never change)
//     take out the row-to-row steps of step 1, so that a void never becomes a ridge or a cliff
//     in the second derivatives (the HAM) that follow.
// Samples within kEdge of a void are treated as voids too: SRTM's void edges carry outliers.
// Rows go out one at a time, `smoothing` rows behind the input; memory holds the look-ahead.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "terrain/heightmap_source.h"

namespace splatkit::terrain {

// Whether `v` is a void: not finite, or equal to `nodata` when has_nodata.
inline bool is_void(float v, bool has_nodata, float nodata) {
  return !(v - v == 0.0f) || (has_nodata && v == nodata);
}

// Fills the voids of one row from the row alone (each run becomes the straight line between
// its neighbours, or their value at the row's ends); returns how many there were, or `width`
// (nothing changed) when the row has no valid sample.
int64_t fill_row_voids(float* row, int64_t width, bool has_nodata, float nodata);

// The look-ahead build-ham uses for a map `width` texels wide: 256 rows, fewer for rows wider
// than 12 K texels (about 16 MiB of rows and flags), at least 16.
inline int64_t default_lookahead(int64_t width) {
  const int64_t rows = (int64_t(16) << 20) / (width > 0 ? width * 5 : 1);
  return rows < 16 ? 16 : rows > 256 ? 256 : rows;
}

class VoidFiller {
 public:
  static constexpr int kSmoothing = 32;
  static constexpr int64_t kEdge = 1;  // samples this close to a void (Chebyshev) are replaced
  // `lookahead`: rows searched below a void (voids taller than it are filled without the samples
  // below them until their end comes into reach).
  VoidFiller(HeightmapSource& source, bool has_nodata, float nodata, int64_t lookahead,
             int smoothing = kSmoothing);
  // Writes the next row, filled, into `out` (width floats) and returns its number of no-data
  // samples; mask() then flags them (1 = no-data). Samples with no good neighbour in their row or
  // column within reach take the filled row above, or at the top the mean of the valid samples
  // of the rows in reach (0 when there is none: a map that starts with more void rows than the
  // look-ahead).
  int64_t next(float* out);
  const std::vector<uint8_t>& mask() const { return mask_; }
  // The samples of that row that were replaced (voids and void edges: 1), valid when
  // any_replaced(); compute_ham bounds the HAM of the texels that depend on them.
  const std::vector<uint8_t>& replaced() const { return replaced_; }
  bool any_replaced() const { return any_replaced_; }
  uint64_t edge_samples() const { return edge_samples_; }  // good samples replaced beside voids

 private:
  using Row = std::shared_ptr<const std::vector<float>>;
  struct Staged {
    int64_t y;
    Row values;  // null: the row had no void within kEdge and is read from the ring
    std::shared_ptr<const std::vector<uint8_t>> filled;  // 1 = replaced (void or void edge)
    int64_t voids;                                       // no-data samples (before erosion)
    std::shared_ptr<const std::vector<uint8_t>> nodata;
  };
  int64_t slot(int64_t y) const { return y % capacity_; }
  float* row(int64_t y) { return rows_.data() + slot(y) * width_; }
  const float* row(int64_t y) const { return rows_.data() + slot(y) * width_; }
  const float* values(const Staged& s) const;
  void load_more();
  int good(int64_t y, int64_t x) const;  // 1 good, 0 void or beside one, 2 not yet known
  float mean_in_reach(int64_t r);         // of the valid samples of rows r to the last loaded
  Staged fill_next();                     // step 1 for the next input row
  void push(int pass, Staged staged);     // step 2, pass by pass

  HeightmapSource& source_;
  bool has_nodata_;
  float nodata_;
  int64_t width_, height_, band_, lookahead_, capacity_ = 0;
  int smoothing_;
  int64_t loaded_ = 0, row_ = 0;     // rows read so far; next input row
  std::vector<float> rows_;          // ring of original rows (capacity_ rows)
  std::vector<uint8_t> voids_;       // their no-data flags
  std::vector<int64_t> counts_;      // no-data samples per ring row
  std::vector<double> sums_;         // and the sum of its valid samples (mean_in_reach),
  std::vector<uint8_t> summed_;      // once that is computed
  std::vector<float> up_val_;        // last good sample above, per column
  std::vector<int64_t> up_row_, down_row_, down_scanned_;
  std::vector<int64_t> left_, right_;
  int64_t last_clean_ = -1;          // the last row kept as it is
  Row prev_filled_;                  // the last step-1 row that was filled
  std::vector<std::deque<Staged>> passes_;  // the last rows of each smoothing pass
  std::deque<Staged> ready_;
  std::vector<uint8_t> mask_, near_, replaced_;
  bool had_mask_ = true, any_replaced_ = false;
  uint64_t edge_samples_ = 0;
};

}  // namespace splatkit::terrain
