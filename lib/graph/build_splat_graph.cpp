#include "graph/build_splat_graph.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "graph/classify_clip_partners.h"
#include "graph/disc_disc_intersect.h"
#include "graph/linsen_boundary_test.h"
#include "graph/sphere_overlap_graph.h"
#include "splatkit/error.h"
#include "splatkit/seconds_since.h"

namespace splatkit::graph {
namespace {

// How far (in splat radii) a continuous neighbour must lie beyond a partner's plane to show that
// the surface passes through it; below that, sampling noise.
constexpr float kSideMargin = 0.25f;

void check_inputs(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                  std::span<const float> radii, const SplatGraphOptions& o) {
  if (normals.size() != positions.size() || radii.size() != positions.size())
    throw std::invalid_argument("build_splat_graph: positions, normals, radii differ in size");
  if (!(o.sharp_threshold >= -1 && o.sharp_threshold <= 1))
    throw_usage("--sharp must be in [-1, 1] (got " + std::to_string(o.sharp_threshold) + ")");
  if (!(o.boundary_gap_degrees > 0 && o.boundary_gap_degrees <= 360))
    throw_usage("--boundary-gap must be in (0, 360] degrees");
  const std::optional<float>& core = o.robust.core_threshold;
  if (core && !(*core >= -1 && *core <= 1))
    throw_usage("--core must be in [-1, 1] (got " + std::to_string(*core) + ")");
  if (o.robust.min_core_size == 0) throw_usage("--min-core must be >= 1");
  if (!(o.flat_tolerance >= 0 && std::isfinite(o.flat_tolerance)))
    throw_usage("the flatness tolerance must be finite and >= 0");
  for (std::size_t i = 0; i < radii.size(); ++i)
    if (!(radii[i] >= 0) || !std::isfinite(radii[i]))
      throw Error(ErrorKind::kBadInput, "splat " + std::to_string(i) + ": radius " +
                                            std::to_string(radii[i]) + " is not a finite length");
}

struct Scratch {
  std::vector<Vec3f> centres, normals;
  std::vector<uint32_t> surfaces, partners;
  std::vector<double> angles;
  ClipClassification classification;
};

// True when S_i's continuous neighbours all lie on one side of the line where S_i's plane meets
// S_j's (none further than tau beyond it, measured in S_i's plane): S_i's surface stops at S_j,
// an edge, rather than passing through it. A point of S_i's plane at in-plane distance x from
// the line is x sin θ from S_j's plane, θ the angle between the normals.
bool stops_at(std::span<const Vec3f> continuous, const Vec3f& n_i, const Vec3f& c_j,
              const Vec3f& n_j, float tau) {
  tau *= norm(cross(n_i, n_j));
  bool above = false, below = false;
  for (const Vec3f& c_k : continuous) {
    const float d = dot(c_k - c_j, n_j);
    above = above || d > tau;
    below = below || d < -tau;
  }
  return !(above && below);
}

struct Splats {
  std::span<const Vec3f> positions, normals;
  std::span<const float> radii;
  SplatEllipses ellipses;
  SplatDisc disc(uint32_t i) const {
    if (ellipses.axes.empty()) return SplatDisc::circle(positions[i], normals[i], radii[i]);
    const Vec3f& u = ellipses.axes[i];
    return SplatDisc::ellipse(positions[i], normals[i], u, cross(normals[i], u), radii[i],
                              ellipses.minor_radii[i]);
  }
};

// Adds kEdgeCrossing to the sharp edges of row i (marked by sphere_overlap_graph) whose discs
// cross.
void flag_crossings(std::size_t i, const Splats& in, SplatGraph& g) {
  for (uint64_t k = g.graph.offsets[i]; k < g.graph.offsets[i + 1]; ++k) {
    if (!(g.edge_flags[k] & kEdgeSharp)) continue;
    const uint32_t j = g.graph.neighbors[k];
    const uint32_t lo = std::min<uint32_t>(uint32_t(i), j), hi = std::max<uint32_t>(uint32_t(i), j);
    if (disc_disc_intersect(in.disc(lo), in.disc(hi)).crosses()) g.edge_flags[k] |= kEdgeCrossing;
  }
}

// The class of a splat with a sharp edge (see SplatClass), from its flagged row.
SplatClass classify_row(std::size_t i, const Splats& in, double alpha, Scratch& s,
                        const SplatGraph& g) {
  const auto row = g.graph.row(i);
  const uint8_t* flags = g.edge_flags.data() + g.graph.offsets[i];
  s.centres.clear();
  for (std::size_t k = 0; k < row.size(); ++k)
    if (!(flags[k] & kEdgeSharp)) s.centres.push_back(in.positions[row[k]]);
  if (linsen_boundary_test(in.positions[i], in.normals[i], s.centres, alpha, s.angles).boundary)
    return SplatClass::kEdge;
  // Every crossing partner must agree: on a curved surface a partner whose plane line only
  // grazes S_i's rim can leave all neighbours on one side even where the surfaces cross.
  const float tau = kSideMargin * in.radii[i];
  bool any_crossing = false;
  for (std::size_t k = 0; k < row.size(); ++k) {
    if (!(flags[k] & kEdgeCrossing)) continue;
    any_crossing = true;
    if (!stops_at(s.centres, in.normals[i], in.positions[row[k]], in.normals[row[k]], tau))
      return SplatClass::kIntersection;
  }
  return any_crossing ? SplatClass::kEdge : SplatClass::kIntersection;
}

// The rows with a sharp edge: crossing flags, then the class, while the row is in cache. (The
// other splats are kSmooth.)
void flag_and_classify(const Splats& in, const SplatGraphOptions& o,
                       std::span<const uint32_t> sharp_rows,
                       tbb::enumerable_thread_specific<Scratch>& scratch, SplatGraph& g) {
  const double alpha = o.boundary_gap_degrees * std::numbers::pi / 180;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, sharp_rows.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      Scratch& s = scratch.local();
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        flag_crossings(sharp_rows[k], in, g);
                        g.classes[sharp_rows[k]] = classify_row(sharp_rows[k], in, alpha, s, g);
                      }
                    });
}

