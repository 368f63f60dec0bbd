#include "render/occlusion_culler.h"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "splatkit/error.h"
#include "splatkit/seconds_since.h"

namespace splatkit::render {

OcclusionMode parse_occlusion_mode(const std::string& name) {
  if (name == "none") return OcclusionMode::kNone;
  if (name == "frustum") return OcclusionMode::kFrustum;
  if (name == "hierarchical") return OcclusionMode::kHierarchical;
  if (name == "chc") return OcclusionMode::kChc;
  if (name == "chc++") return OcclusionMode::kChcPlusPlus;
  throw_usage("--occlusion must be none, frustum, hierarchical, chc or chc++, got '" + name + "'");
}

const char* occlusion_mode_name(OcclusionMode m) {
  switch (m) {
    case OcclusionMode::kNone:
      return "none";
    case OcclusionMode::kFrustum:
      return "frustum";
    case OcclusionMode::kHierarchical:
      return "hierarchical";
    case OcclusionMode::kChc:
      return "chc";
    case OcclusionMode::kChcPlusPlus:
      return "chc++";
  }
  return "none";
}

void OcclusionStats::add(const OcclusionStats& o) {
  nodes_traversed += o.nodes_traversed;
  queries += o.queries;
  multiqueries += o.multiqueries;
  multiquery_nodes += o.multiquery_nodes;
  culled_frustum += o.culled_frustum;
  culled_occlusion += o.culled_occlusion;
  leaves_drawn += o.leaves_drawn;
  splats_drawn += o.splats_drawn;
  traversal_s += o.traversal_s;
  query_s += o.query_s;
  depth_s += o.depth_s;
  splats_culled += o.splats_culled;
  splat_test_s += o.splat_test_s;
}

namespace {

// The descendants (up to 3 levels down) whose boxes bound a node more tightly than its own box:
// refined a level at a time while their summed area stays within 1.4 × the node's.
std::vector<uint32_t> tight_set(const ChunkBvh& bvh, uint32_t node) {
  std::vector<uint32_t> set{node};
  const float limit = 1.4f * bvh.nodes[node].box.area();
  for (int level = 0; level < 3; ++level) {
    std::vector<uint32_t> next;
    float area = 0;
    for (uint32_t n : set) {
      const ChunkBvhNode& x = bvh.nodes[n];
      if (x.leaf) {
        next.push_back(n);
        area += x.box.area();
      } else {
        for (uint32_t c : {x.left, x.right}) {
          next.push_back(c);
          area += bvh.nodes[c].box.area();
        }
      }
    }
    if (area > limit || next.size() == set.size()) break;
    set = std::move(next);
  }
  if (set.size() == 1) set.clear();
  return set;
}

// A deterministic per-node offset in [0, n) (the random offset of the re-test frames).
uint32_t offset_of(uint32_t node, uint32_t n) {
  uint64_t h = (node + 1) * 0x9E3779B97F4A7C15ull;
  h ^= h >> 29;
  return uint32_t(h % n);
}

struct Entry {
  float near;
  uint32_t node;
  bool operator<(const Entry& o) const {  // std::priority_queue is a max-heap: nearest first
    return near != o.near ? near > o.near : node > o.node;
  }
};

}  // namespace

OcclusionCuller::OcclusionCuller(const RenderScene& scene, const ChunkBvh& bvh)
    : scene_(scene),
      bvh_(bvh),
      visible_frame_(bvh.nodes.size(), 0),
      hidden_run_(bvh.nodes.size(), 0),
      tight_(bvh.nodes.size()),
      bounds_at_(bvh.nodes.size(), 0) {
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n)
    if (!bvh.nodes[n].leaf) tight_[n] = tight_set(bvh, n);
  frame_ = 1;
}

