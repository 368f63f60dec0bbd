#include "normals/orient_normals_mst.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "normals/layer_cuts.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit {

namespace {

constexpr uint32_t kNone = SpatialIndex::kNone;
constexpr float kParallel = 0.70710678f;  // cos 45°
// Edges between normals within 20° of parallel build the sheets; every other edge is evidence
// between sheets.
constexpr float kSheet = 0.93969262f;  // cos 20°
// With votes or split gaps (the regional method) the sheets are only what is surely one smooth
// piece, within 11.5°: a sheet takes its sign from its first edges, in row order, so one edge
// between two surfaces that should face apart (a thin feature, noise) turns part of a sheet;
// everything else joins by majority. Measured on a real photogrammetry building (CGAL's
// building.ply, 100k points): within 20°, 81.6 % of the points whose reference normals agree
// locally came out right and the result depended on the point order (98.3 % in the file's
// order); within 11.5°, 99.4 % in either order.
constexpr float kRegionSheet = 0.98f;
// In the majority rounds a set's votes count only when they sum to at least this share of its
// points: a few false sightings do not decide a room glimpsed through a gap in its walls, nor the
// bottom face of a part whose splats along a through hole's rim are seen from above (6.6 % of
// that face's points on the CAD part at 20k points; its creases then decide it). 20 % left the
// ground in front of the real building's facade, under its eaves (18 % of it seen, 93 % of its
// votes up), to its creases, which turned it down.
constexpr float kVoteShare = 0.15f;
// Two sets join when the agreement summed over all the edges between them is at least this
// fraction of the summed confidences (a 62.5 % weighted majority) and at least kMinEvidence.
constexpr double kConsensus = 0.25;
constexpr double kMinEvidence = 1.0;
constexpr int kMaxRounds = 32;
// An edge runs across a gap (OrientRegionsOptions::split_gaps) when it makes less than 60° with
// both normals: (n·e)² > kGap² |e|² at both ends.
constexpr float kGap = 0.5f;

// With split gaps, a sheet edge runs oblique when it makes less than ~81° with either normal
// (|n·ê| > kOblique); it then joins only when at least kSheetTriangles points are joined to both
// its ends by sheet edges. On a noisy scan of a thin slab (noise 0.3 of the spacing, the faces
// 1.6 spacings apart) the two faces come within a spacing of each other at the noise's tails,
// and a single edge between them, parallel by its normals and not steep enough to be seen as
// across the gap, would make them one sheet; such an edge has few common neighbours on either
// face. Counted against the reference normals of the scan test set's noisy city
// (scripts/make-scan-set.sh), 10-NN rows: sheet edges between antiparallel reference normals
// 4134 of 1.46 M -> 118 of 0.89 M (without noise, 10 -> 7 of 1.6 M). Measured alternatives that
// separate less, counted without the oblique test: positions denoised (each moved to the mean
// offset of its row's points within half a spacing along its normal: 2959 of 1.64 M), a
// two-cluster split of each row's offsets along the normal (3874, and 8 % of the ground split),
// shared nearest neighbours alone (2518 at >= 5 of 10).
constexpr float kOblique = 0.15f;
constexpr std::size_t kSheetTriangles = 3;

bool oblique(const Vec3f& ni, const Vec3f& nj, const Vec3f& e) {
  const float e2 = squared_norm(e), a = dot(ni, e), b = dot(nj, e);
  return a * a > kOblique * kOblique * e2 || b * b > kOblique * kOblique * e2;
}

bool across_gap(const Vec3f& ni, const Vec3f& nj, const Vec3f& e, float e2) {
  const float a = dot(ni, e), b = dot(nj, e);
  return a * a > kGap * kGap * e2 && b * b > kGap * kGap * e2;
}

// The agreement of a pair's signs: positive when consistently oriented, its magnitude the
// confidence. Normals within 45° of parallel (or antiparallel): Hoppe's n_i·n_j, which the noise
// of the positions does not touch. Normals further apart (a crease, sharp with robust normals):
// n_i·n_j', where n_j' is n_j mirrored in the plane bisecting the edge x_i x_j (König & Gumhold
// 2009); n_i·n_j alone is ~0 across a 90° crease and negative across a 60° wedge's 120° jump
// for a consistent pair, while the mirror image still agrees with n_i. With split_gaps, an edge
// across a gap is measured on the mirror too: there the consistent signs are the opposite ones
// (both sides of a slab face away from each other, two surfaces across a gap face each other).
float agreement(const Vec3f& xi, const Vec3f& ni, const Vec3f& xj, const Vec3f& nj,
                bool split_gaps) {
  const float d = dot(ni, nj);
  const Vec3f e = xj - xi;
  const float e2 = squared_norm(e);
  if (!(e2 > 0)) return d;
  if (std::fabs(d) >= kParallel && !(split_gaps && across_gap(ni, nj, e, e2))) return d;
  return d - 2 * dot(ni, e) * dot(nj, e) / e2;
}

// The two-layer points' faces (layer_cuts.h): whether an edge joins the two faces of a thin wall
// or slab (1), one face (0), or neither end has two layers (-1).
struct Layers {
  std::span<const Vec3f> positions, normals;
  std::vector<float> cut;  // empty: no point has two layers
  std::span<const float> face_cut;  // OrientRegionsOptions::face_cuts
  // Whether either end's own faces put the other end on its other face.
  bool face_apart(uint32_t i, uint32_t j) const {
    if (face_cut.empty()) return false;
    if (std::isfinite(face_cut[i]) &&
        other_layer(face_cut[i], normals[i], positions[i], positions[j]))
      return true;
    return std::isfinite(face_cut[j]) &&
           other_layer(face_cut[j], normals[j], positions[j], positions[i]);
  }
  int apart(uint32_t i, uint32_t j) const {
    if (cut.empty()) return -1;
    if (std::isfinite(cut[i]))
      return other_layer(cut[i], normals[i], positions[i], positions[j]) ? 1 : 0;
    if (std::isfinite(cut[j]))
      return other_layer(cut[j], normals[j], positions[j], positions[i]) ? 1 : 0;
    return -1;
  }
  // As across_gap(), the layers deciding where they are known.
  bool gap(uint32_t i, uint32_t j) const {
    const int a = apart(i, j);
    if (a >= 0) return a == 1;
    const Vec3f e = positions[j] - positions[i];
    return across_gap(normals[i], normals[j], e, squared_norm(e));
  }
  // As agreement() with split gaps; between near-parallel normals on two layers, −n_i·n_j.
  float agree(uint32_t i, uint32_t j) const {
    const int a = apart(i, j);
    const float d = dot(normals[i], normals[j]);
    if (a >= 0 && std::fabs(d) >= kParallel) return a == 1 ? -d : d;
    return agreement(positions[i], normals[i], positions[j], normals[j], true);
  }
};

// The kNN graph with every edge once: row i holds, in rank order, the neighbours j of i whose
// reverse edge j -> i is not in the earlier row j (the agreement is symmetric, so Kruskal would
// meet that one first and always reject this one; in a kNN graph most edges come in such pairs).
// Rows are compacted: row i is neighbors[start[i] .. start[i + 1]). An edge is named by
// (i << shift) | s, s its place in row i.
template <typename Id>
struct KnnGraph {
  unsigned shift = 0;
  std::vector<Id> start;
  ShrinkableArray neighbors{0};
  std::size_t size() const { return start.size() - 1; }
  uint32_t row_size(std::size_t i) const { return static_cast<uint32_t>(start[i + 1] - start[i]); }
};

constexpr std::size_t kRows = 1 << 15;  // rows per task of the passes below

// The rows of the k nearest neighbours (k - 1 besides the point itself), compacted in place.
template <typename Id>
KnnGraph<Id> build_graph(ShrinkableArray nb, std::size_t n, std::size_t k) {
  const std::size_t w = k - 1;
  // Which slots stay, decided on the full rows (read-only, in parallel).
  std::vector<uint8_t> keep(n * w);
  const std::size_t chunks = chunk_count(n, kRows);
  for_each_chunk(n, kRows, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t s = 0; s < w; ++s) {
        const uint32_t j = nb[i * w + s];
        const uint32_t* row = nb.data() + std::size_t{j} * w;
        keep[i * w + s] = j > i || std::find(row, row + w, uint32_t(i)) == row + w;
      }
  });
  // Each chunk compacts its rows within its own range (in parallel), then the chunks move down
  // in order (each lands at or below where it was, past the chunks before it).
  KnnGraph<Id> g;
  g.shift = static_cast<unsigned>(std::bit_width(w));
  g.start.resize(n + 1);
  std::vector<std::size_t> kept(chunks + 1, 0);
  for_each_chunk(n, kRows, [&](std::size_t c, std::size_t begin, std::size_t end) {
    std::size_t at = begin * w;
    for (std::size_t i = begin; i < end; ++i) {
      g.start[i] = static_cast<Id>(at - begin * w);
      for (std::size_t s = 0; s < w; ++s)
        if (keep[i * w + s]) nb[at++] = nb[i * w + s];
    }
    kept[c + 1] = at - begin * w;
  });
  keep = {};
  for (std::size_t c = 0; c < chunks; ++c) {
    std::copy_n(nb.data() + c * kRows * w, kept[c + 1], nb.data() + kept[c]);
    kept[c + 1] += kept[c];
  }
  g.start[n] = static_cast<Id>(kept[chunks]);
  for_each_chunk(n, kRows, [&](std::size_t c, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) g.start[i] += static_cast<Id>(kept[c]);
  });
  nb.shrink(kept[chunks]);
  g.neighbors = std::move(nb);
  return g;
}

