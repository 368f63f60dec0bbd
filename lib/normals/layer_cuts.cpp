#include "normals/layer_cuts.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <utility>

namespace splatkit {

std::vector<float> layer_cuts(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                              std::span<const uint32_t> rows, std::size_t w,
                              std::span<const uint8_t> layered) {
  const std::size_t n = positions.size();
  std::vector<float> cut(n, std::numeric_limits<float>::quiet_NaN());
  if (w == 0) return cut;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    std::vector<uint32_t> ring;
    std::vector<std::pair<float, uint32_t>> off;
    std::vector<double> prefix, prefix2;
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (!layered.empty() && !layered[i]) continue;
      ring.assign(1, static_cast<uint32_t>(i));
      const uint32_t* row = rows.data() + i * w;
      for (std::size_t s = 0; s < w; ++s) {
        ring.push_back(row[s]);
        const uint32_t* next = rows.data() + std::size_t{row[s]} * w;
        ring.insert(ring.end(), next, next + w);
      }
      std::sort(ring.begin(), ring.end());
      ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
      const std::size_t m = ring.size();
      if (m < 8) continue;
      const Vec3f& ni = normals[i];
      const Vec3f& xi = positions[i];
      off.clear();
      for (uint32_t j : ring) off.push_back({dot(ni, positions[j] - xi), j});
      std::sort(off.begin(), off.end());
      prefix.assign(m + 1, 0.0);
      prefix2.assign(m + 1, 0.0);
      for (std::size_t q = 0; q < m; ++q) {
        prefix[q + 1] = prefix[q] + off[q].first;
        prefix2[q + 1] = prefix2[q] + double{off[q].first} * off[q].first;
      }
      // The split s (parts [0, s) and [s, m)) of the largest separation.
      double best = 0;
      std::size_t split = 0;
      for (std::size_t s = 3; s + 3 <= m; ++s) {
        const double na = static_cast<double>(s), nb = static_cast<double>(m - s);
        const double ma = prefix[s] / na, mb = (prefix[m] - prefix[s]) / nb;
        const double ss = (prefix2[s] - na * ma * ma) + (prefix2[m] - prefix2[s] - nb * mb * mb);
        const double var = std::max(ss, 0.0) / static_cast<double>(m);
        const double gap = mb - ma;
        if (gap * gap > best * best * var && gap > 0) {
          best = var > 0 ? gap / std::sqrt(var) : std::numeric_limits<double>::infinity();
          split = s;
        }
      }
      if (split == 0 || !(best >= kLayerSeparation)) continue;
      // The parts must lie over each other, not side by side.
      Vec3f ca{0, 0, 0}, cb{0, 0, 0};
      float radius2 = 0;
      for (std::size_t q = 0; q < m; ++q) {
        const Vec3f d = positions[off[q].second] - xi;
        radius2 = std::max(radius2, squared_norm(d));
        const Vec3f t = d - ni * off[q].first;
        (q < split ? ca : cb) += t;
      }
      ca = ca * (1.0f / static_cast<float>(split));
      cb = cb * (1.0f / static_cast<float>(m - split));
      if (squared_norm(ca - cb) > kLayerOverlap * kLayerOverlap * radius2) continue;
      cut[i] = 0.5f * (off[split - 1].first + off[split].first);
    }
  });
  return cut;
}

}  // namespace splatkit
