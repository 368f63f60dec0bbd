#include "graph/model_surfaces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "graph/lowest_root_union_find.h"
#include "graph/plane_residual_scale.h"
#include "graph/surface_borders.h"
#include "graph/surface_members.h"
#include "splatkit/pca_normal.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kMaxFitPoints = 4096;  // splats a surface's primitive is fitted to
constexpr std::size_t kScaleSamples = 512;   // splats its local noise is measured on
constexpr int kMaxSplitDepth = 3;

bool finite(const Vec3f& v) { return std::isfinite(v.x + v.y + v.z); }

// Every step-th member, so that at most `limit` remain (evenly spread over the indices).
std::vector<uint32_t> spread(std::span<const uint32_t> members, std::size_t limit) {
  const std::size_t step = std::max<std::size_t>(1, (members.size() + limit - 1) / limit);
  std::vector<uint32_t> out;
  for (std::size_t k = 0; k < members.size(); k += step) out.push_back(members[k]);
  return out;
}

struct Input {
  const NeighborGraph& graph;
  std::span<const Vec3f> positions, normals;
  uint32_t min_surface_size;
  float min_normal_dot;

  template <class Fn>
  void row(std::size_t i, Fn&& fn) const {
    for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) fn(graph.neighbors[k]);
  }
  // Whether the model's primitive explains splat i.
  bool explains(const SurfaceModel& m, uint32_t i) const {
    const Vec3d p = to_vec3d(positions[i]);
    const bool facing = !finite(normals[i]) ||
                        dot(m.primitive.normal_at(p), to_vec3d(normals[i])) >= min_normal_dot;
    return facing && m.primitive.distance(p) <= m.tolerance;
  }
};

// Noise of a surface's splats about planes through their neighbours on the same surface (each
// splat left out of its own plane): 1.4826 × the median residual over up to kScaleSamples
// members; infinity when no member has 5 such neighbours.
double local_scale(const Input& in, std::span<const uint32_t> label,
                   std::span<const uint32_t> members) {
  PlaneResidualScale scale;
  for (uint32_t i : spread(members, kScaleSamples)) {
    const Vec3d p = to_vec3d(in.positions[i]);
    in.row(i, [&](uint32_t j) {
      if (label[j] == label[i]) scale.add(to_vec3d(in.positions[j]) - p);
    });
    scale.close();
  }
  return scale.scale();
}

