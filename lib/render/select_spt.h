// Which entries of a Sequential Point Tree's list [Dachsbacher03] a frame draws.
//
// The list is sorted by r_max descending. With the allowed screen error e (pixels) and the focal
// length f (pixels), an entry stored for the build's error ε_b is drawn at view distance r iff
// r_min ≤ r·k < r_max, k = (e / f) / ε_b (its error e_g = r_min·ε_b is then at most e pixels on
// screen). The prefix of entries with r_max > k·(distance from the eye to the model's bounding
// sphere) is found by binary search; every entry after it fails the test anyway. Each entry of
// the prefix is then tested at its own distance to the eye and drawn as a disc of its diameter,
// so its size on screen is d/r. Nothing else is culled here (the rasteriser drops what lies
// outside the view). Deterministic: the DrawList keeps the list order for any thread count.
#pragma once

#include "formats/read_spt.h"
#include "render/camera.h"
#include "render/select_splats.h"
#include "render/zbuffer_splats.h"

namespace splatkit::render {

// `bounds`: a sphere around every entry (spt_scene.h). `stats` (optional) gets spt_prefix and
// spt_culled.
DrawList select_spt(const SptModel& model, const BoundingSphere& bounds,
                    const Projection& projection, float error_px, LodStats* stats = nullptr);

struct SptZBufferCounts {
  uint64_t prefix = 0, selected = 0;
  uint64_t drawn = 0;          // of the selected, those that cover a pixel
  uint64_t points = 0;         // of the drawn, those written as one pixel
  double diameter_px_sum = 0;  // projected diameters of the drawn, pixels
  double cpu_s = 0;            // CPU time of the selection and drawing, all threads
};

// Splats whose projected diameter is at most this many pixels are drawn as points.
inline constexpr float kSptPointDiameterPx = 1.5f;

// The same selection drawing each selected entry straight into `buffer` (zbuffer_splats.h),
// keyed by its index in the list, with no DrawList in between: the fast path of
// `--blend zbuffer`. An entry whose projected diameter is at most kSptPointDiameterPx is a point:
// one key written into the pixel under its centre, with no loop over the pixels of its disc. What
// that gives up: a disc of 1 to 1.5 pixels whose centre lies near a pixel corner covers up to
// four pixel centres, and the point fills one of them, so where the neighbours do not cover the
// other three a pinhole may show (below 1 pixel the disc covers at most the pixel under its
// centre, so the point is exact).
SptZBufferCounts draw_spt_zbuffer(const SptModel& model, const BoundingSphere& bounds,
                                  const Projection& projection, float error_px,
                                  DepthKeyBuffer& buffer);

// Linear RGB of an entry's 8-bit sRGB colour.
Vec3f spt_linear_color(const std::array<uint8_t, 3>& rgb);

}  // namespace splatkit::render
