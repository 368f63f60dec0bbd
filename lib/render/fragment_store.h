// The A-buffer of one tile, with bounded memory: a fixed number of fragment slots per pixel
// (RenderOptions::max_fragments, default 8). A fragment is (depth, weight, splat index); the
// splat index gives everything else at reconstruction time (normal, colour, depth range, surface
// id), which keeps a slot at 12 bytes and a 32×32 tile with 8 + 4 slots at 144 KiB.
//
// Ring fragments (negative weight, rasterize_tile.h) have kRingSlots slots of their own per pixel,
// so that they never push out a disc fragment nor a disc fragment them, and never set a pixel's
// nearest depth (below): only disc fragments can start a surface.
//
// Overflow: when a pixel's slots of a kind are full, the new fragment replaces the farthest stored
// one of its kind if it is nearer, else it is dropped (equal depths ordered by splat index: the
// lower index stays); losing a disc fragment flags the pixel as overflowed. So the K least (depth,
// splat index) fragments of each kind survive whatever the arrival order, which is all an opaque
// front surface needs unless more than K fragments lie in front of its far side; and fragments
// beyond the depth window (below) change nothing, so a renderer given fewer of them (occlusion
// culling) stores the same front fragments.
//
// Depth window: a fragment deeper than `window` behind the nearest disc fragment stored so far is
// dropped at once, and reconstruction ignores those deeper than `window` behind the final
// nearest one. Since the nearest depth only decreases, the two together keep exactly the
// fragments within the window whatever the arrival order; the window is chosen so that no
// fragment beyond it could join the front surface (reconstruct_pixel.h), so it changes nothing
// but the work and the overflows spent on hidden surfaces.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace splatkit::render {

// Ring slots per pixel, besides the disc slots.
inline constexpr int kRingSlots = 4;

class FragmentStore {
 public:
  // Empties the store for a tile of `pixels` pixels with `capacity` disc slots each (1..255) and
  // kRingSlots ring slots.
  void reset(int pixels, int capacity, float window) {
    capacity_ = capacity;
    stride_ = capacity + kRingSlots;
    window_ = window;
    const std::size_t slots = std::size_t(pixels) * stride_;
    if (depth_.size() < slots) {
      depth_.resize(slots);
      weight_.resize(slots);
      splat_.resize(slots);
    }
    count_.assign(pixels, 0);
    ring_count_.assign(pixels, 0);
    overflowed_.assign(pixels, 0);
    nearest_.assign(pixels, std::numeric_limits<float>::infinity());
  }

  // Returns false when the fragment is dropped at once (beyond the depth window, or on overflow
  // when it is not nearer than the farthest stored one of its kind).
  bool add(int pixel, float depth, float weight, uint32_t splat) {
    float& nearest = nearest_[pixel];
    if (depth > nearest + window_) return false;
    const bool disc = weight > 0;
    if (disc) nearest = std::min(nearest, depth);
    const std::size_t base = std::size_t(pixel) * stride_ + (disc ? 0 : capacity_);
    uint8_t& n = disc ? count_[pixel] : ring_count_[pixel];
    const int capacity = disc ? capacity_ : kRingSlots;
    std::size_t slot;
    if (n < capacity) {
      slot = base + n++;
    } else {
      // The farthest by (depth, splat index), so that equal depths too are decided by the
      // fragments alone, not by the slots they landed in.
      slot = base;
      for (std::size_t k = base + 1; k < base + capacity; ++k)
        if (depth_[k] > depth_[slot] || (depth_[k] == depth_[slot] && splat_[k] > splat_[slot]))
          slot = k;
      overflowed_[pixel] |= disc;
      if (!(depth < depth_[slot] || (depth == depth_[slot] && splat < splat_[slot]))) return false;
    }
    depth_[slot] = depth;
    weight_[slot] = weight;
    splat_[slot] = splat;
    return true;
  }

  float window() const { return window_; }
  // The largest nearest depth over the first `pixels` pixels (+inf if one has no disc fragment): a
  // splat whose whole disc lies deeper than this plus the window cannot add a fragment.
  float farthest_nearest(int pixels) const {
    float m = 0;
    for (int p = 0; p < pixels; ++p) m = std::max(m, nearest_[p]);
    return m;
  }

  // Disc fragments: count(p) of them from depths(p), weights(p), splats(p); ring fragments:
  // ring_count(p) of them from depths(p) + ring_offset() and so on.
  int count(int pixel) const { return count_[pixel]; }
  int ring_count(int pixel) const { return ring_count_[pixel]; }
  int ring_offset() const { return capacity_; }
  float nearest(int pixel) const { return nearest_[pixel]; }  // of the disc fragments
  bool overflowed(int pixel) const { return overflowed_[pixel] != 0; }
  const float* depths(int pixel) const { return depth_.data() + std::size_t(pixel) * stride_; }
  const float* weights(int pixel) const { return weight_.data() + std::size_t(pixel) * stride_; }
  const uint32_t* splats(int pixel) const { return splat_.data() + std::size_t(pixel) * stride_; }

 private:
  int capacity_ = 0, stride_ = 0;
  float window_ = std::numeric_limits<float>::infinity();
  std::vector<float> depth_, weight_, nearest_;
  std::vector<uint32_t> splat_;
  std::vector<uint8_t> count_, ring_count_, overflowed_;
};

}  // namespace splatkit::render