// The surface's model: kPrimitive when its primitive explains it; kUnexplained otherwise, with
// the primitive and tolerance of the fit kept (for splitting) when there is one.
SurfaceModel fit_model(const Input& in, std::span<const uint32_t> label,
                       std::span<const uint32_t> members) {
  SurfaceModel model;
  model.state = SurfaceModel::kUnexplained;
  const std::vector<uint32_t> sample = spread(members, kMaxFitPoints);
  model.primitive = fit_surface_primitive(in.positions, in.normals, sample);
  if (model.primitive.kind == PrimitiveKind::kNone) return model;
  Vec3d lo = to_vec3d(in.positions[sample[0]]), hi = lo;
  for (uint32_t i : sample) {
    const Vec3d p = to_vec3d(in.positions[i]);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double floor = 1e-5 * norm(hi - lo);
  const double scale = std::max(model.primitive.scale, floor);
  model.tolerance = 3 * scale;
  std::size_t inliers = 0;
  for (uint32_t i : sample)
    inliers += model.primitive.distance(to_vec3d(in.positions[i])) <= 3 * scale;
  // A leaked surface has a majority face that the robust fit follows and a minority it does
  // not explain: the inlier count catches it where the scale (a median) does not.
  if (scale <= 2 * local_scale(in, label, members) + floor &&
      inliers >= 0.9 * double(sample.size()))
    model.state = SurfaceModel::kPrimitive;
  return model;
}

// Step 2: splits unexplained surfaces into the pieces their primitives explain.
class Splitter {
 public:
  Splitter(const Input& in, std::vector<uint32_t>& label, uint32_t& label_count,
           std::vector<SurfaceModel>& models)
      : in_(in), label_(label), count_(label_count), models_(models) {}

  // Splits surface s (its members, its unexplained model) if it is a union of explained
  // pieces; else leaves everything as it was. Returns whether it split.
  bool split(uint32_t s, const std::vector<uint32_t>& members, int depth = 0) {
    const SurfaceModel whole = models_[s];  // a copy: models_ grows below
    if (depth >= kMaxSplitDepth || whole.primitive.kind == PrimitiveKind::kNone) return false;
    std::vector<uint32_t> held, rest;
    for (uint32_t i : members) (in_.explains(whole, i) ? held : rest).push_back(i);
    if (2 * held.size() < members.size() || rest.size() < in_.min_surface_size) return false;
    const uint32_t count_before = count_;
    const std::size_t models_before = models_.size();
    bool ok = true;
    for (const std::vector<uint32_t>& piece : pieces(rest)) {
      const uint32_t t = count_++;
      for (uint32_t i : piece) label_[i] = t;
      models_.push_back({});
      if (piece.size() < in_.min_surface_size) continue;  // a fragment, for the rounds
      models_[t] = fit_model(in_, label_, piece);
      if (models_[t].state != SurfaceModel::kPrimitive && !split(t, piece, depth + 1)) {
        ok = false;
        break;
      }
    }
    if (ok) {
      models_[s] = fit_model(in_, label_, held);
      ok = models_[s].state == SurfaceModel::kPrimitive;
    }
    if (!ok) {
      for (uint32_t i : members) label_[i] = s;
      models_[s] = whole;
      models_.resize(models_before);
      count_ = count_before;
    }
    return ok;
  }

 private:
  // The connected pieces of `splats` (ascending) over the edges between them, each ascending,
  // in the order of their lowest splat.
  std::vector<std::vector<uint32_t>> pieces(const std::vector<uint32_t>& splats) {
    if (parent_.empty()) parent_.resize(label_.size()), slot_.assign(label_.size(), kNotInSet);
    for (uint32_t i : splats) parent_[i] = i, slot_[i] = kInSet;
    for (uint32_t i : splats)
      in_.row(i, [&](uint32_t j) {
        if (j > i && slot_[j] != kNotInSet) unite(parent_, i, j);
      });
    // A root is its piece's lowest splat, so it comes before the rest of its piece.
    std::vector<std::vector<uint32_t>> out;
    for (uint32_t i : splats) {
      const uint32_t r = find_root(parent_, i);
      if (r == i) {
        slot_[i] = uint32_t(out.size());
        out.emplace_back();
      }
      out[slot_[r]].push_back(i);
    }
    for (uint32_t i : splats) slot_[i] = kNotInSet;
    return out;
  }

  static constexpr uint32_t kNotInSet = 0xFFFFFFFFu, kInSet = 0xFFFFFFFEu;
  const Input& in_;
  std::vector<uint32_t>& label_;
  uint32_t& count_;
  std::vector<SurfaceModel>& models_;
  std::vector<uint32_t> parent_;  // union-find over the splats of one split (made on first use)
  std::vector<uint32_t> slot_;    // kNotInSet outside the split; a root's piece
};

// Step 3: the label each surface's splats take (its own, or the larger neighbour whose
// primitive explains most of it), following chains to their end.
std::vector<uint32_t> joins(const Input& in, const std::vector<SurfaceModel>& models,
                            const SurfaceMembers& groups, std::span<const uint64_t> pairs) {
  const uint32_t count = uint32_t(models.size());
  auto size = [&](uint32_t s) { return groups.of(s).size(); };
  std::vector<double> fraction(pairs.size(), 0);
  tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t k) {
    const uint32_t f = uint32_t(pairs[k] >> 32), s = uint32_t(pairs[k]);
    if (models[f].state == SurfaceModel::kFragment || models[s].state != SurfaceModel::kPrimitive)
      return;
    if (size(s) < size(f) || (size(s) == size(f) && s > f)) return;
    std::size_t total = 0, near = 0;
    for (uint32_t i : spread(groups.of(f), kMaxFitPoints))
      near += in.explains(models[s], i), ++total;
    fraction[k] = double(near) / double(total);
  });
  std::vector<uint32_t> into(count);
  std::vector<double> best(count, 0.5);
  for (uint32_t s = 0; s < count; ++s) into[s] = s;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const uint32_t f = uint32_t(pairs[k] >> 32), s = uint32_t(pairs[k]);
    if (fraction[k] > best[f] ||
        (fraction[k] == best[f] && into[f] != f && size(s) > size(into[f])))
      into[f] = s, best[f] = fraction[k];
  }
  // The one that explains may join another in turn (always a larger one: chains end).
  for (uint32_t s = 0; s < count; ++s) {
    uint32_t t = s;
    while (into[t] != t) t = into[t];
    into[s] = t;
  }
  return into;
}

}  // namespace

SurfaceModels model_surfaces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                             std::span<const Vec3f> normals, std::vector<uint32_t>& label,
                             uint32_t& label_count, SurfaceBorders& borders,
                             uint32_t min_surface_size, float min_normal_dot) {
  const Input in{graph, positions, normals, min_surface_size, min_normal_dot};
  SurfaceModels out;
  std::vector<SurfaceModel>& models = out.model;
  SurfaceMembers groups = surface_members(label, label_count);
  models.assign(label_count, {});
  tbb::parallel_for(uint32_t{0}, label_count, [&](uint32_t s) {
    if (groups.of(s).size() >= min_surface_size) models[s] = fit_model(in, label, groups.of(s));
  });

  const uint32_t fitted = label_count;
  Splitter splitter(in, label, label_count, models);
  for (uint32_t s = 0; s < fitted; ++s) {
    if (models[s].state != SurfaceModel::kUnexplained) continue;
    const std::span<const uint32_t> m = groups.of(s);
    out.split += splitter.split(s, std::vector<uint32_t>(m.begin(), m.end()));
  }
  if (out.split > 0) {
    groups = surface_members(label, label_count);
    borders = surface_borders(graph, label);
  }

  const std::vector<uint32_t> into = joins(in, models, groups, borders.pairs);
  for (uint32_t s = 0; s < label_count; ++s)
    if (into[s] != s) {
      models[s] = {};
      out.joined += !groups.of(s).empty();
    }
  if (out.joined > 0) {
    for (uint32_t& s : label) s = into[s];
    borders = surface_borders(graph, label, borders.splats);  // joining makes no new border
  }
  return out;
}

}  // namespace splatkit::graph
