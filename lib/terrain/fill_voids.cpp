#include "terrain/fill_voids.h"

#include <algorithm>
#include <cstdint>
#include <optional>

namespace splatkit::terrain {

int64_t fill_row_voids(float* row, int64_t width, bool has_nodata, float nodata) {
  int64_t voids = 0;
  int64_t last_valid = -1;  // index of the last valid sample seen
  int64_t x = 0;
  while (x < width) {
    if (!is_void(row[x], has_nodata, nodata)) {
      last_valid = x++;
      continue;
    }
    int64_t end = x;
    while (end < width && is_void(row[end], has_nodata, nodata)) ++end;
    voids += end - x;
    if (last_valid < 0 && end == width) return width;  // no valid sample in the row
    if (last_valid < 0) {
      for (int64_t i = x; i < end; ++i) row[i] = row[end];
    } else if (end == width) {
      for (int64_t i = x; i < end; ++i) row[i] = row[last_valid];
    } else {
      const double a = row[last_valid], b = row[end];
      const double span = double(end - last_valid);
      for (int64_t i = x; i < end; ++i)
        row[i] = float(a + (b - a) * (double(i - last_valid) / span));
    }
    x = end;
  }
  return voids;
}

}  // namespace splatkit::terrain

namespace splatkit::terrain {

VoidFiller::VoidFiller(HeightmapSource& source, bool has_nodata, float nodata, int64_t lookahead,
                       int smoothing)
    : source_(source),
      has_nodata_(has_nodata),
      nodata_(nodata),
      width_(source.info().width),
      height_(source.info().height),
      band_(std::max<int64_t>(1, source.info().band_rows)),
      lookahead_(std::max<int64_t>(lookahead, 2)),
      smoothing_(smoothing),
      passes_(std::size_t(smoothing)) {
  // Ring capacity: the look-ahead, a band being read, the rows still in the smoothing passes and
  // kEdge rows above; a multiple of the band so that a band never wraps.
  const int64_t need = lookahead_ + band_ + smoothing_ + kEdge + 4;
  capacity_ = (need + band_ - 1) / band_ * band_;
  const auto w = std::size_t(width_);
  rows_.resize(std::size_t(capacity_) * w);
  voids_.resize(rows_.size());
  counts_.assign(std::size_t(capacity_), 0);
  sums_.assign(std::size_t(capacity_), 0.0);
  summed_.assign(std::size_t(capacity_), 0);
  up_val_.assign(w, 0.0f);
  up_row_.assign(w, -1);
  down_row_.assign(w, -1);
  down_scanned_.assign(w, 0);
  mask_.assign(w, 0);
  left_.resize(w);
  right_.resize(w);
  near_.resize(w);
}

void VoidFiller::load_more() {
  const int64_t n = std::min(band_, height_ - loaded_);
  source_.read_rows(n, row(loaded_));
  const int64_t w = width_;
  for (int64_t y = loaded_; y < loaded_ + n; ++y) {
    const float* in = row(y);
    uint8_t* v = voids_.data() + slot(y) * w;
    int64_t count = 0;
    for (int64_t x = 0; x < w; ++x) {
      v[x] = is_void(in[x], has_nodata_, nodata_) ? 1 : 0;
      count += v[x];
    }
    counts_[std::size_t(slot(y))] = count;
    summed_[std::size_t(slot(y))] = 0;
  }
  loaded_ += n;
}

float VoidFiller::mean_in_reach(int64_t r) {
  double sum = 0;
  int64_t count = 0;
  for (int64_t y = r; y < loaded_; ++y) {
    const auto s = std::size_t(slot(y));
    if (!summed_[s]) {  // each row's sum once, and only for maps that need it (rare)
      const float* in = row(y);
      const uint8_t* v = voids_.data() + s * std::size_t(width_);
      double row_sum = 0;
      for (int64_t x = 0; x < width_; ++x) row_sum += v[x] ? 0.0 : double(in[x]);
      sums_[s] = row_sum;
      summed_[s] = 1;
    }
    sum += sums_[s];
    count += width_ - counts_[s];
  }
  return count > 0 ? float(sum / double(count)) : 0.0f;
}

int VoidFiller::good(int64_t y, int64_t x) const {
  if (y + kEdge >= loaded_ && loaded_ < height_) return 2;
  const int64_t w = width_;
  for (int64_t yy = std::max<int64_t>(0, y - kEdge); yy <= std::min(loaded_ - 1, y + kEdge); ++yy) {
    if (counts_[std::size_t(slot(yy))] == 0) continue;
    const uint8_t* v = voids_.data() + slot(yy) * w;
    for (int64_t xx = std::max<int64_t>(0, x - kEdge); xx <= std::min(w - 1, x + kEdge); ++xx)
      if (v[xx]) return 0;
  }
  return 1;
}

const float* VoidFiller::values(const Staged& s) const {
  return s.values ? s.values->data() : row(s.y);
}

VoidFiller::Staged VoidFiller::fill_next() {
  const int64_t w = width_, r = row_++;
  while (loaded_ < height_ && loaded_ <= r + lookahead_) load_more();
  const float* in = row(r);
  const uint8_t* v = voids_.data() + slot(r) * w;
  const int64_t voids = counts_[std::size_t(slot(r))];
  // Rows within kEdge of this one: their voids make samples of this row void edges.
  const int64_t y0 = std::max<int64_t>(0, r - kEdge), y1 = std::min(loaded_ - 1, r + kEdge);
  bool any = false;
  for (int64_t y = y0; y <= y1; ++y) any = any || counts_[std::size_t(slot(y))] > 0;
  if (!any) {  // no void within kEdge rows: the row is kept as it is (read from the ring)
    last_clean_ = r;
    return {r, nullptr, nullptr, 0, nullptr};
  }
  if (last_clean_ >= 0 && last_clean_ == r - 1) {  // the clean row above: the columns' last good
    std::copy(row(r - 1), row(r - 1) + w, up_val_.begin());
    std::fill(up_row_.begin(), up_row_.end(), r - 1);
  }
  std::fill(near_.begin(), near_.end(), 0);
  for (int64_t y = y0; y <= y1; ++y) {
    if (counts_[std::size_t(slot(y))] == 0) continue;
    const uint8_t* vy = voids_.data() + slot(y) * w;
    for (int64_t x = 0; x < w; ++x) near_[std::size_t(x)] |= vy[x];
  }
  auto filled = std::make_shared<std::vector<uint8_t>>(std::size_t(w));
  int64_t replaced = 0;
  for (int64_t x = 0; x < w; ++x) {
    bool bad = false;
    for (int64_t xx = std::max<int64_t>(0, x - kEdge); xx <= std::min(w - 1, x + kEdge); ++xx)
      bad = bad || near_[std::size_t(xx)];
    (*filled)[std::size_t(x)] = bad ? 1 : 0;
    replaced += bad;
  }
  const uint8_t* f = filled->data();
  edge_samples_ += uint64_t(replaced - voids);
  int64_t last = -1;
  for (int64_t x = 0; x < w; ++x) {
    if (!f[x]) last = x;
    left_[std::size_t(x)] = last;
  }
  last = -1;
  for (int64_t x = w - 1; x >= 0; --x) {
    if (!f[x]) last = x;
    right_[std::size_t(x)] = last;
  }
  // The step-1 row above, for samples with nothing in reach.
  const float* prev = r == 0 ? nullptr : (last_clean_ == r - 1 ? row(r - 1) : prev_filled_->data());
  auto filled_values = std::make_shared<std::vector<float>>(in, in + w);
  float* out = filled_values->data();
  std::optional<float> row_mean;  // mean_in_reach(r), once, when a sample needs it
  for (int64_t x = 0; x < w; ++x) {
    if (!f[x]) continue;
    const auto i = std::size_t(x);
    double sum = 0, weight = 0;
    auto add = [&](double value, int64_t distance) {
      sum += value / double(distance);
      weight += 1.0 / double(distance);
    };
    if (left_[i] >= 0) add(in[left_[i]], x - left_[i]);
    if (right_[i] >= 0) add(in[right_[i]], right_[i] - x);
    if (up_row_[i] >= 0) add(up_val_[i], r - up_row_[i]);
    // The next good sample below: cached while below this row; INT64_MAX = none up to
    // down_scanned_ (searched again once more rows are loaded).
    if (down_row_[i] <= r || (down_row_[i] == INT64_MAX && down_scanned_[i] < loaded_ - 1)) {
      int64_t found = INT64_MAX, y = std::max(r + 1, down_scanned_[i]);
      for (; y < loaded_; ++y) {
        const int g = good(y, x);
        if (g == 2) break;
        if (g == 1) {
          found = y;
          break;
        }
      }
      down_row_[i] = found;
      down_scanned_[i] = found == INT64_MAX ? y : found;
    }
    if (down_row_[i] != INT64_MAX) add(row(down_row_[i])[x], down_row_[i] - r);
    if (weight > 0) {
      out[x] = float(sum / weight);
    } else if (!v[x]) {  // a void edge with no good sample in reach keeps its own value
    } else {  // rare: the nearest valid sample of any kind, in the row, then below
      bool done = false;
      for (int64_t k = 1; !done && (k < w || r + k < loaded_); ++k) {
        if (x - k >= 0 && !v[x - k]) out[x] = in[x - k], done = true;
        else if (x + k < w && !v[x + k]) out[x] = in[x + k], done = true;
        else if (r + k < loaded_ && !voids_[std::size_t(slot(r + k) * w + x)])
          out[x] = row(r + k)[x], done = true;
      }
      if (!done) {
        if (!prev && !row_mean) row_mean = mean_in_reach(r);
        out[x] = prev ? prev[x] : *row_mean;
      }
    }
  }
  for (int64_t x = 0; x < w; ++x)
    if (!f[x]) {
      up_val_[std::size_t(x)] = in[x];
      up_row_[std::size_t(x)] = r;
    }
  prev_filled_ = filled_values;
  auto nodata = std::make_shared<std::vector<uint8_t>>(v, v + w);
  return {r, filled_values, filled, voids, nodata};
}

// Pass `pass` (0-based) receives row y of the previous step; once it holds y-2, y-1, y it smooths
// y-1 (and y itself at the last row, clamping below) and hands it on.
void VoidFiller::push(int pass, Staged staged) {
  if (pass == smoothing_) {
    ready_.push_back(std::move(staged));
    return;
  }
  std::deque<Staged>& q = passes_[std::size_t(pass)];
  q.push_back(std::move(staged));
  if (q.size() > 3) q.pop_front();
  const int64_t w = width_;
  auto smooth = [&](const Staged& up, const Staged& mid, const Staged& down) {
    if (!mid.filled) return mid;  // no replaced sample: nothing changes
    auto smoothed = std::make_shared<std::vector<float>>(*mid.values);
    const float *a = values(up), *b = values(mid), *c = values(down);
    const uint8_t* f = mid.filled->data();
    for (int64_t x = 0; x < w; ++x) {
      if (!f[x]) continue;
      const int64_t l = std::max<int64_t>(0, x - 1), r = std::min(w - 1, x + 1);
      (*smoothed)[std::size_t(x)] =
          (a[l] + a[x] + a[r] + b[l] + b[x] + b[r] + c[l] + c[x] + c[r]) * (1.0f / 9.0f);
    }
    Staged out = mid;
    out.values = smoothed;
    return out;
  };
  const Staged& last = q.back();
  if (q.size() == 1 && last.y == height_ - 1) {  // a one-row map
    push(pass + 1, smooth(last, last, last));
    return;
  }
  if (q.size() >= 2) {
    const Staged& mid = q[q.size() - 2];
    const Staged& up = q.size() == 3 ? q[0] : mid;  // clamped at the top
    push(pass + 1, smooth(up, mid, last));
  }
  if (last.y == height_ - 1 && q.size() >= 2) push(pass + 1, smooth(q[q.size() - 2], last, last));
}

int64_t VoidFiller::next(float* out) {
  while (ready_.empty()) push(0, fill_next());
  Staged staged = std::move(ready_.front());
  ready_.pop_front();
  const float* v = values(staged);
  std::copy(v, v + width_, out);
  if (staged.nodata) std::copy(staged.nodata->begin(), staged.nodata->end(), mask_.begin());
  else if (had_mask_) std::fill(mask_.begin(), mask_.end(), 0);
  had_mask_ = staged.nodata != nullptr;
  any_replaced_ = staged.filled != nullptr;
  if (any_replaced_) replaced_.assign(staged.filled->begin(), staged.filled->end());
  return staged.voids;
}

}  // namespace splatkit::terrain
