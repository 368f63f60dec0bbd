#include "normals/select_face_normals.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <vector>

namespace splatkit {

float face_noise(std::span<const FaceModel> models, std::span<const uint32_t> points) {
  std::vector<float> v;
  v.reserve(points.size());
  for (uint32_t i : points)
    if (std::isfinite(models[i].variance)) v.push_back(models[i].variance);
  if (v.empty()) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return std::sqrt(std::max(*mid, 0.0f));
}

std::size_t select_face_normals(const SpatialIndex& index, std::span<const Vec3f> positions,
                                std::span<const uint32_t> points, std::size_t k,
                                std::span<const Vec3f> normals, std::span<const FaceModel> models,
                                float noise, std::span<Vec3f> out, std::span<float> sq_reach,
                                std::span<float> cuts) {
  const std::size_t wide = std::min(2 * k, positions.size());
  const float band = kFaceBand * noise;
  std::atomic<std::size_t> changed{0};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256), [&](const auto& range) {
    std::vector<uint32_t> row(wide, SpatialIndex::kNone);
    std::vector<float> sq(wide);
    std::size_t here = 0;
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      const uint32_t i = points[p];
      const std::size_t got = index.knn(positions[i], wide, row.data(), sq.data());
      if (!sq_reach.empty())
        sq_reach[i] =
            std::max(sq_reach[i], got == wide && wide > 0 ? sq[wide - 1]
                                                          : std::numeric_limits<float>::infinity());
      const auto on_face = [&](const FaceModel& m, float o) {
        return std::fabs(o - m.a) <= band || std::fabs(o - m.b) <= band;
      };
      int best = -1;
      Vec3f chosen = normals[i];
      uint32_t owner = i;
      for (std::size_t c = 0; c < std::min(k, got); ++c) {
        const uint32_t j = row[c];
        const FaceModel& m = models[j];
        if (!std::isfinite(m.variance)) continue;
        const Vec3f& n = normals[j];
        const Vec3f& xj = positions[j];
        if (!on_face(m, dot(n, positions[i] - xj))) continue;  // not through the point
        int count = 0;
        for (std::size_t q = 0; q < got; ++q) count += on_face(m, dot(n, positions[row[q]] - xj));
        if (count > best) {
          best = count;
          chosen = n;
          owner = j;
        }
      }
      if (!cuts.empty()) {
        const FaceModel& m = models[owner];
        cuts[i] = best >= 0 && m.a != m.b
                      ? dot(chosen, positions[owner] - positions[i]) + 0.5f * (m.a + m.b)
                      : std::numeric_limits<float>::quiet_NaN();
      }
      if (!(chosen == normals[i])) ++here;
      out[i] = chosen;
    }
    changed += here;
  });
  return changed;
}

}  // namespace splatkit
