// The point hierarchy of a Sequential Point Tree [Dachsbacher03]: an octree over splats whose
// interior nodes are discs fitted to their children (spt_disc.h).
//
// The splats are first put in the Morton order of their centres (21 bits per axis over the
// bounding cube; sort_spt_splats). A node's range then splits at the first octree level where
// its codes differ, so chains of single-child cells collapse and every interior node has 2–8
// children (splats whose codes are equal become children of one node, however many). A run of
// more than 8 splats with one code (a cluster far smaller than the cube's cells, beside a far
// outlier) is ordered again by codes over its own bounding cube; only coincident centres stay
// one code. Deterministic: the same input gives the same tree for any thread count (subtrees of
// at most a few thousand splats are built in parallel, then numbered in Morton order).
//
// Memory is what build-spt's peak is made of, so the tree is lean: one byte per splat says where
// the Morton order splits (the highest differing octree level of neighbouring codes), each splat
// keeps its parent's number, and an interior node is a 24-byte record already quantised in the
// .spt frame (formats/spt.md) but for its radius and error, whose code scales are known only
// once the whole tree is built. Full-precision files keep the float disc beside each record.
#pragma once

#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <vector>

#include "splatkit/slot_array.h"
#include "splatkit/splat_cloud.h"
#include "splatkit/vec3.h"
#include "spt/spt_disc.h"

namespace splatkit::spt {

inline constexpr uint32_t kNoParent = 0xFFFFFFFFu;

// The splats the tree is built over, owned (the tree's order is made by moving them).
struct SptSplats {
  std::vector<Vec3f> positions;                // #N splat centres, finite
  std::vector<Vec3f> normals;                  // #N unit normals
  std::vector<float> radii;                    // #N radii >= 0
  std::vector<std::array<uint8_t, 3>> colors;  // #N sRGB 8-bit, or empty
  std::size_t size() const { return positions.size(); }
  SptDisc leaf(std::size_t i) const;  // splat i as a disc (error 0)
};

// Takes the cloud's positions, normals (normalised), radii and colours (made 8-bit), leaving
// them empty in `cloud`.
SptSplats take_spt_splats(SplatCloud& cloud);

// What sort_spt_splats leaves for the tree.
struct SptOrder {
  // #N−1: levels[i] ranks where splats i and i+1 part in the octree (higher = nearer the root;
  // 0 = equal codes). A node's children are the runs between its range's highest levels.
  std::vector<uint8_t> levels;
  Vec3f lo{0, 0, 0}, hi{0, 0, 0};  // bounding box of the centres, or the frame given
};

// Puts the splats in the tree's order, in place. `old_index` (optional): gets, for each new
// position, the splat's index before the call. `frame` (optional): the box whose bounding cube
// the codes are made over and whose extent the position codes span (SptOrder::lo, hi), instead
// of the centres' own box: a survey's box for one tile of it (formats/tiles.md), so that the
// tile's octree cells are the whole survey's and a cell inside the tile gets the subtree a build
// over the whole survey gives it. Precondition: 1 <= size() < 2^31; `frame`, when given, holds
// every centre.
SptOrder sort_spt_splats(SptSplats& splats, std::vector<uint32_t>* old_index = nullptr,
                         const Bounds* frame = nullptr);

// An interior node as stored: position, normal and colour as .spt codes, radius and error as
// floats; parent, and from encoding on the r codes.
struct SptRecord {
  std::array<uint16_t, 3> q;  // position code per axis (spt_codes.h)
  uint16_t normal;            // octahedral code
  uint16_t rgb565;
  uint16_t r_min = 0;  // r_min code (set by encode_spt)
  float radius;        // scene units
  float error;         // e_g, monotone up the tree
  uint32_t parent;     // node number, kNoParent for the root
};
static_assert(sizeof(SptRecord) == 24);

// The float disc of an interior node (full-precision files only).
struct SptFullRecord {
  Vec3f centre, normal;
  std::array<uint8_t, 3> color;
};

struct SptTreeOptions {
  float color_weight = 1;  // L of spt_disc.h
  bool full = false;       // keep the float discs (full_records)
};

struct SptTree {
  // Node i < N is splat i (a leaf); node N + s is the interior node in slot s < interiors of
  // `records` (allocated for N, written densely from slot 0: the pages beyond are never
  // touched): each subtree's nodes in post-order, subtrees in Morton order, then the nodes above
  // them in post-order (the root last). Children have smaller numbers than their parent.
  std::size_t leaves = 0;
  std::vector<uint32_t> leaf_parent;  // #N node numbers (kNoParent: a single splat is the root);
                                      // r_max codes after encode_spt
  SlotArray<SptRecord> records;
  SlotArray<SptFullRecord> full_records;      // slots as records, when options.full
  std::size_t interiors = 0;                  // slots in use
  uint32_t depth = 0;                         // edges from the root to the deepest leaf
  Vec3f box_min{0, 0, 0}, step{0, 0, 0};      // frame of the records' position codes
  float error_lo = INFINITY, error_hi = 0;    // positive errors of interior nodes
  float radius_lo = INFINITY, radius_hi = 0;  // positive radii of every node
  std::size_t size() const { return leaves + interiors; }
};

// Builds the tree over splats in the order sort_spt_splats made (`order` from it).
SptTree build_spt_tree(const SptSplats& splats, const SptOrder& order,
                       const SptTreeOptions& options);

}  // namespace splatkit::spt
