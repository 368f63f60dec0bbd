// The four quantisers of the QSplat .qs v11 node [Rusinkiewicz00] (layout: formats/qsplat.md),
// encoding and decoding, shared by the writer (lib/qsplat) and the reader (read_qsplat.h).
//
// - Sphere (13 bits): an index S into a table of 7621 cells (X, Y, Z, R) relative to the parent's
//   decoded sphere: centre = parent centre + parent radius · (X, Y, Z), radius = parent radius · R,
//   evaluated in float exactly as the original viewer does (decode_sphere).
//   encode_sphere is conservative (interior nodes): the decoded sphere contains the child's true
//   sphere and lies inside the decoded parent (both checked on the float values the reader
//   computes); SphereEncoder::nearest_disc (leaves) only keeps the latter and takes the cell
//   whose disc best matches the splat's.
// - Normal (14 bits): dominant axis A (0:+X 1:−X 2:+Y 3:−Y 4:+Z 5:−Z) and the two other components
//   warped by atan and quantised to 52 steps each. Angular error ≤ kNormalMaxError.
// - Cone (2 bits): c = int(4·√(sin θ)) of the half-width θ; decoded as the bound (1 + c)²/16 on
//   sin θ; c = 3 means "do not cull" (θ ≥ ~0.85 rad or θ > 1.5).
// - Colour (16 bits): RGB 5-6-5, each channel to the nearest code (formats/rgb565.h).
#pragma once

#include <array>
#include <cstdint>

#include "formats/rgb565.h"
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

// The slope of the views nearest_disc keeps a leaf's splat covered for: up to atan(1.25) = 51°
// from its normal.
inline constexpr double kDiscSlope = 1.25;
// SphereEncoder::nearest_disc: what a unit of bare band costs against a unit of grown band.
inline constexpr double kBareWeight = 3.0;

// encode_sphere for the children of one parent (what depends on the parent alone is computed
// once; encode_sphere(p, c, r, s) is SphereEncoder(p)(c, r, s)), and nearest_disc, the leaves'
// rule.
class SphereEncoder {
 public:
  explicit SphereEncoder(const Sphere& parent);
  // The code, -1 when no cell contains the child; `decoded` (optional) receives its decoded
  // sphere, decode_sphere's.
  int operator()(const double centre[3], double radius,
                 SphereSearch search = SphereSearch::kNearestFirst,
                 Sphere* decoded = nullptr) const;

  // The leaf rule (not conservative): the cell whose decoded disc (c', n, r') best matches the
  // leaf's disc (centre c, n, radius r), n the leaf's decoded unit normal, among the cells that
  // lie inside the parent: least  grown + kBareWeight · bare, with
  //   grown = max(0, r' + along − r)                      (the band the drawn disc adds),
  //   bare  = max(0, r + along + kDiscSlope · across − r') (the band of the splat it leaves
  //                                                        bare, at views up to 51° oblique),
  // along and across the lengths of c' − c in and across the plane normal to n. A grown band
  // rings every silhouette; a bare one is covered by the neighbours' overlap nearly everywhere
  // (single pixels open where one splat alone covers the surface), hence its larger weight.
  // Candidates: for the two sizes around 13 · r / R (R the parent's radius; one even, one odd:
  // the two offset grids of cell centres), the cell nearest c on every axis; when neither lies
  // inside the parent (a leaf on its parent's edge), the cells of sizes one beyond them with the
  // two nearest indices per axis, then, when none of those does either, every cell. Ties keep
  // the earlier candidate (sizes ascending, then x, y, z). Returns the code: never -1 for a
  // parent of positive radius (the parent's own cell lies inside it).
  int nearest_disc(const double centre[3], double radius, const Vec3f& normal,
                   Sphere* decoded = nullptr) const;

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

}  // namespace splatkit::qsplat
