#include "graph/classify_clip_partners.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "graph/clip_record.h"
#include "graph/vec3d.h"

namespace splatkit::graph {
namespace {

// Classifies one subset (stored positions [info.begin, info.end)), writes its flags and returns
// its side; m, normal: the subset's mean centre and normalised mean normal.
ClipSide classify_subset(const Vec3f& c, const Vec3f& n, std::span<const Vec3f> centres,
                         std::span<const Vec3f> normals, const Vec3d& m, const Vec3d& normal,
                         double tol, ClipSubsetInfo& info, ClipClassification& out) {
  std::vector<Vec3f> sub_c, sub_n;
  for (uint32_t k = info.begin; k < info.end; ++k) {
    sub_c.push_back(centres[out.order[k]]);
    sub_n.push_back(normals[out.order[k]]);
  }
  info.partners = partner_set_convexity(sub_c, sub_n, tol);
  info.splat = splat_partner_convexity(c, n, sub_c, tol);
  ClipSide side;
  if (info.splat == Convexity::kConcave) {
    side = ClipSide::kBehind;
  } else if (info.splat == Convexity::kConvex) {
    side = ClipSide::kFront;
  } else {
    // The symmetric crease test on the subset as a whole: S sees the surface plus the surface
    // sees S. A floor around a box's corner puts some floor partners behind the plane of a box
    // face splat and some in front (eq. 4.14 mixed), yet the floor plane sees S from one side.
    const Vec3d cd = to_vec3d(c);
    side = dot(m - cd, to_vec3d(n) - normal) > 0 ? ClipSide::kBehind : ClipSide::kFront;
  }
  for (uint32_t k = info.begin; k < info.end; ++k)
    out.flags[k] = side == ClipSide::kFront ? kClipFront : 0;
  info.rule = clip_rule(info.partners, side);
  out.flags[info.begin] |= kClipSubsetStart;
  if (info.rule == ClipRule::kIntersection) out.flags[info.begin] |= kClipSubsetIntersection;
  return side;
}

}  // namespace

void classify_clip_partners(const Vec3f& c, const Vec3f& n, std::span<const Vec3f> centres,
                            std::span<const Vec3f> normals, std::span<const uint32_t> surfaces,
                            double tol, ClipClassification& out) {
  const std::size_t count = centres.size();
  if (normals.size() != count || (!surfaces.empty() && surfaces.size() != count))
    throw std::invalid_argument(
        "classify_clip_partners: centres, normals, surfaces differ in size");
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

  bool sides_agree = true;
  ClipSide common = ClipSide::kBehind;
  std::vector<Vec3f> rep_c, rep_n;
  for (std::size_t s = 0; s < out.subsets.size(); ++s) {
    ClipSubsetInfo& info = out.subsets[s];
    Vec3d mean, normal;
    for (uint32_t k = info.begin; k < info.end; ++k) {
      mean += to_vec3d(centres[out.order[k]]);
      normal += to_vec3d(normals[out.order[k]]);
    }
    mean = mean / static_cast<double>(info.end - info.begin);
    const double len = norm(normal);
    if (len > 0) normal = normal / len;
    const ClipSide side = classify_subset(c, n, centres, normals, mean, normal, tol, info, out);
    sides_agree = sides_agree && (s == 0 || side == common);
    common = side;
    rep_c.push_back({float(mean.x), float(mean.y), float(mean.z)});
    rep_n.push_back({float(normal.x), float(normal.y), float(normal.z)});
  }
  if (out.subsets.size() < 2) return;
  out.subsets_convexity = partner_set_convexity(rep_c, rep_n, tol);
  out.combine_intersection =
      sides_agree && clip_rule(out.subsets_convexity, common) == ClipRule::kIntersection;
}

}  // namespace splatkit::graph
