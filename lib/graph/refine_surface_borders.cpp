#include "graph/refine_surface_borders.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "graph/fit_surface_primitive.h"
#include "graph/renumber_surfaces.h"
#include "graph/surface_members.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/pca_normal.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kMaxFitPoints = 4096;  // splats a surface's primitive is fitted to
constexpr std::size_t kScaleSamples = 512;   // splats its local noise is measured on
constexpr std::size_t kChunk = 4096;

bool finite(const Vec3f& v) { return std::isfinite(v.x + v.y + v.z); }

// Every step-th member, so that at most `limit` remain (evenly spread over the indices).
std::vector<uint32_t> spread(std::span<const uint32_t> members, std::size_t limit) {
  const std::size_t step = std::max<std::size_t>(1, (members.size() + limit - 1) / limit);
  std::vector<uint32_t> out;
  for (std::size_t k = 0; k < members.size(); k += step) out.push_back(members[k]);
  return out;
}

struct Rows {
  const NeighborGraph& graph;
  template <class Fn>
  void each(std::size_t i, Fn&& fn) const {
    for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) fn(graph.neighbors[k]);
  }
};

// Noise of a surface's splats about planes through their neighbours on the same surface (each
// splat left out of its own plane): 1.4826 × the median residual over up to kScaleSamples
// members; infinity when no member has 5 such neighbours.
double local_scale(const Rows& rows, std::span<const Vec3f> positions,
                   std::span<const uint32_t> label, std::span<const uint32_t> members) {
  std::vector<double> r;
  for (uint32_t i : spread(members, kScaleSamples)) {
    const Vec3d p = to_vec3d(positions[i]);
    double w = 0;
    Vec3d s;
    std::array<double, 6> ss{};
    rows.each(i, [&](uint32_t j) {
      if (label[j] != label[i]) return;
      const Vec3d d = to_vec3d(positions[j]) - p;
      w += 1;
      s += d;
      ss[0] += d.x * d.x, ss[1] += d.x * d.y, ss[2] += d.x * d.z;
      ss[3] += d.y * d.y, ss[4] += d.y * d.z, ss[5] += d.z * d.z;
    });
    if (w < 5) continue;
    const Vec3d c = s / w;
    const std::array<double, 3> n =
        pca_normal({ss[0] / w - c.x * c.x, ss[1] / w - c.x * c.y, ss[2] / w - c.x * c.z,
                    ss[3] / w - c.y * c.y, ss[4] / w - c.y * c.z, ss[5] / w - c.z * c.z})
            .normal;
    r.push_back(std::abs(c.x * n[0] + c.y * n[1] + c.z * n[2]));
  }
  if (r.empty()) return std::numeric_limits<double>::infinity();
  auto mid = r.begin() + r.size() / 2;
  std::nth_element(r.begin(), mid, r.end());
  return 1.4826 * *mid;
}

struct Model {
  enum State : uint8_t { kFragment, kUnexplained, kPrimitive };
  State state = kFragment;
  SurfacePrimitive primitive;
  double tolerance = 0;  // 3 robust scales, at least a rounding floor
};

