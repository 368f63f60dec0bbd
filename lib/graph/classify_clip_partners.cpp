#include "graph/classify_clip_partners.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "graph/clip_record.h"
#include "graph/vec3d.h"

namespace splatkit::graph {
namespace {

ClipSide side_of(Convexity splat_class, const Vec3d& c, const Vec3d& n, const Vec3f& cj,
                 const Vec3f& nj, double tol) {
  if (splat_class == Convexity::kConcave) return ClipSide::kBehind;
  if (splat_class == Convexity::kConvex) return ClipSide::kFront;
  const Vec3d w = to_vec3d(cj) - c;
  const double seen = dot(w, n);
  if (seen > tol) return ClipSide::kBehind;
  if (seen < -tol) return ClipSide::kFront;
  // The crease test is symmetric in S and S_j: positive when each sees the other.
  return dot(w, n - to_vec3d(nj)) > 0 ? ClipSide::kBehind : ClipSide::kFront;
}

// Classifies one subset (stored positions [info.begin, info.end)) and writes its flags.
// Returns true when all its partners have the same side, stored in *side.
bool classify_subset(const Vec3d& c, const Vec3d& n, const Vec3f& c_f, const Vec3f& n_f,
                     std::span<const Vec3f> centres, std::span<const Vec3f> normals, double tol,
                     ClipSubsetInfo& info, ClipClassification& out, ClipSide* side) {
  std::vector<Vec3f> sub_c, sub_n;
  for (uint32_t k = info.begin; k < info.end; ++k) {
    sub_c.push_back(centres[out.order[k]]);
    sub_n.push_back(normals[out.order[k]]);
  }
  info.partners = partner_set_convexity(sub_c, sub_n, tol);
  info.splat = splat_partner_convexity(c_f, n_f, sub_c, tol);
  bool uniform = true;
  const ClipSide first = side_of(info.splat, c, n, sub_c[0], sub_n[0], tol);
  for (uint32_t k = info.begin; k < info.end; ++k) {
    const ClipSide s = side_of(info.splat, c, n, sub_c[k - info.begin], sub_n[k - info.begin], tol);
    uniform = uniform && s == first;
    out.flags[k] = s == ClipSide::kFront ? kClipFront : 0;
  }
  info.rule = uniform ? clip_rule(info.partners, first) : ClipRule::kIntersection;
  out.flags[info.begin] |= kClipSubsetStart;
  if (info.rule == ClipRule::kIntersection) out.flags[info.begin] |= kClipSubsetIntersection;
  *side = first;
  return uniform;
}

}  // namespace

void classify_clip_partners(const Vec3f& c, const Vec3f& n, std::span<const Vec3f> centres,
                            std::span<const Vec3f> normals, std::span<const uint32_t> surfaces,
                            double tol, ClipClassification& out) {
  const std::size_t count = centres.size();
  if (normals.size() != count || (!surfaces.empty() && surfaces.size() != count))
    throw std::invalid_argument("classify_clip_partners: centres, normals, surfaces differ in size");
  out.order.resize(count);
  std::iota(out.order.begin(), out.order.end(), 0u);
  if (!surfaces.empty())
    std::stable_sort(out.order.begin(), out.order.end(),
                     [&](uint32_t a, uint32_t b) { return surfaces[a] < surfaces[b]; });
  out.flags.assign(count, 0);
  out.subsets.clear();
  out.combine_intersection = false;
  out.subsets_convexity = Convexity::kFlat;
  if (count == 0) return;

  for (uint32_t k = 0; k < count;) {
    ClipSubsetInfo info;
    info.surface = surfaces.empty() ? 0 : surfaces[out.order[k]];
    info.begin = k;
    while (k < count && (surfaces.empty() || surfaces[out.order[k]] == info.surface)) ++k;
    info.end = k;
    out.subsets.push_back(info);
  }

  const Vec3d cd = to_vec3d(c), nd = to_vec3d(n);
  bool sides_agree = true;
  ClipSide common = ClipSide::kBehind;
  std::vector<Vec3f> rep_c, rep_n;
  for (std::size_t s = 0; s < out.subsets.size(); ++s) {
    ClipSubsetInfo& info = out.subsets[s];
    ClipSide side;
    sides_agree = classify_subset(cd, nd, c, n, centres, normals, tol, info, out, &side) &&
                  sides_agree && (s == 0 || side == common);
    common = side;
    Vec3d mean, normal_sum;
    for (uint32_t k = info.begin; k < info.end; ++k) {
      mean += to_vec3d(centres[out.order[k]]);
      normal_sum += to_vec3d(normals[out.order[k]]);
    }
    mean = mean / static_cast<double>(info.end - info.begin);
    const double len = norm(normal_sum);
    if (len > 0) normal_sum = normal_sum / len;
    rep_c.push_back({float(mean.x), float(mean.y), float(mean.z)});
    rep_n.push_back({float(normal_sum.x), float(normal_sum.y), float(normal_sum.z)});
  }
  if (out.subsets.size() < 2) return;
  out.subsets_convexity = partner_set_convexity(rep_c, rep_n, tol);
  out.combine_intersection =
      sides_agree && clip_rule(out.subsets_convexity, common) == ClipRule::kIntersection;
}

}  // namespace splatkit::graph
