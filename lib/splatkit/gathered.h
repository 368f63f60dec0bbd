// gathered: the values of a vector or span at the given positions, in parallel: out[t] =
// v[order[t]]. Used to put per-point arrays into another order (estimate_normals' Morton order)
// and to take the values of a subset (the points a piece loads, splat_pieces.h).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace splatkit {

template <class Values>
auto gathered(const Values& v, const std::vector<uint32_t>& order) {
  std::vector<std::remove_cv_t<typename Values::value_type>> out(order.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, order.size(), 1 << 14), [&](const auto& r) {
    for (std::size_t t = r.begin(); t < r.end(); ++t) out[t] = v[order[t]];
  });
  return out;
}

}  // namespace splatkit