Model fit_model(const Rows& rows, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                std::span<const uint32_t> label, std::span<const uint32_t> members) {
  Model model;
  model.state = Model::kUnexplained;
  const std::vector<uint32_t> sample = spread(members, kMaxFitPoints);
  const SurfacePrimitive f = fit_surface_primitive(positions, normals, sample);
  if (f.kind == PrimitiveKind::kNone) return model;
  // Rounding floor for noiseless input: 1e-5 of the surface's extent.
  Vec3d lo = to_vec3d(positions[sample[0]]), hi = lo;
  for (uint32_t i : sample) {
    const Vec3d p = to_vec3d(positions[i]);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double floor = 1e-5 * norm(hi - lo);
  const double scale = std::max(f.scale, floor);
  std::size_t inliers = 0;
  for (uint32_t i : sample) inliers += f.distance(to_vec3d(positions[i])) <= 3 * scale;
  // A leaked surface has a majority face that the robust fit follows and a minority it does
  // not explain: the inlier count catches it where the scale (a median) does not.
  if (scale <= 2 * local_scale(rows, positions, label, members) + floor &&
      inliers >= 0.9 * double(sample.size())) {
    model.state = Model::kPrimitive;
    model.primitive = f;
    model.tolerance = 3 * scale;
  }
  return model;
}

// The splats with a neighbour on another surface, and every pair (a, b) of different surfaces
// joined by an edge (as a << 32 | b), both ascending: one pass over the edges.
struct Borders {
  std::vector<uint32_t> splats;
  std::vector<uint64_t> pairs;
};

Borders find_borders(const NeighborGraph& graph, std::span<const uint32_t> label) {
  const std::size_t n = graph.num_points();
  std::vector<Borders> parts(chunk_count(n, kChunk));
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    Borders& out = parts[c];
    for (std::size_t i = begin; i < end; ++i) {
      const uint32_t a = label[i];
      bool border = false;
      for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
        const uint32_t b = label[graph.neighbors[k]];
        if (a == b) continue;
        border = true;
        out.pairs.push_back(uint64_t{a} << 32 | b);
      }
      if (border) out.splats.push_back(uint32_t(i));
    }
    std::sort(out.pairs.begin(), out.pairs.end());
    out.pairs.erase(std::unique(out.pairs.begin(), out.pairs.end()), out.pairs.end());
  });
  Borders all;
  for (const Borders& p : parts) {
    all.splats.insert(all.splats.end(), p.splats.begin(), p.splats.end());
    all.pairs.insert(all.pairs.end(), p.pairs.begin(), p.pairs.end());
  }
  std::sort(all.pairs.begin(), all.pairs.end());
  all.pairs.erase(std::unique(all.pairs.begin(), all.pairs.end()), all.pairs.end());
  return all;
}

// The fraction of `members` that `by`'s primitive explains (within its tolerance, normals
// compatible).
double explained(const Model& by, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                 std::span<const uint32_t> members, float min_normal_dot) {
  std::size_t total = 0, near = 0;
  for (uint32_t i : spread(members, kMaxFitPoints)) {
    const Vec3d p = to_vec3d(positions[i]);
    const bool facing = !finite(normals[i]) ||
                        dot(by.primitive.normal_at(p), to_vec3d(normals[i])) >= min_normal_dot;
    near += facing && by.primitive.distance(p) <= by.tolerance;
    ++total;
  }
  return double(near) / double(total);
}

struct Candidate {
  uint32_t surface = 0;
  double signed_distance = 0;  // of the splat from the primitive, > 0 where its normals point
  Vec3d normal;                // the primitive's normal at the splat
  Vec3d centroid;              // of the surface's splats among the neighbours (their sum first)
  uint32_t count = 0;          // how many there are
};

// Where splat i belongs, given the labels of the round.
class Judge {
 public:
  Judge(const Rows& rows, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
        std::span<const uint32_t> label, std::span<const Model> models,
        const RefineBordersOptions& options)
      : rows_(rows),
        positions_(positions),
        normals_(normals),
        label_(label),
        models_(models),
        options_(options) {}

  // cands: scratch.
  uint32_t operator()(uint32_t i, std::vector<Candidate>& cands) const {
    const uint32_t own = label_[i];
    bool border = models_[own].state == Model::kFragment;
    rows_.each(i, [&](uint32_t j) { border = border || label_[j] != own; });
    if (!border) return own;
    // The modelled surfaces among the splat and its neighbours, with their splats' mean
    // position there (the splat itself left out).
    cands.clear();
    bool unexplained = false;
    auto candidate = [&](uint32_t s) -> Candidate* {
      if (models_[s].state == Model::kFragment) return nullptr;
      unexplained = unexplained || models_[s].state == Model::kUnexplained;
      for (Candidate& c : cands)
        if (c.surface == s) return &c;
      Candidate& c = cands.emplace_back();
      c.surface = s;
      return &c;
    };
    candidate(own);
    rows_.each(i, [&](uint32_t j) {
      if (Candidate* c = candidate(label_[j])) c->centroid += to_vec3d(positions_[j]), ++c->count;
    });
    if (unexplained) return own;
    const Vec3d p = to_vec3d(positions_[i]);
    const Vec3f& ni = normals_[i];
    std::size_t kept = 0;
    for (Candidate c : cands) {
      const SurfacePrimitive& f = models_[c.surface].primitive;
      c.signed_distance = f.signed_distance(p);
      c.normal = f.normal_at(p);
      if (finite(ni) && dot(c.normal, to_vec3d(ni)) < options_.min_normal_dot) continue;
      if (c.count > 0) c.centroid = c.centroid / double(c.count);
      cands[kept++] = c;
    }
    cands.resize(kept);
    return cands.empty() ? own : choose(own, cands);
  }

