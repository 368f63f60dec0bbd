#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "splatkit/simd_level.h"
#include "splatkit/spatial_index.h"
#include "splatkit/spatial_index_search.h"

namespace splatkit {

using namespace spatial_index_detail;

std::size_t SpatialIndex::knn(const Vec3f& q, std::size_t k, uint32_t* out_indices,
                              float* out_sq_dists) const {
  k = std::min(k, size());
  if (k == 0 || !is_finite(q)) return 0;
  std::vector<uint64_t> keys(k);
  KnnState state(k, keys.data());
  KnnSearch{*this, q.x, q.y, q.z, kNone, state, simd_level() >= SimdLevel::kSse2}.from_root();
  state.finish();
  for (std::size_t c = 0; c < state.count; ++c) {
    out_indices[c] = key_id(keys[c]);
    if (out_sq_dists != nullptr) out_sq_dists[c] = key_d2(keys[c]);
  }
  return state.count;
}

void SpatialIndex::radius(const Vec3f& q, float r, std::vector<uint32_t>& out_indices,
                          std::vector<float>* out_sq_dists) const {
  if (!(r >= 0.0f) || !std::isfinite(r)) {
    throw std::invalid_argument("SpatialIndex::radius: radius must be finite and >= 0");
  }
  out_indices.clear();
  if (out_sq_dists != nullptr) out_sq_dists->clear();
  if (size() == 0 || !is_finite(q)) return;
  const float r2 = r * r;
  struct Hit {
    float d2;
    uint32_t id;
  };
  std::vector<Hit> hits;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    uint32_t node = stack.back();
    stack.pop_back();
    if (box_sq_dist(boxes_[node], q.x, q.y, q.z) > r2) continue;
    if (node < first_leaf_) {
      stack.push_back(2 * node + 2);
      stack.push_back(2 * node + 1);
      continue;
    }
    uint32_t leaf = node - first_leaf_;
    for (uint32_t p = leaf_start_[leaf]; p < leaf_start_[leaf + 1]; ++p) {
      float dx = xs_[p] - q.x, dy = ys_[p] - q.y, dz = zs_[p] - q.z;
      float d = dx * dx + dy * dy + dz * dz;
      if (d <= r2) hits.push_back({d, ids_[p]});
    }
  }
  std::sort(hits.begin(), hits.end(),
            [](const Hit& a, const Hit& b) { return before(a.d2, a.id, b.d2, b.id); });
  out_indices.reserve(hits.size());
  for (const Hit& h : hits) out_indices.push_back(h.id);
  if (out_sq_dists != nullptr) {
    out_sq_dists->reserve(hits.size());
    for (const Hit& h : hits) out_sq_dists->push_back(h.d2);
  }
}

}  // namespace splatkit