OcclusionCuller::Query OcclusionCuller::project(const Box3& box) const {
  Query q;
  if (box.empty()) return q;
  const Projection& p = projection_;
  float zmin = INFINITY, zmax = -INFINITY, xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY,
        ymax = -INFINITY;
  Vec3f cam[8];
  for (int k = 0; k < 8; ++k) {
    const Vec3f c{k & 1 ? box.max.x : box.min.x, k & 2 ? box.max.y : box.min.y,
                  k & 4 ? box.max.z : box.min.z};
    cam[k] = p.to_camera(c);
    zmin = std::min(zmin, cam[k].z);
    zmax = std::max(zmax, cam[k].z);
  }
  // Nothing in the box reaches beyond the near plane: every splat there is too near to draw.
  if (zmax < p.near) return q;
  q.in_frustum = true;
  if (zmin <= p.near) {  // straddles the near plane: the whole image, nearest depth 0
    q.rect = {0, 0, p.width - 1, p.height - 1};
    return q;
  }
  for (const Vec3f& c : cam) {
    const float inv = 1.0f / c.z;
    const float x = p.cx + p.focal_px * c.x * inv, y = p.cy + p.focal_px * c.y * inv;
    xmin = std::min(xmin, x);
    xmax = std::max(xmax, x);
    ymin = std::min(ymin, y);
    ymax = std::max(ymax, y);
  }
  // Pixel centres i + 0.5 in [min, max], one pixel more on each side for round-off.
  auto lo = [](float v, int size) {
    return int(std::floor(std::clamp(v - 0.5f, -4.0f, float(size) + 4))) - 1;
  };
  auto hi = [](float v, int size) {
    return int(std::ceil(std::clamp(v - 0.5f, -4.0f, float(size) + 4))) + 1;
  };
  q.rect = {std::max(0, lo(xmin, p.width)), std::max(0, lo(ymin, p.height)),
            std::min(p.width - 1, hi(xmax, p.width)), std::min(p.height - 1, hi(ymax, p.height))};
  if (q.rect.empty()) {
    q.in_frustum = false;
    return q;
  }
  // The renderer's depths carry float round-off: 0.1 % nearer than the box.
  q.near = zmin * 0.999f;
  return q;
}

bool OcclusionCuller::hidden(const Query& q) const {
  if (!q.in_frustum) return true;
  const float front = pyramid_.max_depth(cells_of(q.rect));
  return q.near > (front + margin_) * 1.001f;  // false when front is +inf
}

bool OcclusionCuller::query_node(uint32_t node) {
  const auto t0 = Clock::now();
  ++stats_->queries;
  bool visible = false;
  if (tight_bounds_ && !tight_[node].empty()) {
    for (uint32_t d : tight_[node])
      if (!hidden(project(bvh_.nodes[d].box))) {
        visible = true;
        break;
      }
  } else {
    visible = !hidden(project(bvh_.nodes[node].box));
  }
  stats_->query_s += seconds_since(t0);
  return visible;
}

void OcclusionCuller::draw_leaf(uint32_t leaf) {
  leaf_.assign(1, leaf);
  draw_leaves(leaf_, true);
}

void OcclusionCuller::draw_leaves(const std::vector<uint32_t>& leaves, bool depth) {
  if (leaves.empty()) return;
  const auto t0 = Clock::now();
  // Pieces of at most kDepthPiece splats, so that a batch of a few leaves (or one) still
  // spreads over the threads.
  constexpr uint32_t kDepthPiece = 512;
  struct Piece {
    uint32_t first;      // entry in bvh_.order
    uint32_t count;      // splats
    std::size_t bounds;  // entry in bounds_
  };
  std::vector<Piece> pieces;
  for (uint32_t leaf : leaves) {
    const ChunkBvhNode& n = bvh_.nodes[leaf];
    bounds_at_[leaf] = bounds_.size();
    for (uint32_t k = 0; k < n.size(); k += kDepthPiece)
      pieces.push_back({n.left + k, std::min(kDepthPiece, n.size() - k), bounds_.size() + k});
    bounds_.resize(bounds_.size() + n.size());
  }
  std::vector<PixelRect> dirty(pieces.size());
  tbb::parallel_for(std::size_t{0}, pieces.size(), [&](std::size_t k) {
    const Piece& p = pieces[k];
    dirty[k] =
        draw_depth(scene_, bvh_.order.data() + p.first, p.count, projection_, cull_backfaces_,
                   depth ? &pyramid_ : nullptr, thread_scratch_.local(), bounds_.data() + p.bounds);
  });
  // One update over the union when the pieces overlap on screen, else one per piece.
  PixelRect all;
  std::size_t area = 0;
  for (const PixelRect& r : dirty) {
    all.extend(r);
    if (!r.empty()) area += std::size_t(r.x1 - r.x0 + 1) * (r.y1 - r.y0 + 1);
  }
  if (!all.empty() && area > std::size_t(all.x1 - all.x0 + 1) * (all.y1 - all.y0 + 1))
    pyramid_.update(all);
  else
    for (const PixelRect& r : dirty) pyramid_.update(r);
  drawn_leaves_.insert(drawn_leaves_.end(), leaves.begin(), leaves.end());
  stats_->depth_s += seconds_since(t0);
}

