// The point hierarchy of a Sequential Point Tree [Dachsbacher03]: an octree over splats whose
// interior nodes are discs fitted to their children (spt_disc.h).
//
// The splats are sorted by the Morton code of their centre (21 bits per axis over the bounding
// cube); a node's range splits at the first octree level where its codes differ, so chains of
// single-child cells collapse and every interior node has 2–8 children (splats whose codes are
// equal become children of one node, however many). Deterministic: the same input gives the same
// tree for any thread count (subtrees of at most a few thousand splats are built in parallel and
// numbered in sorted order).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "splatkit/vec3.h"
#include "spt/spt_disc.h"

namespace splatkit::spt {

inline constexpr uint32_t kNoParent = 0xFFFFFFFFu;

struct SptInput {
  std::span<const Vec3f> positions;                 // #N splat centres
  std::span<const Vec3f> normals;                   // #N unit normals
  std::span<const float> radii;                     // #N radii >= 0
  std::span<const std::array<uint16_t, 3>> colors;  // #N RGB, or empty
  int color_bits = 8;                               // 8 or 16
  std::size_t size() const { return positions.size(); }
  SptDisc leaf(std::size_t i) const;  // splat i as a disc (colour made 8-bit, error 0)
};

struct SptTree {
  // Node i < N is splat i (a leaf); node N + j is interiors[j]. Children have smaller numbers than
  // their parent; the root is the last node (a single splat is its own root).
  std::vector<SptDisc> interiors;  // #M
  std::vector<uint32_t> parent;    // #N+M, kNoParent for the root
  uint32_t depth = 0;              // edges from the root to the deepest leaf
  std::size_t size() const { return parent.size(); }
  uint32_t root() const { return static_cast<uint32_t>(parent.size() - 1); }
};

// Precondition: input.size() >= 1 and < 2^31, finite positions. `color_weight`: L of spt_disc.h.
SptTree build_spt_tree(const SptInput& input, float color_weight);

// The splats in the order the tree visits them (Morton order of their centres over the bounding
// cube, ties by index). A caller that owns the splats may put them in this order first: the tree
// is then built reading memory in order (faster on large clouds), with the same shape.
std::vector<uint32_t> morton_order(std::span<const Vec3f> positions);

}  // namespace splatkit::spt
