#include "render/zbuffer_splats.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "splatkit/sized_in_parallel.h"

namespace splatkit::render {

void DepthKeyBuffer::reset(int w, int h) {
  width = w;
  height = h;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  if (keys.size() != n) {  // a new buffer (no copy of stale contents), its pages mapped in parallel
    keys = {};
    sized_in_parallel(keys, n);
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 16), [&](const auto& r) {
    std::fill(keys.begin() + r.begin(), keys.begin() + r.end(), kNoSplatKey);
  });
}

}  // namespace splatkit::render