void OcclusionCuller::mark_visible(uint32_t node) {
  while (node != UINT32_MAX && visible_frame_[node] != frame_) {
    visible_frame_[node] = frame_;
    node = bvh_.nodes[node].parent;
  }
}

bool OcclusionCuller::was_visible(uint32_t node) const {
  return visible_frame_[node] == frame_ - 1;
}

bool OcclusionCuller::retest_due(uint32_t node) const {
  return (frame_ + offset_of(node, kRetestInterval)) % kRetestInterval == 0;
}

void OcclusionCuller::run_frustum() {
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const uint32_t node = stack.back();
    stack.pop_back();
    ++stats_->nodes_traversed;
    const ChunkBvhNode& n = bvh_.nodes[node];
    if (!project(n.box).in_frustum) {
      ++stats_->culled_frustum;
      continue;
    }
    if (n.leaf) {
      drawn_leaves_.push_back(node);
    } else {
      stack.push_back(n.right);
      stack.push_back(n.left);
    }
  }
}

// Previously visible leaves in `pending` (those due re-queried first, against the pyramid
// without them), then the previously invisible nodes in `invisible` by multiqueries; nodes found
// visible: leaves drawn, interior nodes' children into `children`.
void OcclusionCuller::flush(std::vector<uint32_t>& pending, std::vector<uint32_t>& invisible,
                            std::vector<uint32_t>& children) {
  std::vector<uint32_t> still_visible;
  for (uint32_t leaf : pending)
    if (!retest_due(leaf) || query_node(leaf)) still_visible.push_back(leaf);
  // The last batch: no query will read the pyramid again, so the leaves need no depth pass (only
  // their splats' bounds, for the splat test).
  draw_leaves(pending, !(invisible.empty() && frontier_empty_));
  for (uint32_t leaf : still_visible) mark_visible(leaf);
  pending.clear();

  // Multiqueries (CHC++): p_keep(i) = 0.99 − 0.7 e^(−i) for a node hidden for the last i frames;
  // C(M) = 1 + (1 − Π p_keep)·|M|; M grows while |M| / C(M) grows.
  auto p_keep = [&](uint32_t node) {
    return 0.99f - 0.7f * std::exp(-std::min(20.0f, float(hidden_run_[node])));
  };
  // Neighbours in the hierarchy (close node numbers) make tighter groups than the traversal
  // order, which interleaves distant parts of the view at equal depth.
  std::sort(invisible.begin(), invisible.end());
  std::vector<uint32_t> newly;
  auto found_visible = [&](uint32_t node) {
    const ChunkBvhNode& n = bvh_.nodes[node];
    if (n.leaf) {
      newly.push_back(node);
    } else {
      children.push_back(n.left);
      children.push_back(n.right);
    }
  };
  auto single = [&](uint32_t node) {
    if (query_node(node)) {
      hidden_run_[node] = 0;
      found_visible(node);
    } else {
      ++hidden_run_[node];
      ++stats_->culled_occlusion;
    }
  };
  // One test of the group's rectangle and nearest depth; when it fails, each half again, down to
  // single nodes.
  std::function<void(const uint32_t*, std::size_t)> multiquery = [&](const uint32_t* m,
                                                                     std::size_t count) {
    if (count == 1) return single(m[0]);
    const auto t0 = Clock::now();
    Query u;
    u.near = INFINITY;
    auto add = [&](uint32_t node) {
      const Query q = project(bvh_.nodes[node].box);
      if (!q.in_frustum) return;
      u.in_frustum = true;
      u.rect.extend(q.rect);
      u.near = std::min(u.near, q.near);
    };
    for (std::size_t k = 0; k < count; ++k) {
      if (tight_bounds_ && !tight_[m[k]].empty())
        for (uint32_t d : tight_[m[k]]) add(d);
      else
        add(m[k]);
    }
    ++stats_->queries;
    ++stats_->multiqueries;
    stats_->multiquery_nodes += count;
    const bool all_hidden = hidden(u);
    stats_->query_s += seconds_since(t0);
    if (all_hidden) {
      stats_->culled_occlusion += count;
      for (std::size_t k = 0; k < count; ++k) ++hidden_run_[m[k]];
      return;
    }
    multiquery(m, count / 2);
    multiquery(m + count / 2, count - count / 2);
  };
  std::size_t i = 0;
  while (i < invisible.size()) {
    std::size_t end = i + 1;
    float keep = p_keep(invisible[i]);
    double value = 1.0 / (1.0 + (1.0 - keep));
    // Only nodes a query found hidden before join a group: for a node without that history the
    // model's p_keep (0.29) makes any group look worth it, and most such groups fail.
    while (end < invisible.size() && hidden_run_[invisible[i]] > 0 &&
           hidden_run_[invisible[end]] > 0) {
      const float k2 = keep * p_keep(invisible[end]);
      const double m = double(end + 1 - i);
      const double v = m / (1.0 + (1.0 - k2) * m);
      if (v <= value) break;
      value = v;
      keep = k2;
      ++end;
    }
    multiquery(invisible.data() + i, end - i);
    i = end;
  }
  invisible.clear();
  draw_leaves(newly, true);
  for (uint32_t leaf : newly) mark_visible(leaf);
}

