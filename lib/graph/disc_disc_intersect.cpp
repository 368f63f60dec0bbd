#include "graph/disc_disc_intersect.h"

#include <algorithm>

#include "graph/line_disc_segment.h"
#include "graph/line_ellipse_segment.h"
#include "graph/plane_plane_line.h"

namespace splatkit::graph {
namespace {

std::optional<Interval> chord(const Line3& line, const SplatDisc& s) {
  if (s.is_ellipse())
    return line_ellipse_segment(line, s.center, s.axis_u, s.axis_v, s.semi_u, s.semi_v);
  return line_disc_segment(line, s.center, s.normal, s.radius);
}

}  // namespace

DiscDiscResult disc_disc_intersect(const SplatDisc& s_i, const SplatDisc& s_j, double min_sin2) {
  DiscDiscResult result;
  const auto line = plane_plane_line(s_i.center, s_i.normal, s_j.center, s_j.normal, min_sin2);
  if (!line) return result;
  result.line = *line;
  const auto ci = chord(*line, s_i);
  if (!ci) {
    result.status = DiscCrossing::kMissI;
    return result;
  }
  result.segment_i = *ci;
  const auto cj = chord(*line, s_j);
  if (!cj) {
    result.status = DiscCrossing::kMissJ;
    return result;
  }
  result.segment_j = *cj;
  const double lo = std::max(ci->t0, cj->t0), hi = std::min(ci->t1, cj->t1);
  if (lo > hi) {
    result.status = DiscCrossing::kDisjoint;
    return result;
  }
  result.status = DiscCrossing::kCross;
  result.overlap = {lo, hi};
  return result;
}

}  // namespace splatkit::graph
