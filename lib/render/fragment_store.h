// The A-buffer of one tile, with bounded memory: a fixed number of fragment slots per pixel
// (RenderOptions::max_fragments, default 8). A fragment is (depth, weight, splat index); the
// splat index gives everything else at reconstruction time (normal, colour, depth range, surface
// id), which keeps a slot at 12 bytes and a 32×32 tile with 8 slots at 96 KiB.
//
// Overflow: when a pixel's slots are full, the new fragment replaces the last stored one in the
// order (ring, depth, splat index) if it comes before it, else it is dropped: disc fragments push
// out ring fragments, then the farthest goes (equal depths ordered by splat index: the lower index
// stays); the pixel is flagged as overflowed when a disc fragment is lost. So the K least
// fragments in that order survive whatever the arrival order, which is all an opaque front surface
// needs unless more than K disc fragments lie in front of its far side; and fragments beyond the depth window (below) change nothing, so a
// renderer given fewer of them (occlusion culling) stores the same front fragments.
//
// Ring fragments (negative weight, rasterize_tile.h) are stored like the others but never set a
// pixel's nearest depth: only disc fragments can start a surface.
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

class FragmentStore {
 public:
  // Empties the store for a tile of `pixels` pixels with `capacity` slots each (1..255).
  void reset(int pixels, int capacity, float window) {
    capacity_ = capacity;
    window_ = window;
    const std::size_t slots = std::size_t(pixels) * capacity;
    if (depth_.size() < slots) {
      depth_.resize(slots);
      weight_.resize(slots);
      splat_.resize(slots);
    }
    count_.assign(pixels, 0);
    overflowed_.assign(pixels, 0);
    nearest_.assign(pixels, std::numeric_limits<float>::infinity());
  }

  // Returns false when the fragment is dropped at once (beyond the depth window, or on overflow
  // when it is not nearer than the farthest stored one).
  bool add(int pixel, float depth, float weight, uint32_t splat) {
    float& nearest = nearest_[pixel];
    if (depth > nearest + window_) return false;
    if (weight > 0) nearest = std::min(nearest, depth);
    const std::size_t base = std::size_t(pixel) * capacity_;
    uint8_t& n = count_[pixel];
    std::size_t slot;
    if (n < capacity_) {
      slot = base + n++;
    } else {
      // The last by (ring, depth, splat index), so that equal depths too are decided by the
      // fragments alone, not by the slots they landed in.
      slot = base;
      for (std::size_t k = base + 1; k < base + capacity_; ++k)
        if (before(weight_[slot], depth_[slot], splat_[slot], weight_[k], depth_[k], splat_[k]))
          slot = k;
      // Overflowed: a disc fragment is lost (ring fragments lost are not counted).
      if (!before(weight, depth, splat, weight_[slot], depth_[slot], splat_[slot])) {
        overflowed_[pixel] |= weight > 0;
        return false;
      }
      overflowed_[pixel] |= weight_[slot] > 0;
    }
    depth_[slot] = depth;
    weight_[slot] = weight;
    splat_[slot] = splat;
    return true;
  }

  // The order in which fragments keep their slots: disc fragments before ring fragments (a ring
  // only smooths the normal), then nearer first, then the lower splat index.
  static bool before(float wa, float da, uint32_t sa, float wb, float db, uint32_t sb) {
    const bool ring_a = !(wa > 0), ring_b = !(wb > 0);
    if (ring_a != ring_b) return ring_b;
    return da < db || (da == db && sa < sb);
  }

  float window() const { return window_; }
  // The largest nearest depth over the first `pixels` pixels (+inf if one has no disc fragment): a
  // splat whose whole disc lies deeper than this plus the window cannot add a fragment.
  float farthest_nearest(int pixels) const {
    float m = 0;
    for (int p = 0; p < pixels; ++p) m = std::max(m, nearest_[p]);
    return m;
  }

  int count(int pixel) const { return count_[pixel]; }
  float nearest(int pixel) const { return nearest_[pixel]; }  // of the disc fragments
  bool overflowed(int pixel) const { return overflowed_[pixel] != 0; }
  const float* depths(int pixel) const { return depth_.data() + std::size_t(pixel) * capacity_; }
  const float* weights(int pixel) const { return weight_.data() + std::size_t(pixel) * capacity_; }
  const uint32_t* splats(int pixel) const { return splat_.data() + std::size_t(pixel) * capacity_; }

 private:
  int capacity_ = 0;
  float window_ = std::numeric_limits<float>::infinity();
  std::vector<float> depth_, weight_, nearest_;
  std::vector<uint32_t> splat_;
  std::vector<uint8_t> count_, overflowed_;
};

}  // namespace splatkit::render
