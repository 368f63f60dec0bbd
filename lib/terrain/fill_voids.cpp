#include "terrain/fill_voids.h"

#include <algorithm>
#include <cstdint>

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
      lookahead_(std::max(lookahead, std::max<int64_t>(2, source.info().band_rows))),
      smoothing_(smoothing),
      passes_(std::size_t(smoothing)) {
  const auto w = std::size_t(width_);
  up_val_.assign(w, 0.0f);
  up_row_.assign(w, -1);
  down_row_.assign(w, -1);
  down_scanned_.assign(w, 0);
  mask_.assign(w, 0);
  left_.resize(w);
  right_.resize(w);
}

void VoidFiller::load_more() {
  const int64_t n = std::min(std::max<int64_t>(1, source_.info().band_rows), height_ - loaded_);
  const std::size_t at = std::size_t((loaded_ - first_) * width_);
  rows_.resize(at + std::size_t(n * width_));
  voids_.resize(rows_.size());
  source_.read_rows(n, rows_.data() + at);
  for (std::size_t i = at; i < rows_.size(); ++i)
    voids_[i] = is_void(rows_[i], has_nodata_, nodata_) ? 1 : 0;
  loaded_ += n;
}

int VoidFiller::good(int64_t y, int64_t x) const {
  if (y + kEdge >= loaded_ && loaded_ < height_) return 2;
  const int64_t w = width_;
  for (int64_t yy = std::max(first_, y - kEdge); yy <= std::min(loaded_ - 1, y + kEdge); ++yy) {
    const uint8_t* v = voids_.data() + (yy - first_) * w;
    for (int64_t xx = std::max<int64_t>(0, x - kEdge); xx <= std::min(w - 1, x + kEdge); ++xx)
      if (v[xx]) return 0;
  }
  return 1;
}

VoidFiller::Staged VoidFiller::fill_next() {
  const int64_t w = width_, r = row_++;
  while (loaded_ < height_ && loaded_ <= r + lookahead_) load_more();
  if (r - first_ > lookahead_) {  // keep kEdge rows above r for the void-edge test
    const int64_t drop = r - kEdge - first_;
    rows_.erase(rows_.begin(), rows_.begin() + drop * w);
    voids_.erase(voids_.begin(), voids_.begin() + drop * w);
    first_ = r - kEdge;
  }
  const float* in = rows_.data() + (r - first_) * w;
  const uint8_t* v = voids_.data() + (r - first_) * w;
  int64_t voids = 0, replaced = 0;
  for (int64_t x = 0; x < w; ++x) voids += v[x];
  // Rows within kEdge of this one: their voids make samples of this row void edges.
  const int64_t y0 = std::max(first_, r - kEdge), y1 = std::min(loaded_ - 1, r + kEdge);
  std::vector<uint8_t>& near = near_;
  near.assign(std::size_t(w), 0);
  bool any = false;
  for (int64_t y = y0; y <= y1; ++y) {
    const uint8_t* vy = voids_.data() + (y - first_) * w;
    for (int64_t x = 0; x < w; ++x) near[std::size_t(x)] |= vy[x];
    any = any || std::find(vy, vy + w, 1) != vy + w;
  }
  if (!any) {  // no void within kEdge rows: the row is kept as it is
    auto values = std::make_shared<std::vector<float>>(in, in + w);
    std::copy(in, in + w, up_val_.begin());
    std::fill(up_row_.begin(), up_row_.end(), r);
    prev_ = *values;
    return {r, values, nullptr, 0, nullptr};
  }
  auto filled = std::make_shared<std::vector<uint8_t>>(std::size_t(w));
  for (int64_t x = 0; x < w; ++x) {
    bool bad = false;
    for (int64_t xx = std::max<int64_t>(0, x - kEdge); xx <= std::min(w - 1, x + kEdge); ++xx)
      bad = bad || near[std::size_t(xx)];
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
  auto values = std::make_shared<std::vector<float>>(in, in + w);
  float* out = values->data();
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
    if (down_row_[i] != INT64_MAX)
      add(rows_[std::size_t((down_row_[i] - first_) * w + x)], down_row_[i] - r);
    if (weight > 0) {
      out[x] = float(sum / weight);
    } else if (!v[x]) {  // a void edge with no good sample in reach keeps its own value
    } else {  // rare: the nearest valid sample of any kind, in the row, below, above
      int64_t k = 1;
      for (; k < w || k < loaded_ - r; ++k) {
        if (x - k >= 0 && !v[x - k]) { out[x] = in[x - k]; break; }
        if (x + k < w && !v[x + k]) { out[x] = in[x + k]; break; }
        if (r + k < loaded_ && !voids_[std::size_t((r + k - first_) * w + x)]) {
          out[x] = rows_[std::size_t((r + k - first_) * w + x)];
          break;
        }
      }
      if (k >= w && k >= loaded_ - r) out[x] = prev_.empty() ? 0.0f : prev_[i];
    }
  }
  for (int64_t x = 0; x < w; ++x)
    if (!f[x]) {
      up_val_[std::size_t(x)] = in[x];
      up_row_[std::size_t(x)] = r;
    }
  prev_ = *values;
  auto nodata = std::make_shared<std::vector<uint8_t>>(v, v + w);
  return {r, values, filled, voids, nodata};
}

// Pass `pass` (0-based) receives row y of the previous step; once it holds y-2, y-1, y it smooths
// y-1 (and y itself at the last row, clamping below) and hands it on.
void VoidFiller::push(int pass, Staged row) {
  if (pass == smoothing_) {
    ready_.push_back(std::move(row));
    return;
  }
  std::deque<Staged>& q = passes_[std::size_t(pass)];
  q.push_back(std::move(row));
  if (q.size() > 3) q.pop_front();
  const int64_t w = width_;
  auto smooth = [&](const Staged& up, const Staged& mid, const Staged& down) {
    if (!mid.filled) return mid;  // no replaced sample: nothing changes
    auto values = std::make_shared<std::vector<float>>(*mid.values);
    const float *a = up.values->data(), *b = mid.values->data(), *c = down.values->data();
    const uint8_t* f = mid.filled->data();
    for (int64_t x = 0; x < w; ++x) {
      if (!f[x]) continue;
      const int64_t l = std::max<int64_t>(0, x - 1), r = std::min(w - 1, x + 1);
      (*values)[std::size_t(x)] =
          (a[l] + a[x] + a[r] + b[l] + b[x] + b[r] + c[l] + c[x] + c[r]) * (1.0f / 9.0f);
    }
    Staged out = mid;
    out.values = values;
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
  Staged row = std::move(ready_.front());
  ready_.pop_front();
  std::copy(row.values->begin(), row.values->end(), out);
  if (row.nodata) std::copy(row.nodata->begin(), row.nodata->end(), mask_.begin());
  else std::fill(mask_.begin(), mask_.end(), 0);
  return row.voids;
}

}  // namespace splatkit::terrain