 private:
  // Nearest first (ties: the own surface, then the lower id); then each other candidate takes
  // over where the crease between the two says so.
  uint32_t choose(uint32_t own, std::vector<Candidate>& cands) const {
    std::sort(cands.begin(), cands.end(), [&](const Candidate& a, const Candidate& b) {
      const double da = std::abs(a.signed_distance), db = std::abs(b.signed_distance);
      if (da != db) return da < db;
      if ((a.surface == own) != (b.surface == own)) return a.surface == own;
      return a.surface < b.surface;
    });
    std::size_t win = 0;
    for (std::size_t k = 1; k < cands.size(); ++k) {
      const Candidate& a = cands[win];
      const Candidate& b = cands[k];
      // Only within b's noise: where surfaces cross rather than meet, a splat of one lies on
      // the far side of the other beyond the crossing, and only its distance tells.
      if (a.count == 0 || b.count == 0 ||
          std::abs(b.signed_distance) > models_[b.surface].tolerance)
        continue;
      const Vec3d ab = b.centroid - a.centroid;
      const double len = norm(ab);
      if (!(len > 0)) continue;
      // Convex: each normal points away from the other surface's splats.
      const double va = dot(a.normal, ab) / len, vb = -dot(b.normal, ab) / len;
      const double t = options_.crease_sine;
      const int convex = va < -t && vb < -t ? 1 : (va > t && vb > t ? -1 : 0);
      if (convex * (b.signed_distance - a.signed_distance) > 0) win = k;
    }
    return cands[win].surface;
  }

  const Rows& rows_;
  std::span<const Vec3f> positions_, normals_;
  std::span<const uint32_t> label_;
  std::span<const Model> models_;
  const RefineBordersOptions& options_;
};

struct Models {
  std::vector<Model> model;    // per surface
  std::vector<uint32_t> into;  // per surface: the surface its splats join first (itself, or the
                               // larger neighbour that explains it)
};