// Hierarchical (coherent false): every node queried, as CHC treats a node it has no history for.
void OcclusionCuller::run_chc(bool coherent, bool plus) {
  tight_bounds_ = plus;
  std::priority_queue<Entry> heap;
  heap.push({0, 0});
  std::vector<uint32_t> pending, invisible, children;
  auto push_children = [&](const ChunkBvhNode& n) {
    for (uint32_t c : {n.left, n.right}) heap.push({project(bvh_.nodes[c].box).near, c});
  };
  const bool coherent_frame = was_visible(0);  // the previous frame saw something
  bool fresh = false;  // chc++, no previous frame: `invisible` holds a node, query it now
  while (true) {
    if (heap.empty() || invisible.size() >= std::size_t(kBatchSize) || fresh) {
      fresh = false;
      if (!plus || (pending.empty() && invisible.empty())) {
        if (heap.empty()) break;
      } else {
        frontier_empty_ = heap.empty();
        flush(pending, invisible, children);
        for (uint32_t c : children) heap.push({project(bvh_.nodes[c].box).near, c});
        children.clear();
        continue;
      }
    }
    const uint32_t node = heap.top().node;
    heap.pop();
    ++stats_->nodes_traversed;
    const ChunkBvhNode& n = bvh_.nodes[node];
    if (!project(n.box).in_frustum) {
      ++stats_->culled_frustum;
      continue;
    }
    if (coherent && was_visible(node)) {
      if (!n.leaf) {
        push_children(n);
      } else if (plus) {
        pending.push_back(node);
      } else {
        const bool visible = !retest_due(node) || query_node(node);
        draw_leaf(node);
        if (visible) mark_visible(node);
      }
      continue;
    }
    if (plus) {
      // Without a previous frame (the first of a walk), nothing is drawn before the queries and
      // no node has a history to join a multiquery: a batch would query its nodes against a
      // pyramid without the leaves found visible meanwhile, and find more visible. Each node is
      // then queried at once, as the hierarchical traversal does (on the CPU an answer costs
      // no latency). With a previous frame, batches: flushing at each node without history
      // (there are ~100 a frame on the city walk) costs a parallel depth pass each and saves no
      // query.
      invisible.push_back(node);
      fresh = !coherent_frame;
      continue;
    }
    if (!query_node(node)) {
      ++stats_->culled_occlusion;
      continue;
    }
    if (n.leaf) {
      draw_leaf(node);
      mark_visible(node);
    } else {
      push_children(n);
    }
  }
  tight_bounds_ = false;
}