// Union-find whose links carry a parity: flip(x) is whether x's sign is the opposite of its set
// root's. Joining two sets along a tree edge sets the parity of the new link so that the edge's
// relation holds; the relation between any two points of a set is then the product of the
// relations along their path in the spanning forest, which is what propagating signs over the
// forest breadth first gives, without storing the forest.
class SignedUnionFind {
 public:
  explicit SignedUnionFind(std::size_t n) : parent_(n), rank_(n, 0), flip_(n, 0) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = static_cast<uint32_t>(i);
  }
  // The root of x's set; `flip` gets x's parity relative to it.
  uint32_t find(uint32_t x, uint8_t& flip) {
    uint8_t acc = 0;
    while (parent_[x] != x) {
      const uint32_t p = parent_[x];
      if (parent_[p] != p) {  // path halving: link x to its grandparent
        flip_[x] ^= flip_[p];
        parent_[x] = parent_[p];
      }
      acc ^= flip_[x];
      x = parent_[x];
    }
    flip = acc;
    return x;
  }
  // Joins the sets of a and b so that b's sign is a's (opposite(): a's negated); false when they
  // were already one set. opposite() is asked only when they were not: most edges Kruskal meets
  // join nothing, and their relation would cost the reads of both points' data.
  template <class Opposite>
  bool unite(uint32_t a, uint32_t b, Opposite&& opposite) {
    uint8_t fa, fb;
    a = find(a, fa), b = find(b, fb);
    if (a == b) return false;
    const bool flip = fa ^ fb ^ (opposite() ? 1 : 0);
    if (rank_[a] < rank_[b]) std::swap(a, b);
    parent_[b] = a;
    flip_[b] = static_cast<uint8_t>(flip);
    if (rank_[a] == rank_[b]) ++rank_[a];
    return true;
  }

 private:
  std::vector<uint32_t> parent_;
  std::vector<uint8_t> rank_, flip_;
};

