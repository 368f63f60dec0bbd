// The splat cloud: structure-of-arrays storage shared by every tool.
//
// Positions are float32 in a local frame; `origin` (float64) is added back to get the file's
// coordinates. Readers set origin with choose_origin_from_sample() so that georeferenced scans
// (UTM, LAS offsets) keep millimetre precision in float, even when the file starts with a stray
// point such as (0, 0, 0). Optional attributes are either empty or hold
// exactly size() entries. Colours keep the source depth (8 or 16 bits per channel) losslessly.
// Extra per-point attributes (intensity, classification, any unknown PLY property, ...) are
// carried through by name with their original scalar type.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "splatkit/extra_values.h"
#include "splatkit/scalar_type.h"
#include "splatkit/vec3.h"

namespace splatkit {

struct ExtraAttribute {
  ExtraAttribute() = default;
  ExtraAttribute(std::string attribute_name, ScalarType type)
      : name(std::move(attribute_name)), values(type) {}
  ExtraAttribute(std::string attribute_name, ScalarType type, const std::vector<double>& v)
      : ExtraAttribute(std::move(attribute_name), type) {
    values.reserve(v.size());
    for (double x : v) values.push_back(x);
  }
  // The type in the source file, used again when writing; the values are held at its width.
  ScalarType type() const { return values.type(); }

  std::string name;
  ExtraValues values;  // size() entries
};

struct Bounds {
  Vec3f min{0, 0, 0}, max{0, 0, 0};  // local frame; min > max when the cloud is empty
  bool empty() const { return min.x > max.x; }
  Vec3f center() const { return (min + max) * 0.5f; }
  float diagonal() const;
};

struct SplatCloud {
  std::array<double, 3> origin{0, 0, 0};
  std::vector<Vec3f> positions;                 // #N, local frame
  std::vector<Vec3f> normals;                   // #N unit vectors, or empty
  std::vector<float> radii;                     // #N disc radii (same units as positions), or empty
  std::vector<std::array<uint16_t, 3>> colors;  // #N RGB, or empty
  int color_bits = 8;                           // 8 or 16: range of `colors` is [0, 2^bits - 1]
  std::vector<ExtraAttribute> extras;           // each with #N values
  // Polygonal faces when the source had them (PLY, OFF): CSR of vertex indices.
  std::vector<uint32_t> face_offsets;  // #F+1 (empty when there are no faces)
  std::vector<uint32_t> face_indices;
  // Scanner position (file coordinates) when the source records one (PCD VIEWPOINT, ...).
  std::optional<std::array<double, 3>> viewpoint;
  // Elliptic splats (both empty for circular ones): #N unit axes u in the splat's plane
  // (perpendicular to its normal) and #N semi-axes along v = normal × u. `radii` then holds the
  // semi-axis along u, the larger one, so it stays the splat's bounding-sphere radius and every
  // consumer that knows only circles draws a disc that contains the ellipse.
  std::vector<Vec3f> axes;
  std::vector<float> minor_radii;

  std::size_t size() const { return positions.size(); }
  std::size_t face_count() const { return face_offsets.empty() ? 0 : face_offsets.size() - 1; }
  bool has_normals() const { return !normals.empty(); }
  bool has_radii() const { return !radii.empty(); }
  bool has_ellipses() const { return !axes.empty(); }
  bool has_colors() const { return !colors.empty(); }
  const ExtraAttribute* find_extra(const std::string& name) const;
  ExtraAttribute* find_extra(const std::string& name);
  // Replaces the attribute of a's name, or appends a.
  void set_extra(ExtraAttribute a);

  // Throws std::logic_error when an attribute array does not match size(), when axes and
  // minor_radii are not both empty or both present with radii and normals, or a face index is out
  // of range. Readers call it before returning so that every consumer can rely on the invariants.
  void check_consistent() const;
};

// Bounding box of the positions (local frame).
Bounds compute_bounds(const SplatCloud& cloud);
// The bounds of the positions, in parallel (min > max when empty).
Bounds compute_bounds(std::span<const Vec3f> positions);

// Origin for a cloud whose first point (file coordinates) is p: zero when every |p_i| < 1e4,
// otherwise p truncated to a multiple of 1000 — keeps local float coordinates small.
std::array<double, 3> choose_origin(const std::array<double, 3>& p);

// How many of a file's first points the readers look at to choose the origin.
inline constexpr std::size_t kOriginSampleSize = 256;

// Origin for a cloud from its first points (file coordinates, file order, finite; at most
// kOriginSampleSize are used): choose_origin(first point), unless on some axis that origin lies
// more than 1e4 outside the range of the middle 90 % of the sample (the first point is a stray
// one, e.g. (0, 0, 0) ahead of a UTM scan); then choose_origin(per-axis median of the sample).
// Zero for an empty sample. A cloud whose first point is representative keeps the origin
// choose_origin(first point) gives.
std::array<double, 3> choose_origin_from_sample(
    std::span<const std::array<double, 3>> first_points);

}  // namespace splatkit