void OcclusionCuller::collect(bool test_splats) {
  const std::size_t n = scene_.size();
  mask_.assign((n + 63) / 64, 0);
  if (test_splats) {
    const auto t0 = Clock::now();
    keep_.resize(bounds_.size());
    tbb::parallel_for(std::size_t{0}, drawn_leaves_.size(), [&](std::size_t k) {
      const uint32_t leaf = drawn_leaves_[k];
      const SplatBounds* b = bounds_.data() + bounds_at_[leaf];
      uint8_t* keep = keep_.data() + bounds_at_[leaf];
      for (uint32_t e = 0, size = bvh_.nodes[leaf].size(); e < size; ++e) {
        // Not drawn by the renderer (its setup is the same arithmetic), or hidden.
        Query q;
        q.in_frustum = b[e].drawn();
        q.rect = {b[e].x0, b[e].y0, b[e].x1, b[e].y1};
        q.near = b[e].zmin * 0.999f;
        keep[e] = !hidden(q);
      }
    });
    stats_->splat_test_s += seconds_since(t0);
  }
  uint64_t splats = 0;
  for (uint32_t leaf : drawn_leaves_) {
    const ChunkBvhNode& x = bvh_.nodes[leaf];
    const uint8_t* keep = test_splats ? keep_.data() + bounds_at_[leaf] : nullptr;
    for (uint32_t k = x.left; k < x.right; ++k) {
      if (keep && !keep[k - x.left]) continue;
      const uint32_t i = bvh_.order[k];
      mask_[i >> 6] |= uint64_t{1} << (i & 63);
      ++splats;
    }
    if (test_splats) stats_->splats_culled += x.size();
  }
  if (test_splats) stats_->splats_culled -= splats;
  stats_->leaves_drawn += drawn_leaves_.size();
  stats_->splats_drawn += splats;
  splats_.clear();
  splats_.reserve(splats);
  for (std::size_t w = 0; w < mask_.size(); ++w)
    for (uint64_t bits = mask_[w]; bits != 0; bits &= bits - 1)
      splats_.push_back(uint32_t(w * 64 + __builtin_ctzll(bits)));
}

const std::vector<uint32_t>& OcclusionCuller::cull(const Projection& projection, OcclusionMode mode,
                                                   float margin, bool cull_backfaces,
                                                   OcclusionStats& stats) {
  const auto t0 = Clock::now();
  const double query0 = stats.query_s, depth0 = stats.depth_s, test0 = stats.splat_test_s;
  ++frame_;
  projection_ = projection;
  margin_ = margin;
  cull_backfaces_ = cull_backfaces;
  stats_ = &stats;
  drawn_leaves_.clear();
  bounds_.clear();
  if (mode != OcclusionMode::kNone && mode != OcclusionMode::kFrustum)
    pyramid_.reset((projection.width + kDepthCell - 1) >> kDepthCellShift,
                   (projection.height + kDepthCell - 1) >> kDepthCellShift);
  switch (mode) {
    case OcclusionMode::kNone:
      for (uint32_t n = 0; n < bvh_.nodes.size(); ++n)
        if (bvh_.nodes[n].leaf) drawn_leaves_.push_back(n);
      break;
    case OcclusionMode::kFrustum:
      run_frustum();
      break;
    case OcclusionMode::kHierarchical:
      run_chc(false, false);
      break;
    case OcclusionMode::kChc:
      run_chc(true, false);
      break;
    case OcclusionMode::kChcPlusPlus:
      run_chc(true, true);
      break;
  }
  collect(mode != OcclusionMode::kNone && mode != OcclusionMode::kFrustum);
  stats.traversal_s += seconds_since(t0) - (stats.query_s - query0) - (stats.depth_s - depth0) -
                       (stats.splat_test_s - test0);
  stats_ = nullptr;
  return splats_;
}

}  // namespace splatkit::render