// The sheet edges of the graph as symmetric adjacency lists (sorted), for counting the common
// neighbours of an edge's two ends.
struct SheetNeighbours {
  std::vector<std::size_t> start;
  std::vector<uint32_t> list;
  std::size_t common(uint32_t i, uint32_t j) const {
    const uint32_t *a = list.data() + start[i], *a_end = list.data() + start[i + 1];
    const uint32_t *b = list.data() + start[j], *b_end = list.data() + start[j + 1];
    std::size_t c = 0;
    while (a < a_end && b < b_end) {
      if (*a < *b) {
        ++a;
      } else if (*b < *a) {
        ++b;
      } else {
        ++c, ++a, ++b;
      }
    }
    return c;
  }
};

template <typename Id, class Passes>
SheetNeighbours sheet_neighbours(const KnnGraph<Id>& g, Passes&& passes) {
  const std::size_t n = g.size();
  SheetNeighbours s;
  s.start.assign(n + 1, 0);
  auto for_each_sheet_edge = [&](auto&& fn) {
    for (std::size_t i = 0; i < n; ++i) {
      const uint32_t* row = g.neighbors.data() + g.start[i];
      for (uint32_t k = 0, m = g.row_size(i); k < m; ++k)
        if (passes(i, row[k])) fn(static_cast<uint32_t>(i), row[k]);
    }
  };
  for_each_sheet_edge([&](uint32_t i, uint32_t j) { ++s.start[i + 1], ++s.start[j + 1]; });
  for (std::size_t i = 0; i < n; ++i) s.start[i + 1] += s.start[i];
  s.list.resize(s.start[n]);
  std::vector<std::size_t> at(s.start.begin(), s.start.end() - 1);
  for_each_sheet_edge([&](uint32_t i, uint32_t j) { s.list[at[i]++] = j, s.list[at[j]++] = i; });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kRows), [&](const auto& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      std::sort(s.list.begin() + static_cast<std::ptrdiff_t>(s.start[i]),
                s.list.begin() + static_cast<std::ptrdiff_t>(s.start[i + 1]));
  });
  return s;
}

