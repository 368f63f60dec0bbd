// Occlusion culling over a chunk hierarchy (chunk_bvh.h): which splats a frame must draw so that
// the image is byte-identical to drawing them all.
//
// A query is conservative: a node (its box, or for chc++ the boxes of a few descendants) is
// hidden when its nearest camera depth lies beyond the largest front depth over its screen
// rectangle in the DepthPyramid plus `margin` (the renderer's depth window: fragments that far
// behind the nearest fragment of a pixel never change it, fragment_store.h). The pyramid holds
// upper bounds of the front depth of the splats drawn so far (draw_depth.h), so a hidden node
// has no fragment the full render would use.
//
// Modes (Bittner et al. 2004, "Coherent Hierarchical Culling"; Mattausch, Bittner and Wimmer
// 2008, "CHC++"; docs/references.md):
//   kNone: every splat; kFrustum: leaves whose box meets the view frustum;
//   kHierarchical: front-to-back traversal, every node queried and the answer awaited, each
//     visible leaf drawn into the pyramid before the next query;
//   kChc: temporal coherence: leaves visible in the previous frame drawn at once and re-queried
//     only every kRetestInterval frames (a per-node offset spreads them), interior nodes visible
//     in the previous frame traversed without a query, the rest queried; visibility pulled up;
//   kChcPlusPlus: CHC with previously visible leaves drawn in batches, previously invisible
//     nodes queried in batches of kBatchSize after the batch of visible leaves is drawn, grouped
//     into multiqueries by the cost model (one test of the group's rectangle and nearest depth;
//     if it fails, each half of the group again, down to single nodes, where the GPU method
//     queries each member alone; a batch is grouped in hierarchy order, so that a group's
//     members lie close together), and tight bounds. A batch of previously visible leaves that
//     no later query reads gets no depth pass.
// The pyramid modes then test each splat of the drawn leaves alone against the final pyramid
// (the same test as a node's, with the pixel box and nearest depth the renderer's setup gives
// it, computed by the depth pass): a leaf partly in view or partly hidden draws only the splats
// that can show, and no splat the renderer would not draw (off screen, too near). Exact as the
// node test is: every value of the final pyramid comes from a splat that passes (a splat is
// dropped only when it lies beyond the pyramid plus the margin everywhere it covers, so beyond
// its own depth-pass values).
// Not thread safe; the depth pass of a batch runs in parallel in the caller's TBB arena.
#pragma once

#include <oneapi/tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <string>
#include <vector>

#include "render/chunk_bvh.h"
#include "render/depth_pyramid.h"
#include "render/draw_depth.h"

namespace splatkit::render {

enum class OcclusionMode { kNone, kFrustum, kHierarchical, kChc, kChcPlusPlus };

// "none", "frustum", "hierarchical", "chc", "chc++"; Error(kUsage) for anything else.
OcclusionMode parse_occlusion_mode(const std::string& name);
const char* occlusion_mode_name(OcclusionMode mode);

struct OcclusionStats {
  uint64_t nodes_traversed = 0;   // nodes taken from the traversal queue
  uint64_t queries = 0;           // pyramid tests issued (a multiquery counts once)
  uint64_t multiqueries = 0;      // queries covering more than one node
  uint64_t multiquery_nodes = 0;  // nodes covered by those
  uint64_t culled_frustum = 0;    // nodes outside the frustum
  uint64_t culled_occlusion = 0;  // nodes found hidden
  uint64_t leaves_drawn = 0, splats_drawn = 0;
  uint64_t splats_culled = 0;  // splats of drawn leaves found hidden (or off screen) one by one
  // Wall time (depth pass = drawing leaves; splat test = the per-splat test of drawn leaves).
  double traversal_s = 0, query_s = 0, depth_s = 0, splat_test_s = 0;
  void add(const OcclusionStats& o);
};

class OcclusionCuller {
 public:
  static constexpr int kRetestInterval = 5;  // n_av
  static constexpr int kBatchSize = 50;      // b

  OcclusionCuller(const RenderScene& scene, const ChunkBvh& bvh);
  // The splats to draw for one frame, ascending. `margin`: the renderer's depth window (scene
  // units). Frames are expected in sequence (temporal coherence); any camera works. Adds the
  // frame's counts and times to `stats`.
  const std::vector<uint32_t>& cull(const Projection& projection, OcclusionMode mode, float margin,
                                    bool cull_backfaces, OcclusionStats& stats);

 private:
  struct Query {
    PixelRect rect;
    float near = 0;
    bool in_frustum = false;
  };
  Query project(const Box3& box) const;
  bool hidden(const Query& q) const;
  Query project_splat(uint32_t splat) const;              // the splat's bounding sphere
  bool query_node(uint32_t node);                         // counts one query; true when visible
  void draw_leaf(uint32_t leaf);  // at once, into the pyramid (draw_leaves of one)
  // In parallel; with `depth` false only the splats' bounds are computed (no depth pass).
  void draw_leaves(const std::vector<uint32_t>& leaves, bool depth);
  void mark_visible(uint32_t node);                       // this frame, pulled up
  bool was_visible(uint32_t node) const;
  bool retest_due(uint32_t node) const;
  void run_frustum();
  void run_chc(bool coherent, bool plus);
  void flush(std::vector<uint32_t>& pending, std::vector<uint32_t>& invisible,
             std::vector<uint32_t>& queue_out);
  void collect(bool test_splats);  // drawn_leaves_ -> splats_

  const RenderScene& scene_;
  const ChunkBvh& bvh_;
  Projection projection_;
  float margin_ = 0;
  bool cull_backfaces_ = false;
  DepthPyramid pyramid_;
  OcclusionStats* stats_ = nullptr;
  uint32_t frame_ = 0;
  std::vector<uint32_t> visible_frame_;  // per node: last frame it was visible (0: never)
  std::vector<uint32_t> hidden_run_;     // per node: queries in a row that found it hidden (chc++)
  std::vector<std::vector<uint32_t>> tight_;  // per node: descendants whose boxes bound it
  std::vector<uint32_t> drawn_leaves_;
  std::vector<uint64_t> mask_;
  std::vector<SplatBounds> bounds_;     // this frame's drawn leaves' splats, a leaf at a time
  std::vector<std::size_t> bounds_at_;  // per leaf drawn this frame: its first entry in bounds_
  std::vector<uint8_t> keep_;           // per entry of bounds_: the splat test's answer
  std::vector<uint32_t> splats_;
  std::vector<uint32_t> leaf_;  // draw_leaf's list of one
  tbb::enumerable_thread_specific<DepthPassScratch> thread_scratch_;
  bool tight_bounds_ = false;
  bool frontier_empty_ = false;  // chc++: the traversal queue is empty at this flush
};

}  // namespace splatkit::render
