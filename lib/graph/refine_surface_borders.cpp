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
#include "splatkit/for_each_chunk.h"
#include "splatkit/pca_normal.h"

namespace splatkit::graph {
namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;
constexpr std::size_t kMaxFitPoints = 16384;  // members a primitive is fitted to, evenly spaced
constexpr std::size_t kScaleSamples = 512;    // members the local noise scale is measured on
constexpr std::size_t kChunk = 4096;

bool finite(const Vec3f& v) { return std::isfinite(v.x + v.y + v.z); }

// Weighted sums of positions (relative to an origin near them) and normals: a plane by PCA.
struct Moments {
  double w = 0;
  Vec3d s, n;
  std::array<double, 6> ss{};

  void add(const Vec3d& d, const Vec3f& normal) {
    w += 1;
    s += d;
    ss[0] += d.x * d.x, ss[1] += d.x * d.y, ss[2] += d.x * d.z;
    ss[3] += d.y * d.y, ss[4] += d.y * d.z, ss[5] += d.z * d.z;
    if (finite(normal)) n += to_vec3d(normal);
  }
};

struct Plane {
  Vec3d c, n;  // centroid (relative to the moments' origin), unit normal along the mean normal
};

Plane plane_of(const Moments& m) {
  const Vec3d c = m.s / m.w;
  const std::array<double, 6> cov{m.ss[0] / m.w - c.x * c.x, m.ss[1] / m.w - c.x * c.y,
                                  m.ss[2] / m.w - c.x * c.z, m.ss[3] / m.w - c.y * c.y,
                                  m.ss[4] / m.w - c.y * c.z, m.ss[5] / m.w - c.z * c.z};
  const std::array<double, 3> e = pca_normal(cov).normal;
  Vec3d n{e[0], e[1], e[2]};
  if (dot(n, m.n) < 0) n = -n;
  return {c, n};
}

struct Rows {
  const NeighborGraph& graph;
  template <class Fn>
  void each(std::size_t i, Fn&& fn) const {
    for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) fn(graph.neighbors[k]);
  }
};

// The geometry a surface is judged by: its primitive when one explains it, else planes fitted
// to its splats around each splat in question.
struct Model {
  bool exists = false;  // a surface of at least min_surface_size splats
  SurfacePrimitive primitive;
  double tolerance = 0;  // primitive: 3 robust scales (at least a rounding floor)
  bool local() const { return primitive.kind == PrimitiveKind::kNone; }
};

// Noise of the surface's splats about planes fitted to their same-surface neighbours (each
// splat left out of its own fit), 1.4826 × median residual over up to kScaleSamples members.
double local_scale(const Rows& rows, std::span<const Vec3f> positions,
                   std::span<const Vec3f> normals, std::span<const uint32_t> label,
                   std::span<const uint32_t> members) {
  const std::size_t step = std::max<std::size_t>(1, members.size() / kScaleSamples);
  std::vector<double> r;
  for (std::size_t k = 0; k < members.size(); k += step) {
    const uint32_t i = members[k];
    const Vec3d p = to_vec3d(positions[i]);
    Moments m;
    rows.each(i, [&](uint32_t j) {
      if (label[j] == label[i]) m.add(to_vec3d(positions[j]) - p, normals[j]);
    });
    if (m.w < 5) continue;
    const Plane pl = plane_of(m);
    r.push_back(std::abs(dot(pl.c, pl.n)));
  }
  if (r.empty()) return std::numeric_limits<double>::infinity();
  auto mid = r.begin() + r.size() / 2;
  std::nth_element(r.begin(), mid, r.end());
  return 1.4826 * *mid;
}