// The signed sets in three steps.
// 1. Sheets: Kruskal over the edges whose normals are within 20° of parallel (smooth pieces of
//    surface, where n_i·n_j is reliable), with the signed union-find; at layered points an edge
//    oblique to its normals only when confirmed (kOblique).
// 2. Every other edge between two sets adds its agreement, in the sets' frames, to the evidence
//    between them.
// 3. Pairs of sets join strongest evidence first, with the sign of the summed agreement, and only
//    when it is a clear majority (|Σa| >= kConsensus Σ|a| and >= kMinEvidence).
// Steps 2 and 3 repeat, the sets grown in one round pooling their evidence in the next, until a
// round joins nothing. Sets whose evidence contradicts itself (a T-junction: a sheet that runs on
// past the crease, like ground under a wall or a slab touching a wall, with comparable votes from
// its two sides; noise at a crease) stay apart until then, and are joined last, by the sign of
// their sum, so that each connected component is one set.
// A single edge never decides the sign of a whole sheet: across a crease the mirrored agreement
// of one pair can be ±1 by noise (a point whose robust normal is the other face's, or whose
// offset from its neighbour is mostly noise), and a spanning tree takes exactly such an edge, the
// cheapest, as the only link between two faces.
// With evidence, the virtual point n (its set and parity too) stands for the votes' frame.
template <typename Id>
SignedUnionFind signed_sets(const KnnGraph<Id>& g, std::span<const Vec3f> positions,
                            std::span<const Vec3f> normals, const OrientRegionsOptions& options,
                            const Layers& layers, std::size_t& sheets) {
  const std::size_t n = positions.size();
  const bool votes = !options.evidence.empty();
  const std::size_t nodes = n + (votes ? 1 : 0);
  SignedUnionFind sets(nodes);
  const float sheet = votes || options.split_gaps ? kRegionSheet : kSheet;
  // Step 1, in row order: within 20° the relation is the sign of n_i·n_j whichever edge comes
  // first.
  std::size_t joined = 0;
  auto passes = [&](std::size_t i, uint32_t j) {
    if (std::fabs(dot(normals[i], normals[j])) < sheet) return false;
    if (!options.split_gaps) return true;
    return !layers.gap(static_cast<uint32_t>(i), j) &&
           !layers.face_apart(static_cast<uint32_t>(i), j);
  };
  // With split gaps, an edge at a layered point that runs oblique to its normals joins only when
  // confirmed by kSheetTriangles common neighbours that join both ends (sheet_neighbours).
  const bool confirming = options.split_gaps && !options.layered.empty() &&
                          std::find(options.layered.begin(), options.layered.end(), 1) !=
                              options.layered.end();
  const SheetNeighbours confirm = confirming ? sheet_neighbours(g, passes) : SheetNeighbours{};
  for (std::size_t i = 0; i < n && joined + 1 < nodes; ++i) {
    const uint32_t* row = g.neighbors.data() + g.start[i];
    for (uint32_t s = 0, m = g.row_size(i); s < m; ++s) {
      const uint32_t j = row[s];
      if (!passes(i, j)) continue;
      if (confirming && (options.layered[i] || options.layered[j]) &&
          oblique(normals[i], normals[j], positions[j] - positions[i]) &&
          confirm.common(static_cast<uint32_t>(i), j) < kSheetTriangles)
        continue;
      const float d = dot(normals[i], normals[j]);
      joined += sets.unite(static_cast<uint32_t>(i), j, [&] { return d < 0; });
    }
  }
  sheets = n - std::min(joined, n);
  if (joined + 1 >= nodes) return sets;
  // Each point's set and parity, read off the union-find once per round (n finds, in order,
  // rather than two per edge).
  std::vector<uint32_t> root(nodes);
  std::vector<uint8_t> parity(nodes);
  std::vector<uint32_t> size(votes ? nodes : 0);  // points per set, with votes
  auto read_sets = [&] {
    for (std::size_t i = 0; i < nodes; ++i)
      root[i] = sets.find(static_cast<uint32_t>(i), parity[i]);
    if (votes) {
      std::fill(size.begin(), size.end(), 0);
      for (std::size_t i = 0; i < n; ++i) ++size[root[i]];
    }
  };
  read_sets();
  // The edges between sets, in row order, with their agreements (counted first: no regrowth).
  struct Edge {
    uint32_t i, j;
    float agree;
  };
  auto for_each_between = [&](auto&& fn) {
    for (std::size_t i = 0; i < n; ++i) {
      const uint32_t* row = g.neighbors.data() + g.start[i];
      for (uint32_t s = 0, m = g.row_size(i); s < m; ++s)
        if (root[i] != root[row[s]]) fn(static_cast<uint32_t>(i), row[s]);
    }
  };
  std::size_t count = 0;
  for_each_between([&](uint32_t, uint32_t) { ++count; });
  if (votes)
    for (float v : options.evidence) count += v != 0;
  std::vector<Edge> between;
  between.reserve(count);
  for_each_between([&](uint32_t i, uint32_t j) {
    between.push_back({i, j,
                       options.split_gaps
                           ? layers.agree(i, j)
                           : agreement(positions[i], normals[i], positions[j], normals[j], false)});
  });
  if (votes)
    for (std::size_t i = 0; i < n; ++i)
      if (options.evidence[i] != 0)
        between.push_back(
            {static_cast<uint32_t>(i), static_cast<uint32_t>(n), options.evidence[i]});
  // One round: the agreements summed per pair of sets, in the sets' frames, then the pairs
  // joined strongest sum first, with its sign; with `majority`, only where the sum is a clear
  // majority. Returns the joins.
  struct Link {
    uint32_t a, b;  // set roots, a < b
    float agree, confidence;
    float vote_agree, vote_confidence;  // the votes' part of the two
  };
  std::vector<Link> links;
  links.reserve(count);
  // The votes (edges to the virtual point n) summed per set first, in `between`'s order: one
  // link per voted set rather than one per point to sort.
  std::vector<float> vote_sum(votes ? nodes : 0), vote_abs(votes ? nodes : 0);
  std::vector<uint32_t> voted_sets;
  auto round = [&](bool majority) {
    read_sets();
    links.clear();
    voted_sets.clear();
    std::size_t kept = 0;
    for (const Edge& e : between) {
      const uint32_t ri = root[e.i], rj = root[e.j];
      if (ri == rj) continue;
      between[kept++] = e;
      const float a = parity[e.i] != parity[e.j] ? -e.agree : e.agree;
      if (votes && e.j == n) {
        if (vote_abs[ri] == 0) voted_sets.push_back(ri);
        vote_sum[ri] += a;
        vote_abs[ri] += std::fabs(a);
        continue;
      }
      links.push_back({std::min(ri, rj), std::max(ri, rj), a, std::fabs(a), 0.0f, 0.0f});
    }
    between.resize(kept);
    for (uint32_t r : voted_sets) {
      const uint32_t v = root[n];
      links.push_back({std::min(r, v), std::max(r, v), vote_sum[r], vote_abs[r], vote_sum[r],
                       vote_abs[r]});
      vote_sum[r] = vote_abs[r] = 0;
    }
    // (std::sort is deterministic for a given input: the sums do not depend on the threads.)
    std::sort(links.begin(), links.end(),
              [](const Link& x, const Link& y) { return std::tie(x.a, x.b) < std::tie(y.a, y.b); });
    std::size_t pairs = 0;
    for (std::size_t l = 0; l < links.size();) {
      Link sum = links[l];
      std::size_t m = l + 1;
      for (; m < links.size() && links[m].a == sum.a && links[m].b == sum.b; ++m) {
        sum.agree += links[m].agree;
        sum.confidence += links[m].confidence;
        sum.vote_agree += links[m].vote_agree;
        sum.vote_confidence += links[m].vote_confidence;
      }
      // In the majority rounds a set's votes count only when they sum to kVoteShare of its
      // points; its creases and gaps to the voted set count whatever the votes.
      if (majority && votes && (sum.a == root[n] || sum.b == root[n]) &&
          std::fabs(sum.vote_agree) <
              kVoteShare * static_cast<float>(size[sum.a == root[n] ? sum.b : sum.a])) {
        sum.agree -= sum.vote_agree;
        sum.confidence -= sum.vote_confidence;
      }
      links[pairs++] = sum;
      l = m;
    }
    links.resize(pairs);
    std::sort(links.begin(), links.end(), [](const Link& x, const Link& y) {
      return std::make_tuple(std::fabs(x.agree), x.a, x.b) >
             std::make_tuple(std::fabs(y.agree), y.a, y.b);
    });
    std::size_t joins = 0;
    for (const Link& p : links) {
      const float strength = std::fabs(p.agree);
      if (majority && !(strength >= kConsensus * p.confidence && strength >= kMinEvidence))
        continue;
      joins += sets.unite(p.a, p.b, [&] { return p.agree < 0; });
    }
    return joins;
  };
  for (int r = 0; r < kMaxRounds && !between.empty(); ++r)
    if (round(true) == 0) break;
  if (votes) read_sets();
  if (votes && size[root[n]] < n) {
    // A set the majorities did not join to the votes' frame is one no view sees clearly and no
    // crease ties to what is seen: an enclosed part (the rooms behind a building's walls). Its
    // prior faces its own inside, as a scanner standing in it would see it: each point votes
    // n·(c − p) / |c − p| towards the set's centroid c, summed in the set's frame.
    const uint32_t voted = root[n];
    std::vector<double> sum(n, 0.0);
    std::vector<Vec3f> centre(n, Vec3f{0, 0, 0});
    for (std::size_t i = 0; i < n; ++i)
      if (root[i] != voted) centre[root[i]] += positions[i];
    for (std::size_t i = 0; i < n; ++i) {
      const uint32_t r = root[i];
      if (r == voted || size[r] < 2) continue;
      const Vec3f to = centre[r] * (1.0f / static_cast<float>(size[r])) - positions[i];
      const float l = norm(to);
      if (!(l > 0)) continue;
      const float a = dot(normals[i], to) / l;
      sum[r] += parity[i] ? -a : a;
    }
    for (std::size_t r = 0; r < n; ++r)
      if (root[r] == r && r != voted && sum[r] != 0)
        between.push_back(
            {static_cast<uint32_t>(r), static_cast<uint32_t>(n), static_cast<float>(sum[r])});
  }
  // What the majorities left apart within a connected component joins by the sign of its sum
  // (strongest first): a piece of a surface seeded on its own by its top-most point would face
  // +z, wrong under an object, a coin flip on a wall.
  while (!between.empty())
    if (round(false) == 0) break;
  return sets;
}

