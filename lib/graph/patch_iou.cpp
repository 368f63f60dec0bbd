#include "graph/patch_iou.h"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace splatkit::graph {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

}  // namespace

std::vector<PatchMatch> patch_iou(std::span<const uint32_t> truth,
                                  std::span<const uint32_t> surfaces) {
  if (truth.size() != surfaces.size())
    throw std::invalid_argument("patch_iou: truth and surfaces differ in size");
  // Sorting the (patch, surface) pairs counts every overlap with one pass and no hash order.
  std::vector<uint64_t> pairs(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) pairs[i] = uint64_t{truth[i]} << 32 | surfaces[i];
  std::sort(pairs.begin(), pairs.end());
  std::map<uint32_t, uint64_t> surface_size;
  for (uint32_t s : surfaces) ++surface_size[s];

  std::vector<PatchMatch> out;
  for (std::size_t a = 0; a < pairs.size();) {
    const uint32_t patch = uint32_t(pairs[a] >> 32);
    std::size_t end = a;
    while (end < pairs.size() && uint32_t(pairs[end] >> 32) == patch) ++end;
    PatchMatch m;
    m.patch = patch;
    m.size = end - a;
    m.surface = kNone;
    for (std::size_t b = a; b < end;) {
      const uint32_t s = uint32_t(pairs[b]);
      std::size_t e = b;
      while (e < end && uint32_t(pairs[e]) == s) ++e;
      if (s != kNone) {
        const uint64_t both = e - b, size = surface_size[s];
        const double iou = double(both) / double(m.size + size - both);
        if (iou > m.iou) m = {patch, m.size, s, size, both, iou};
      }
      b = e;
    }
    out.push_back(m);
    a = end;
  }
  return out;
}

double fraction_recovered(std::span<const PatchMatch> matches, double threshold) {
  if (matches.empty()) return 1;
  const auto ok = std::count_if(matches.begin(), matches.end(),
                                [&](const PatchMatch& m) { return m.iou >= threshold; });
  return double(ok) / double(matches.size());
}

}  // namespace splatkit::graph
