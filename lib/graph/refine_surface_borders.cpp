#include "graph/refine_surface_borders.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <vector>

#include "graph/model_surfaces.h"
#include "graph/renumber_surfaces.h"
#include "graph/surface_borders.h"

namespace splatkit::graph {
namespace {

constexpr uint32_t kMaxPasses = 3;
constexpr std::size_t kChunk = 4096;

bool finite(const Vec3f& v) { return std::isfinite(v.x + v.y + v.z); }

struct Rows {
  const NeighborGraph& graph;
  template <class Fn>
  void each(std::size_t i, Fn&& fn) const {
    for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) fn(graph.neighbors[k]);
  }
};

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
        std::span<const uint32_t> label, std::span<const SurfaceModel> models,
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
    bool border = models_[own].state == SurfaceModel::kFragment;
    rows_.each(i, [&](uint32_t j) { border = border || label_[j] != own; });
    if (!border) return own;
    // The modelled surfaces among the splat and its neighbours, with their splats' mean
    // position there (the splat itself left out).
    cands.clear();
    bool unexplained = false;
    auto candidate = [&](uint32_t s) -> Candidate* {
      if (models_[s].state == SurfaceModel::kFragment) return nullptr;
      unexplained = unexplained || models_[s].state == SurfaceModel::kUnexplained;
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
  std::span<const SurfaceModel> models_;
  const RefineBordersOptions& options_;
};

// Rounds of judging, from the border splats: each round judges its splats on the labels it
// started with, then the next judges the splats that changed and their neighbours (a judgement
// reads the labels of the splat and its neighbours, nothing else that changes). Returns every
// splat judged or due to be (ascending): they include every border splat of the new labels.
std::vector<uint32_t> judge_rounds(const Rows& rows, const Judge& judge,
                                   std::vector<uint32_t>& label, std::vector<uint32_t> work,
                                   uint32_t rounds, RefineBordersInfo& info) {
  std::vector<uint32_t> verdict, changed, touched = work, merged;
  for (uint32_t round = 0; round < rounds && !work.empty(); ++round) {
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
    ++info.rounds;
    info.moved += changed.size();
    work.clear();
    for (uint32_t i : changed) {
      work.push_back(i);
      rows.each(i, [&](uint32_t j) { work.push_back(j); });
    }
    std::sort(work.begin(), work.end());
    work.erase(std::unique(work.begin(), work.end()), work.end());
    merged.clear();
    std::set_union(touched.begin(), touched.end(), work.begin(), work.end(),
                   std::back_inserter(merged));
    touched.swap(merged);
  }
  return touched;
}

}  // namespace

Segmentation refine_surface_borders(const NeighborGraph& graph, std::span<const Vec3f> positions,
                                    std::span<const Vec3f> normals, Segmentation seg,
                                    const RefineBordersOptions& options, RefineBordersInfo* info) {
  const std::size_t n = graph.num_points();
  if (positions.size() != n || normals.size() != n || seg.surface.size() != n)
    throw std::invalid_argument("refine_surface_borders: one position, normal and id per splat");
  for (uint32_t s : seg.surface)
    if (s >= seg.count())
      throw std::invalid_argument("refine_surface_borders: surface id out of range");
  RefineBordersInfo done;
  if (options.rounds == 0 || n == 0) {
    if (info) *info = done;
    return seg;
  }
  const Rows rows{graph};
  std::vector<uint32_t> label = std::move(seg.surface);
  uint32_t count = seg.count();
  // A pass that joined or split surfaces changed what the next one fits (the next fit may find
  // more to join); after one that did not, a refit would find the same surfaces.
  SurfaceModels models;
  SurfaceBorders borders = surface_borders(graph, label);
  for (uint32_t pass = 0; pass < kMaxPasses; ++pass) {
    models = model_surfaces(graph, positions, normals, label, count, borders,
                            options.min_surface_size, options.min_normal_dot);
    done.joined += models.joined;
    done.split += models.split;
    if (pass > 0 && models.joined == 0 && models.split == 0) break;
    const Judge judge(rows, positions, normals, label, models.model, options);
    const std::vector<uint32_t> touched =
        judge_rounds(rows, judge, label, borders.splats, options.rounds, done);
    ++done.passes;
    if (models.joined == 0 && models.split == 0) break;
    borders = surface_borders(graph, label, touched);
  }
  for (const SurfaceModel& m : models.model) {
    const bool primitive = m.state == SurfaceModel::kPrimitive;
    done.unexplained += m.state == SurfaceModel::kUnexplained;
    done.planes += primitive && m.primitive.kind == PrimitiveKind::kPlane;
    done.spheres += primitive && m.primitive.kind == PrimitiveKind::kSphere;
    done.cylinders += primitive && m.primitive.kind == PrimitiveKind::kCylinder;
  }
  if (info) *info = done;
  return renumber_surfaces(label, count);
}

}  // namespace splatkit::graph