// One block of the rows with a sharp edge, for the clip table, filled independently of the other
// blocks (only class kEdge rows have partners; every other row is empty).
struct ClipBlock {
  std::vector<uint32_t> counts, partners;  // counts: one per row of the block
  std::vector<uint8_t> flags, splat_flags;
};

void clip_row(std::size_t i, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
              std::span<const float> radii, const SplatGraphOptions& o, const SplatGraph& g,
              Scratch& s, ClipBlock& out) {
  s.centres.clear();
  s.normals.clear();
  s.surfaces.clear();
  s.partners.clear();
  if (g.classes[i] == SplatClass::kEdge) {
    for (uint64_t k = g.graph.offsets[i]; k < g.graph.offsets[i + 1]; ++k) {
      if (!(g.edge_flags[k] & kEdgeCrossing)) continue;
      const uint32_t j = g.graph.neighbors[k];
      s.partners.push_back(j);
      s.centres.push_back(positions[j]);
      s.normals.push_back(normals[j]);
      if (o.per_surface) s.surfaces.push_back(g.surfaces.surface[j]);
    }
  }
  out.counts.push_back(static_cast<uint32_t>(s.partners.size()));
  if (s.partners.empty()) {
    out.splat_flags.push_back(0);
    return;
  }
  ClipClassification& c = s.classification;
  classify_clip_partners(positions[i], normals[i], s.centres, s.normals, s.surfaces,
                         o.flat_tolerance * radii[i], c);
  for (std::size_t k = 0; k < c.order.size(); ++k) {
    out.partners.push_back(s.partners[c.order[k]]);
    out.flags.push_back(c.flags[k]);
  }
  out.splat_flags.push_back(c.combine_intersection ? kClipCombineIntersection : 0);
}