Model fit_model(const Rows& rows, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                std::span<const uint32_t> label, std::span<const uint32_t> members) {
  Model model;
  model.exists = true;
  std::vector<uint32_t> sample;
  const std::size_t step = (members.size() + kMaxFitPoints - 1) / kMaxFitPoints;
  for (std::size_t k = 0; k < members.size(); k += step) sample.push_back(members[k]);
  SurfacePrimitive f = fit_surface_primitive(positions, normals, sample);
  if (f.kind == PrimitiveKind::kNone) return model;
  // Explained: the primitive is about as close to the splats as local planes are, for nearly
  // all of them (a surface that leaked over a crease has a majority face the robust fit
  // follows, and a minority it does not explain).
  Vec3d lo = to_vec3d(positions[members[0]]), hi = lo;
  std::size_t inliers = 0;
  for (uint32_t i : sample) {
    const Vec3d p = to_vec3d(positions[i]);
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double floor = 1e-5 * norm(hi - lo);
  const double scale = std::max(f.scale, floor);
  for (uint32_t i : sample) inliers += f.distance(to_vec3d(positions[i])) <= 3 * scale;
  const double local = local_scale(rows, positions, normals, label, members);
  if (scale <= 2 * local + floor && inliers >= 0.9 * double(sample.size())) {
    model.primitive = f;
    model.tolerance = 3 * scale;
  }
  return model;
}

// Every pair (a, b) of different surfaces joined by an edge, as a << 32 | b, ascending.
std::vector<uint64_t> adjacent_surfaces(const NeighborGraph& graph,
                                        std::span<const uint32_t> label) {
  const std::size_t n = graph.num_points();
  std::vector<std::vector<uint64_t>> parts(chunk_count(n, kChunk));
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::vector<uint64_t>& out = parts[c];
    for (std::size_t i = begin; i < end; ++i)
      for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
        const uint32_t a = label[i], b = label[graph.neighbors[k]];
        if (a != b) out.push_back(uint64_t{a} << 32 | b);
      }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  });
  std::vector<uint64_t> pairs;
  for (const auto& p : parts) pairs.insert(pairs.end(), p.begin(), p.end());
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

// Whether the primitive of surface `by` explains at least half of `members` (within its
// tolerance, normals compatible).
bool explains(const Model& by, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
              std::span<const uint32_t> members, float min_normal_dot) {
  const std::size_t step = (members.size() + kMaxFitPoints - 1) / kMaxFitPoints;
  std::size_t total = 0, near = 0;
  for (std::size_t k = 0; k < members.size(); k += step, ++total) {
    const uint32_t i = members[k];
    const Vec3d p = to_vec3d(positions[i]);
    const bool facing = !finite(normals[i]) ||
                        dot(by.primitive.normal_at(p), to_vec3d(normals[i])) >= min_normal_dot;
    near += facing && by.primitive.distance(p) <= by.tolerance;
  }
  return 2 * near >= total;
}

struct Candidate {
  uint32_t surface = kNone;
  double signed_distance = 0;  // > 0 on the side the surface's normals point to
  Vec3d normal;                // the surface's unit normal at the splat
  Vec3d centroid;              // of the surface's splats among the neighbours (relative to p)
  bool has_centroid = false;
};