// +1 / -1 per point from the sets: the set of the evidence's virtual point n (when `evidence`)
// keeps the signs that agree with it; in every other set, its top-most point (largest z,
// smallest index on ties) points +z and the rest follow their parity relative to it. Returns
// the number of sets (the virtual point's counted as the set of its points).
std::size_t assign_signs(std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                         SignedUnionFind& sets, std::span<const float> evidence,
                         std::vector<int8_t>& sign, OrientStats& stats) {
  const std::size_t n = positions.size();
  std::vector<uint32_t> root(n);
  std::vector<uint8_t> flip(n);
  for (std::size_t i = 0; i < n; ++i) root[i] = sets.find(static_cast<uint32_t>(i), flip[i]);
  uint8_t voted_flip = 0;
  const uint32_t voted = evidence.empty() ? kNone : sets.find(static_cast<uint32_t>(n), voted_flip);
  std::vector<uint32_t> seed(n + 1, kNone);  // per root: its set's top-most point
  std::size_t components = 0;
  for (std::size_t i = 0; i < n; ++i) {
    uint32_t& s = seed[root[i]];
    components += s == kNone;
    if (s == kNone || positions[i].z > positions[s].z) s = static_cast<uint32_t>(i);
  }
  sign.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (root[i] == voted) {
      sign[i] = static_cast<int8_t>(flip[i] == voted_flip ? 1 : -1);
      ++stats.by_evidence;
      stats.against_evidence += evidence[i] * sign[i] < 0;
      continue;
    }
    const uint32_t s = seed[root[i]];
    const bool seed_up = !(normals[s].z < 0);
    sign[i] = static_cast<int8_t>((seed_up != (flip[i] != flip[s])) ? 1 : -1);
  }
  return components;
}