void build_clip_table(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                      std::span<const float> radii, const SplatGraphOptions& o,
                      std::span<const uint32_t> sharp_rows,
                      tbb::enumerable_thread_specific<Scratch>& scratch, SplatGraph& g) {
  const std::size_t n = positions.size(), rows = sharp_rows.size();
  constexpr std::size_t kRows = 256;  // sharp rows per block
  std::vector<ClipBlock> blocks((rows + kRows - 1) / kRows);
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t b) {
    Scratch& s = scratch.local();
    for (std::size_t k = b * kRows; k < std::min(rows, (b + 1) * kRows); ++k)
      clip_row(sharp_rows[k], positions, normals, radii, o, g, s, blocks[b]);
  });
  // The last use of the surface ids: released before the table's per-splat arrays when not kept.
  if (!o.keep_surface_ids) std::vector<uint32_t>().swap(g.surfaces.surface);
  // Row lengths at i + 1, then their sums; the blocks' partners in order (rows ascending).
  ClipPartnerTable& t = g.clip;
  uint64_t total = 0;
  for (const ClipBlock& block : blocks) total += block.partners.size();
  if (total > kMaxClipPartners)
    throw Error(ErrorKind::kBadInput, "the clip table would hold " + std::to_string(total) +
                                          " partners, more than 2^32 - 1");
  t.offsets.assign(n + 1, 0);
  t.splat_flags.assign(n, 0);
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const ClipBlock& block = blocks[b];
    for (std::size_t k = 0; k < block.counts.size(); ++k) {
      const uint32_t i = sharp_rows[b * kRows + k];
      t.offsets[i + 1] = block.counts[k];
      t.splat_flags[i] = block.splat_flags[k];
    }
    t.partners.insert(t.partners.end(), block.partners.begin(), block.partners.end());
    t.flags.insert(t.flags.end(), block.flags.begin(), block.flags.end());
  }
  for (std::size_t i = 0; i < n; ++i) t.offsets[i + 1] += t.offsets[i];
}

// The columns of the report; the sharp and crossing edges are all in the rows with a sharp edge.
SplatGraphStats count_stats(const SplatGraph& g, std::span<const uint32_t> sharp_rows) {
  SplatGraphStats st;
  st.splats = g.classes.size();
  st.edges = g.graph.neighbors.size() / 2;
  st.mean_degree = st.splats ? double(g.graph.neighbors.size()) / double(st.splats) : 0;
  for (uint32_t i : sharp_rows) {
    for (uint64_t k = g.graph.offsets[i]; k < g.graph.offsets[i + 1]; ++k) {
      st.sharp_edges += (g.edge_flags[k] & kEdgeSharp) != 0;
      st.crossing_edges += (g.edge_flags[k] & kEdgeCrossing) != 0;
    }
    st.candidate_splats += g.classes[i] != SplatClass::kSmooth;
    st.edge_splats += g.classes[i] == SplatClass::kEdge;
    st.intersection_splats += g.classes[i] == SplatClass::kIntersection;
    st.clipped_splats += g.clip.has_partners(i);
  }
  st.sharp_edges /= 2;
  st.crossing_edges /= 2;
  st.clip_partners = g.clip.partners.size();
  st.surfaces = g.surfaces.count();
  return st;
}

