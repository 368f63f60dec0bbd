// cover_splat: the smallest splat centred on a point that covers the point's cell of the surface,
// so that the splats of a cloud leave no hole whatever the sampling (i.i.d. random, scan lines).
//
// The cell is the point's Voronoi cell among its neighbours, in its tangent plane: the neighbours
// are projected onto the plane through `center` perpendicular to `normal`, and the cell is the set
// of points of that plane nearer to the centre than to any projected neighbour. Every point of the
// surface near the centre lies in the cell of some sample, up to curvature (the tangent planes of
// neighbouring samples differ by the angle between their normals), so discs that reach the
// farthest vertex of their cell cover the surface.
//
// Neighbours more than 60° above or below the tangent plane are left out: they belong to another
// sheet of the surface (across a crease, the far side of a thin part), and cutting the cell at
// their projection would leave a strip near the crease that no splat of this sheet covers.
//
// The cell starts as the square |x|, |y| <= D, D the distance to the farthest neighbour of the
// row, which holds any cell the row's neighbours close. A cell that still touches that square is
// open (the border of an open surface, a thread of points, a row too short for the sampling's
// anisotropy): its splat is cut at `open_cap` (a circle's radius, an ellipse's semi-axes). A cell
// open to one side only (the mean of the unit directions of its vertices on the square at least
// 0.5 long: a border) is first cut open_cap / 4 past the centre across that side, where the
// surface ends (half the mean kNN distance past the border samples, for the default cap), so that
// border splats do not reach open_cap beyond the border.
//
//  - Circle: radius = distance to the cell's farthest vertex.
//  - Ellipse: axes along the principal directions of the cell's second moment of area (about the
//    centre), aspect ratio sqrt(λ_min / λ_max) (at most kMaxEllipseAspect), scaled so that every
//    vertex of the cell lies inside; where that ellipse is no smaller than the circle, the circle
//    (as an ellipse with equal semi-axes). On scan lines (dense along, sparse across) the cell is a
//    long thin polygon, and the ellipse covers it with about half the circle's area.
//
// Neighbours at distance 0 (duplicates) and neighbours that project onto the centre are skipped.
// Computed in double; deterministic. Never NaN for finite input; a point with no usable neighbour
// gets radius `open_cap` (its cell is the whole square).
#pragma once

#include <cstdint>
#include <span>

#include "splatkit/vec3.h"

namespace splatkit {

// Longest ellipse axis over the shortest: cells thinner than this are covered by an ellipse of
// this aspect ratio (bounds the splat's screen footprint and its numerical conditioning).
inline constexpr float kMaxEllipseAspect = 8.0f;

// Two splats whose normals are more than 25° apart (either sign) lie on different sheets of the
// surface: across a crease, or on the two sides of a thin part.
inline constexpr float kSameSheetCos = 0.9063078f;  // cos 25°

struct SplatShape {
  float radius = 0;        // circle radius, or the ellipse's larger semi-axis (along axis)
  float minor_radius = 0;  // the ellipse's smaller semi-axis (= radius for a circle)
  Vec3f axis{1, 0, 0};     // unit, in the tangent plane: direction of the larger semi-axis
  bool open = false;       // the row's neighbours left the cell open (see above)
};

// center: the splat's centre; normal: its unit normal; neighbors: positions[row[j]] for the
// entries of `row` that are not SpatialIndex::kNone (the centre itself may be among them and is
// skipped like any point at distance 0). open_cap > 0 (see above). ellipse: false gives a circle
// (minor_radius = radius).
// normals: empty, or the unit normals of `positions` (either sign): then a neighbour whose normal
// is more than 25° from `normal` lies on another sheet (across a crease that the 60° test misses,
// such as a turn of 60°) and bounds the cell at its own projection rather than half-way, so that
// this sheet's splat reaches the crease, up to where the other sheet's samples begin.
SplatShape cover_splat(const Vec3f& center, const Vec3f& normal, std::span<const Vec3f> positions,
                       std::span<const uint32_t> row, float open_cap, bool ellipse,
                       std::span<const Vec3f> normals = {});

// A unit vector perpendicular to the unit vector n, a continuous choice over the sphere but for
// one seam (Duff et al. 2017, branchless orthonormal basis): the first axis of the tangent basis
// cover_splat works in.
Vec3f tangent_axis(const Vec3f& n);

}  // namespace splatkit