Models fit_models(const NeighborGraph& graph, std::span<const Vec3f> positions,
                  std::span<const Vec3f> normals, const Segmentation& seg,
                  std::span<const uint64_t> pairs, const RefineBordersOptions& options,
                  RefineBordersInfo& info) {
  const Rows rows{graph};
  const SurfaceMembers groups = surface_members(seg.surface, seg.count());
  Models out{std::vector<Model>(seg.count()), std::vector<uint32_t>(seg.count())};
  std::vector<Model>& models = out.model;
  tbb::parallel_for(uint32_t{0}, seg.count(), [&](uint32_t s) {
    if (seg.sizes[s] >= options.min_surface_size)
      models[s] = fit_model(rows, positions, normals, seg.surface, groups.of(s));
  });
  // A surface that a larger neighbour's primitive explains for at least half of its splats is
  // a fragment of that neighbour (of the one explaining most; ties: the larger, the lower id):
  // decided on the models as fitted, so the order of the pairs does not matter.
  std::vector<double> fraction(pairs.size(), 0);
  tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t k) {
    const uint32_t f = uint32_t(pairs[k] >> 32), s = uint32_t(pairs[k]);
    if (models[f].state == Model::kFragment || models[s].state != Model::kPrimitive) return;
    if (seg.sizes[s] < seg.sizes[f] || (seg.sizes[s] == seg.sizes[f] && s > f)) return;
    fraction[k] = explained(models[s], positions, normals, groups.of(f), options.min_normal_dot);
  });
  for (uint32_t s = 0; s < seg.count(); ++s) out.into[s] = s;
  std::vector<double> best(seg.count(), 0.5);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const uint32_t f = uint32_t(pairs[k] >> 32), s = uint32_t(pairs[k]);
    const uint32_t& t = out.into[f];
    if (fraction[k] > best[f] || (fraction[k] == best[f] && t != f && seg.sizes[s] > seg.sizes[t]))
      out.into[f] = s, best[f] = fraction[k];
  }
  // The absorber may be absorbed in turn (always by a larger surface, so chains end).
  for (uint32_t s = 0; s < seg.count(); ++s) {
    uint32_t t = s;
    while (out.into[t] != t) t = out.into[t];
    out.into[s] = t;
    if (t != s) models[s] = Model{};
  }
  for (const Model& m : models) {
    info.fragments += m.state == Model::kFragment;
    info.unexplained += m.state == Model::kUnexplained;
    info.planes += m.state == Model::kPrimitive && m.primitive.kind == PrimitiveKind::kPlane;
    info.spheres += m.state == Model::kPrimitive && m.primitive.kind == PrimitiveKind::kSphere;
    info.cylinders += m.state == Model::kPrimitive && m.primitive.kind == PrimitiveKind::kCylinder;
  }
  return out;
}

}  // namespace

Segmentation refine_surface_borders(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                    std::span<const Vec3f> normals, Segmentation seg,
                                    const RefineBordersOptions& options, RefineBordersInfo* info) {
  const std::size_t n = graph.num_points();
  if (positions.size() != n || normals.size() != n || seg.surface.size() != n)
    throw std::invalid_argument("refine_surface_borders: one position, normal and id per splat");
  RefineBordersInfo done;
  for (uint32_t s : seg.surface)
    if (s >= seg.count())
      throw std::invalid_argument("refine_surface_borders: surface id out of range");
  if (options.rounds == 0 || n == 0) {
    if (info) *info = done;
    return seg;
  }
  Borders borders = find_borders(graph, seg.surface);
  const Models fitted = fit_models(graph, positions, normals, seg, borders.pairs, options, done);
  const std::vector<Model>& models = fitted.model;
  std::vector<uint32_t> label = std::move(seg.surface);
  bool joined = false;
  for (uint32_t s = 0; s < seg.count(); ++s) joined = joined || fitted.into[s] != s;
  if (joined) {
    for (uint32_t& s : label) s = fitted.into[s];
    borders = find_borders(graph, label);
  }

  // Round 1 judges the border splats (a splat inside a fragment has no other candidate); later
  // rounds the splats that changed and their neighbours (a judgement reads the labels of the
  // splat and its neighbours, nothing else that changes).
  const Rows rows{graph};
  const Judge judge(rows, positions, normals, label, models, options);
  std::vector<uint32_t> work = std::move(borders.splats), verdict, changed;
  for (uint32_t round = 0; round < options.rounds && !work.empty(); ++round) {
    verdict.resize(work.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work.size(), kChunk),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        std::vector<Candidate> cands;
                        for (std::size_t k = r.begin(); k < r.end(); ++k)
                          verdict[k] = judge(work[k], cands);
                      });
    changed.clear();
    for (std::size_t k = 0; k < work.size(); ++k)
      if (verdict[k] != label[work[k]]) {
        label[work[k]] = verdict[k];
        changed.push_back(work[k]);
      }
    ++done.rounds;
    done.moved += changed.size();
    work.clear();
    if (changed.empty()) break;
    for (uint32_t i : changed) {
      work.push_back(i);
      rows.each(i, [&](uint32_t j) { work.push_back(j); });
    }
    std::sort(work.begin(), work.end());
    work.erase(std::unique(work.begin(), work.end()), work.end());
  }
  if (info) *info = done;
  return renumber_surfaces(label, seg.count());
}

}  // namespace splatkit::graph