// The regional method's last pass: a point whose signed agreements with its graph neighbours
// (under the signs found; n_i·n_j alone, which position noise does not touch, and no edge across
// a gap) sum to less than −1/2 of their magnitudes is turned to follow them. A point whose every
// edge runs across a gap follows those edges instead, read as one surface: it is a noise tail off
// a surface (on the noisy CAD part, a point 4 σ above a face, each of its 9 nearest 0.5-0.9 of
// its distance along the normal), not a face of a slab of its own, which would have neighbours
// on that face.
// The sheets grow within 11.5° only, so a point whose noisy normal left it a set of its own
// takes its sign from its few edges in the rounds, and a vote or an edge of noise can decide it
// against all of its neighbours (80 of 50k points on a noisy scan-line cube). Signs are read
// before the pass and written after it: independent of the order. Returns how many turned.
template <typename Id>
std::size_t follow_neighbours(const KnnGraph<Id>& g, std::span<const Vec3f> positions,
                              std::span<const Vec3f> normals, bool split_gaps,
                              const Layers& layers, std::vector<int8_t>& sign) {
  const std::size_t n = positions.size();
  // Per point: summed agreement and magnitude over the edges on its surface, then across gaps.
  std::vector<std::array<float, 4>> sums(n, std::array<float, 4>{});
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t* row = g.neighbors.data() + g.start[i];
    for (uint32_t s = 0, m = g.row_size(i); s < m; ++s) {
      const uint32_t j = row[s];
      std::size_t at = 0;
      if (split_gaps && layers.gap(static_cast<uint32_t>(i), j))
        at = 2;  // the two sides of a thin wall face apart: not one surface
      const float a = dot(normals[i], normals[j]) * static_cast<float>(sign[i] * sign[j]);
      for (const std::size_t p : {i, std::size_t{j}}) {
        sums[p][at] += a;
        sums[p][at + 1] += std::fabs(a);
      }
    }
  }
  std::size_t turned = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t at = sums[i][1] > 0 ? 0 : 2;
    if (sums[i][at] < -0.5f * sums[i][at + 1]) {
      sign[i] = static_cast<int8_t>(-sign[i]);
      ++turned;
    }
  }
  return turned;
}