// The phases after the neighbour graph (g.graph, with its sharp marks).
void classify_and_clip(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                       std::span<const float> radii, const SplatGraphOptions& options,
                       const ProgressFn& progress, SplatEllipses ellipses, SharpEdgeMarks& sharp,
                       SplatGraph& g) {
  SplatGraphTimings& t = g.timings;
  g.edge_flags = std::move(sharp.flags);
  progress(0.6, "classes");
  Clock::time_point t0 = Clock::now();
  g.classes.resize(positions.size());
  tbb::enumerable_thread_specific<Scratch> scratch;
  flag_and_classify(Splats{positions, normals, radii, ellipses}, options, sharp.rows, scratch, g);
  t.classify = seconds_since(t0);
  progress(0.85, "surfaces");
  t0 = Clock::now();
  RobustSegmentInfo robust_info;
  if (options.robust_surfaces) {
    RobustSegmentOptions ro = options.robust;
    ro.sharp_threshold = options.sharp_threshold;
    g.surfaces = segment_surfaces_robust(g.graph, g.edge_flags, kEdgeSharp, positions, normals, ro,
                                         &robust_info);
  } else {
    g.surfaces = segment_surfaces(g.graph, g.edge_flags, kEdgeSharp);
  }
  t.surfaces = seconds_since(t0);
  progress(0.9, "clip partners");
  t0 = Clock::now();
  build_clip_table(positions, normals, radii, options, sharp.rows, scratch, g);
  t.clip = seconds_since(t0);
  g.stats = count_stats(g, sharp.rows);
  g.stats.surface_method = robust_info;
  progress(1.0, "done");
}

void check_ellipses(SplatEllipses ellipses, std::size_t n) {
  if (!ellipses.axes.empty() && (ellipses.axes.size() != n || ellipses.minor_radii.size() != n))
    throw std::invalid_argument("build_splat_graph: ellipses differ in size from the splats");
}

void check_cloud(const SplatCloud& cloud) {
  if (!cloud.has_normals())
    throw Error(ErrorKind::kBadInput, "the splats have no normals: run estimate-normals first");
  if (!cloud.has_radii())
    throw Error(ErrorKind::kBadInput, "the splats have no radii: run estimate-normals first");
}

}  // namespace

SplatGraph build_splat_graph(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                             std::span<const float> radii, const SplatGraphOptions& options,
                             const ProgressFn& progress, SplatEllipses ellipses) {
  check_inputs(positions, normals, radii, options);
  check_ellipses(ellipses, positions.size());
  SplatGraph g;
  progress(0.0, "neighbour graph");
  const Clock::time_point t0 = Clock::now();
  // Eqs. 3.2–3.3: the weights w_ij = n_i·n_j are tested against w_s where the rows are found.
  SharpEdgeMarks sharp;
  g.graph = sphere_overlap_graph(positions, radii,
                                 SharpEdges{normals, options.sharp_threshold, kEdgeSharp}, sharp);
  g.timings.overlaps = seconds_since(t0);
  classify_and_clip(positions, normals, radii, options, progress, ellipses, sharp, g);
  return g;
}

SplatGraph build_splat_graph(const SplatCloud& cloud, const SplatGraphOptions& options,
                             const ProgressFn& progress) {
  check_cloud(cloud);
  return build_splat_graph(cloud.positions, cloud.normals, cloud.radii, options, progress,
                           {cloud.axes, cloud.minor_radii});
}

SplatGraph build_splat_graph_in_place(SplatCloud& cloud, const SplatGraphOptions& options,
                                      const ProgressFn& progress) {
  check_cloud(cloud);
  check_inputs(cloud.positions, cloud.normals, cloud.radii, options);
  const SplatEllipses ellipses{cloud.axes, cloud.minor_radii};
  check_ellipses(ellipses, cloud.size());
  SplatGraph g;
  progress(0.0, "neighbour graph");
  const Clock::time_point t0 = Clock::now();
  SharpEdgeMarks sharp;
  g.graph = sphere_overlap_graph(LentSplats{cloud.positions, cloud.radii, cloud.normals},
                                 options.sharp_threshold, kEdgeSharp, sharp);
  g.timings.overlaps = seconds_since(t0);
  classify_and_clip(cloud.positions, cloud.normals, cloud.radii, options, progress, ellipses, sharp,
                    g);
  return g;
}

}  // namespace splatkit::graph
