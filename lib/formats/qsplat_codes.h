// The four quantisers of the QSplat .qs v11 node [Rusinkiewicz00] (layout: formats/qsplat.md),
// encoding and decoding, shared by the writer (lib/qsplat) and the reader (read_qsplat.h).
//
// - Sphere (13 bits): an index S into a table of 7621 cells (X, Y, Z, R) relative to the parent's
//   decoded sphere: centre = parent centre + parent radius · (X, Y, Z), radius = parent radius · R,
//   evaluated in float exactly as the original viewer does (decode_sphere).
//   encode_sphere is conservative: the decoded sphere contains the child's true sphere and lies
//   inside the decoded parent (both checked on the float values the reader computes).
// - Normal (14 bits): dominant axis A (0:+X 1:−X 2:+Y 3:−Y 4:+Z 5:−Z) and the two other components
//   warped by atan and quantised to 52 steps each. Angular error ≤ kNormalMaxError.
// - Cone (2 bits): c = int(4·√(sin θ)) of the half-width θ; decoded as the bound (1 + c)²/16 on
//   sin θ; c = 3 means "do not cull" (θ ≥ ~0.85 rad or θ > 1.5).
// - Colour (16 bits): RGB 5-6-5 by truncation; decoded channels expand to 8 bits (v << 3 | v >> 2,
//   v << 2 | v >> 4), error ≤ 7 (red, blue) and ≤ 3 (green) per 8-bit channel.
#pragma once

#include <array>
#include <cstdint>

#include "splatkit/vec3.h"

namespace splatkit::qsplat {

inline constexpr int kSphereCells = 7621;
inline constexpr int kNormalSteps = 52;
inline constexpr int kNormalCodes = 6 * kNormalSteps * kNormalSteps;  // 16224 of the 16384
// Largest angle (radians) between a unit normal and its decoded code (measured over a dense
// sampling of the sphere gives 0.034: test_formats_qsplat_codes.cpp).
inline constexpr double kNormalMaxError = 0.036;

struct Sphere {
  Vec3f centre;
  float radius = 0;
};

struct SphereCell {
  float x, y, z, r;  // relative to the parent: centre offset and radius in parent radii
};

// The table, indexed by S, in the original's order: size 1..13, then x, y, z in [0, 13 − size].
const std::array<SphereCell, kSphereCells>& sphere_cells();

// Decoded child sphere of code `s` (< kSphereCells) under the decoded `parent`.
inline Sphere decode_sphere(const SphereCell& cell, const Sphere& parent) {
  return {{parent.centre.x + parent.radius * cell.x, parent.centre.y + parent.radius * cell.y,
           parent.centre.z + parent.radius * cell.z},
          parent.radius * cell.r};
}

// How encode_sphere searches the cells of one size: from the nearest cell outwards (the default;
// it tries one cell, or up to eight near float-rounding ties, before it falls back to the whole
// box), or every cell of the box that can contain the child (the reference the tests compare
// with). Both return the same code.
enum class SphereSearch { kNearestFirst, kExhaustive };

// The code of the smallest cell whose decoded sphere contains the sphere (centre, radius) (double
// precision, the true sphere) and lies inside `parent`; among cells of that size, the one whose
// centre is closest to `centre` (the first in the table's x, y, z order among equally close ones).
// Precondition: the true sphere lies inside `parent` (then the parent's own cell, S = 7620,
// always qualifies); returns -1 when nothing qualifies.
int encode_sphere(const Sphere& parent, const double centre[3], double radius,
                  SphereSearch search = SphereSearch::kNearestFirst);

// encode_sphere for the children of one parent: what depends on the parent alone is computed
// once. encode_sphere(p, c, r, s) is SphereEncoder(p)(c, r, s).
class SphereEncoder {
 public:
  explicit SphereEncoder(const Sphere& parent);
  int operator()(const double centre[3], double radius,
                 SphereSearch search = SphereSearch::kNearestFirst) const;

 private:
  Sphere parent_;
  double pc_[3], pr_;
  // How far (in parent radii) float rounding may move a decoded cell, and the same in steps of
  // the cell grid.
  double unsure_, unsure_steps_;
};

// Unit normal -> 14-bit code (nearest decoded normal among the original's candidate and its
// neighbours); a zero normal encodes as +Z.
int encode_normal(const Vec3f& n);
// Code (< kNormalCodes) -> unit normal. Codes whose two stored components exceed the unit circle
// (never written) decode to the normalised (u, v, 0) direction plus the axis.
const Vec3f& decode_normal(int code);

// Half-width θ (radians, ≥ 0) -> 2-bit cone code.
int encode_cone(double theta);
// Bound on sin θ for cone code c (1 for c = 3, which disables culling).
inline float decode_cone_sine(int c) { return static_cast<float>((1 + c) * (1 + c)) / 16.0f; }

// 8-bit RGB -> 5-6-5 word, and back.
inline uint16_t encode_rgb565(int r, int g, int b) {
  return static_cast<uint16_t>(((r >> 3) << 11) | ((g >> 2) << 5) | (b >> 3));
}
inline std::array<uint8_t, 3> decode_rgb565(uint16_t w) {
  const unsigned r = w >> 11, g = (w >> 5) & 63u, b = w & 31u;
  return {static_cast<uint8_t>((r << 3) | (r >> 2)), static_cast<uint8_t>((g << 2) | (g >> 4)),
          static_cast<uint8_t>((b << 3) | (b >> 2))};
}

}  // namespace splatkit::qsplat