// Each layered point whose graph neighbours on its own layer agree (the length of the sum of
// their oriented normals at least half their count) and whose own normal lies more than 18° from
// that sum takes the sum's direction, signed so that `sign` gives it back: at a crease or a thin
// edge its PCA normal is a blend of the faces and can lie more than 90° from its own face's,
// while its neighbours' mean, in the frame the orientation has just fixed, lies within 90° of
// each face it joins. On the scan set (scripts/make-scan-set.sh) wrong-signed normals: noisy
// scan-line CAD part 14 -> 7, noisy stratified one 10 -> 1, noisy city 1 835 -> 1 217 (walls out
// 98.90 -> 99.39 %). Points within 18° keep theirs: settling every layered point fixed as many
// signs but rounded more creases (1 % more normals more than 30° off on the noisy scan-line city);
// 30° left 10 wrong on the CAD part. The sums are in fixed point, so a tile's run, whose graph
// lists the same neighbours in another order, gives the same bits. Read before, written after.
// Returns how many.
template <typename Id>
std::size_t settle_layered(const KnnGraph<Id>& g, std::span<Vec3f> normals,
                           std::span<const uint8_t> layered, const Layers& layers,
                           const std::vector<int8_t>& sign) {
  constexpr double kFixed = 0x1p40;    // fixed-point scale of the sums
  constexpr double kSettleCos = 0.95;  // cos 18°
  const std::size_t n = normals.size();
  std::vector<std::array<int64_t, 3>> sum(n, std::array<int64_t, 3>{});
  std::vector<uint32_t> count(n, 0);
  const auto add = [&](std::size_t to, std::size_t from) {
    const double s = sign[from];
    const Vec3f& v = normals[from];
    sum[to][0] += static_cast<int64_t>(s * v.x * kFixed);
    sum[to][1] += static_cast<int64_t>(s * v.y * kFixed);
    sum[to][2] += static_cast<int64_t>(s * v.z * kFixed);
    ++count[to];
  };
  for (std::size_t i = 0; i < n; ++i) {
    const uint32_t* row = g.neighbors.data() + g.start[i];
    for (uint32_t s = 0, m = g.row_size(i); s < m; ++s) {
      const uint32_t j = row[s];
      if (!layered[i] && !layered[j]) continue;
      if (layers.apart(static_cast<uint32_t>(i), j) == 1) continue;  // the other face of a slab
      if (layered[i]) add(i, j);
      if (layered[j]) add(j, i);
    }
  }
  std::size_t settled = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!layered[i] || count[i] == 0) continue;
    const double x = static_cast<double>(sum[i][0]) / kFixed,
                 y = static_cast<double>(sum[i][1]) / kFixed,
                 z = static_cast<double>(sum[i][2]) / kFixed;
    const double length = std::sqrt(x * x + y * y + z * z);
    if (!(length >= 0.5 * count[i])) continue;
    const double own = sign[i] * (normals[i].x * x + normals[i].y * y + normals[i].z * z) / length;
    if (own >= kSettleCos) continue;
    const double f = sign[i] / length;
    normals[i] =
        Vec3f{static_cast<float>(x * f), static_cast<float>(y * f), static_cast<float>(z * f)};
    ++settled;
  }
  return settled;
}

}  // namespace