// The one thing every round does: where splat i belongs given the current labels.
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

  // The label splat i should have; its own when it is not on a border.
  uint32_t operator()(uint32_t i, std::vector<Candidate>& cands) const {
    const uint32_t own = label_[i];
    bool border = !models_[own].exists;
    cands.clear();
    auto consider = [&](uint32_t s) {
      for (const Candidate& c : cands)
        if (c.surface == s) return;
      if (models_[s].exists) cands.push_back({s});
    };
    consider(own);
    rows_.each(i, [&](uint32_t j) {
      border = border || label_[j] != own;
      consider(label_[j]);
    });
    if (!border) return own;
    const Vec3d p = to_vec3d(positions_[i]);
    std::size_t kept = 0;
    for (Candidate c : cands)
      if (measure(i, p, c)) cands[kept++] = c;
    cands.resize(kept);
    if (cands.empty()) return own;
    return choose(own, cands);
  }

 private:
  bool measure(uint32_t i, const Vec3d& p, Candidate& c) const {
    const uint32_t s = c.surface;
    Moments near;  // the surface's splats among i's neighbours
    rows_.each(i, [&](uint32_t j) {
      if (label_[j] == s) near.add(to_vec3d(positions_[j]) - p, normals_[j]);
    });
    if (near.w > 0) {
      c.centroid = near.s / near.w;
      c.has_centroid = true;
    }
    const Model& m = models_[s];
    if (!m.local()) {
      c.signed_distance = m.primitive.signed_distance(p);
      c.normal = m.primitive.normal_at(p);
    } else {
      // A plane through the surface's splats within two hops of i (i left out; a splat reached
      // by several paths counts that many times, which weights the fit towards i).
      Moments ring;
      rows_.each(i, [&](uint32_t k) {
        if (label_[k] == s) ring.add(to_vec3d(positions_[k]) - p, normals_[k]);
        rows_.each(k, [&](uint32_t l) {
          if (l != i && label_[l] == s) ring.add(to_vec3d(positions_[l]) - p, normals_[l]);
        });
      });
      if (ring.w < 6) return false;
      const Plane pl = plane_of(ring);
      c.signed_distance = -dot(pl.c, pl.n);
      c.normal = pl.n;
    }
    const Vec3f& n = normals_[i];
    return !finite(n) || dot(c.normal, to_vec3d(n)) >= options_.min_normal_dot;
  }

  // The nearest surface, except across a crease whose convexity says otherwise: at a convex
  // crease a true splat of A lies inside B's half-space (beneath B's extension) whatever its
  // noise, so the surface with the larger signed distance wins; at a concave one, the smaller.
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
      if (!a.has_centroid || !b.has_centroid) continue;
      const Vec3d ab = b.centroid - a.centroid;
      const double len = norm(ab);
      if (!(len > 0)) continue;
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

  // Members of every surface, in index order (counting sort).
  std::vector<uint64_t> start(seg.count() + 1, 0);
  for (uint32_t s : label) ++start[s + 1];
  for (std::size_t s = 0; s < seg.count(); ++s) start[s + 1] += start[s];
  std::vector<uint32_t> members(n);
  {
    std::vector<uint64_t> at(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) members[at[label[i]]++] = uint32_t(i);
  }
  std::vector<Model> models(seg.count());
  tbb::parallel_for(uint32_t{0}, seg.count(), [&](uint32_t s) {
    if (seg.sizes[s] < options.min_surface_size) return;
    models[s] = fit_model(rows, positions, normals, label,
                          std::span(members).subspan(start[s], seg.sizes[s]));
  });
  // A surface that a larger neighbour's primitive explains is a fragment of it (a strip of
  // splats with wild normals along a crease, an island of agreeing normals): it keeps no model
  // and its splats are judged one by one.
  const std::vector<uint64_t> pairs = adjacent_surfaces(graph, label);
  std::vector<uint8_t> absorbed(pairs.size());
  tbb::parallel_for(std::size_t{0}, pairs.size(), [&](std::size_t k) {
    const uint32_t f = uint32_t(pairs[k] >> 32), s = uint32_t(pairs[k]);
    if (!models[f].exists || !models[s].exists || models[s].local()) return;
    if (seg.sizes[s] < seg.sizes[f] || (seg.sizes[s] == seg.sizes[f] && s > f)) return;
    absorbed[k] =
        explains(models[s], positions, normals, std::span(members).subspan(start[f], seg.sizes[f]),
                 options.min_normal_dot);
  });
  for (std::size_t k = 0; k < pairs.size(); ++k)
    if (absorbed[k]) models[pairs[k] >> 32] = Model{};
  for (const Model& m : models) {
    done.primitives += m.exists && !m.local();
    done.local += m.exists && m.local();
  }

  // Round 1 judges every splat; later rounds only those within two hops of a change (a
  // judgement reads the labels two hops out).
  std::vector<uint32_t> work(n), next;
  for (std::size_t i = 0; i < n; ++i) work[i] = uint32_t(i);
  const Judge judge(rows, positions, normals, label, models, options);
  std::vector<uint32_t> verdict;
  for (uint32_t round = 0; round < options.rounds && !work.empty(); ++round) {
    verdict.resize(work.size());
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, work.size(), kChunk),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        std::vector<Candidate> cands;
                        for (std::size_t k = r.begin(); k < r.end(); ++k)
                          verdict[k] = judge(work[k], cands);
                      });
    next.clear();
    for (std::size_t k = 0; k < work.size(); ++k) {
      if (verdict[k] == label[work[k]]) continue;
      label[work[k]] = verdict[k];
      next.push_back(work[k]);
    }
    ++done.rounds;
    done.moved += next.size();
    const std::size_t changed = next.size();
    for (int hop = 0; hop < 2; ++hop) {
      const std::size_t end = next.size();
      for (std::size_t k = 0; k < end; ++k)
        rows.each(next[k], [&](uint32_t j) { next.push_back(j); });
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
    }
    if (changed == 0) next.clear();
    work.swap(next);
  }
  if (info) *info = done;
  return renumber_surfaces(label, seg.count());
}

}  // namespace splatkit::graph