void index_knn_rows(const SpatialIndex& index, std::size_t k, std::span<uint32_t> out) {
  const std::size_t w = k - 1;
  index.for_each_knn_block(k, [&](std::span<const uint32_t> queries,
                                  std::span<const uint32_t> indices, std::span<const float>) {
    for (std::size_t r = 0; r < queries.size(); ++r)  // column 0 is the point itself
      std::copy_n(indices.data() + r * k + 1, w, out.data() + queries[r] * w);
  });
}

ShrinkableArray orient_knn_rows(const KnnRowsFn& rows, std::size_t n, std::size_t k) {
  if (k < 2) throw std::invalid_argument("orient_normals_mst: k must be at least 2");
  k = std::min(k, n);
  ShrinkableArray out(n * (k > 0 ? k - 1 : 0));  // every slot is written by rows: k <= n
  if (k > 1) rows(k, std::span<uint32_t>(out.data(), out.size()));
  return out;
}

OrientStats orient_normals_mst(SpatialIndex index, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k) {
  if (index.size() != positions.size())
    throw std::invalid_argument("orient_normals_mst: positions and index differ in size");
  ShrinkableArray rows = orient_knn_rows(
      [&](std::size_t row_k, std::span<uint32_t> out) { index_knn_rows(index, row_k, out); },
      positions.size(), k);
  index = SpatialIndex();  // released before the graph's peak
  return orient_normals_mst(std::move(rows), positions, normals, k);
}

OrientStats orient_normals_mst(const KnnRowsFn& rows, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k) {
  return orient_normals_mst(orient_knn_rows(rows, positions.size(), k), positions, normals, k);
}

OrientStats orient_normals_mst(ShrinkableArray rows, std::span<const Vec3f> positions,
                               std::span<Vec3f> normals, std::size_t k,
                               const OrientRegionsOptions& regions) {
  if (k < 2) throw std::invalid_argument("orient_normals_mst: k must be at least 2");
  const std::size_t n = positions.size();
  if (normals.size() != n)
    throw std::invalid_argument("orient_normals_mst: positions and normals differ in size");
  if (rows.size() != n * (std::min(k, n) > 0 ? std::min(k, n) - 1 : 0))
    throw std::invalid_argument("orient_normals_mst: the kNN rows do not match the points");
  if (!regions.evidence.empty() && regions.evidence.size() != n)
    throw std::invalid_argument("orient_normals_mst: evidence and positions differ in size");
  if (!regions.face_cuts.empty() && regions.face_cuts.size() != n)
    throw std::invalid_argument("orient_normals_mst: face_cuts and positions differ in size");
  if (!regions.layered.empty() && regions.layered.size() != n)
    throw std::invalid_argument("orient_normals_mst: layered and positions differ in size");
  OrientStats stats;
  if (n == 0) return stats;

  Layers layers{positions, normals, {}};
  if (regions.split_gaps && regions.blended_layers &&
      std::find(regions.layered.begin(), regions.layered.end(), 1) != regions.layered.end())
    layers.cut = layer_cuts(positions, normals, std::span<const uint32_t>(rows.data(), rows.size()),
                            std::min(k, n) - 1, regions.layered);
  if (regions.split_gaps) layers.face_cut = regions.face_cuts;
  // 32-bit edge names and row starts while (n << shift) fits, which also bounds the edges.
  std::vector<int8_t> sign;
  auto forest = [&]<typename Id>(Id) {
    const KnnGraph<Id> graph = build_graph<Id>(std::move(rows), n, std::min(k, n));
    SignedUnionFind sets = signed_sets<Id>(graph, positions, normals, regions, layers, stats.sheets);
    stats.components = assign_signs(positions, normals, sets, regions.evidence, sign, stats);
    if (!regions.evidence.empty() || regions.split_gaps)
      stats.relabelled =
          follow_neighbours(graph, positions, normals, regions.split_gaps, layers, sign);
    if (regions.blended_layers &&
        std::find(regions.layered.begin(), regions.layered.end(), 1) != regions.layered.end())
      stats.settled = settle_layered(graph, normals, regions.layered, layers, sign);
  };
  const std::size_t width = std::min(k, n) - 1;
  if ((uint64_t{n} << std::bit_width(width)) <= std::numeric_limits<uint32_t>::max())
    forest(uint32_t{});
  else
    forest(uint64_t{});
  for (std::size_t i = 0; i < n; ++i) {
    if (sign[i] < 0) {
      normals[i] = -normals[i];
      ++stats.flipped;
    }
  }
  return stats;
}

}  // namespace splatkit
