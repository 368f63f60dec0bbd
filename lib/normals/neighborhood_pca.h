// neighborhood_pca: the PCA normal of a point's neighbourhood ([Hoppe92]; [Carvalho09] §2.1.1;
// docs/references.md):
// C = Σ (x_j − x̄)(x_j − x̄)ᵀ over the neighbourhood, normal = eigenvector of the smallest
// eigenvalue of C, from the closed-form solver splatkit/pca_normal.h.
//
// Accumulated in double in one pass, relative to the first point of the neighbourhood, so clouds
// far from the origin or with tiny spacing keep their precision. The normal is a unit vector with a
// canonical sign (its largest-magnitude component positive, the first such component on ties) so
// that the unoriented result is fully determined by the set of points. Never NaN: an empty or
// single-point neighbourhood gives (0, 0, 1) and degenerate = true.
//
// Degenerate (fewer than 3 distinct points, or rank < 2): the middle eigenvalue is at most
// kCollinearRatio times the largest one (points on a line, or all identical). Such a normal is an
// arbitrary perpendicular and must be replaced from a wider neighbourhood.
#pragma once

#include <cstdint>
#include <span>

#include "splatkit/vec3.h"

namespace splatkit {

struct PcaNormal {
  Vec3f normal{0, 0, 1};  // unit, canonical sign
  Vec3f axis{1, 0, 0};  // unit eigenvector of the largest eigenvalue (the line of a collinear set)
  double eigenvalues[3] = {0, 0, 0};  // of C, ascending
  bool degenerate = true;
};

inline constexpr double kCollinearRatio = 1e-6;

// PCA over positions[indices[j]] for the entries of `indices` that are not kNone (UINT32_MAX).
// Every index must be < positions.size().
PcaNormal neighborhood_pca(std::span<const Vec3f> positions, std::span<const uint32_t> indices);

// Whether the neighbourhood `indices` of point `centre`, with PCA `pca`, is a thread of points
// rather than a piece of surface: degenerate; or its middle eigenvalue below kThinRatio of the
// largest (one straight scan line, with none of the next lines among the points); or below
// kThreadCheckRatio of it with every neighbour close to the line through the centre along the
// principal axis (the mean squared sine of the angle between the centre-to-neighbour direction
// and the axis below kThreadSin2: one curved scan line, whose curvature alone lifts the middle
// eigenvalue). The PCA plane of a thread is the line's osculating plane, not the surface's.
inline constexpr double kThinRatio = 1e-2;
inline constexpr double kThreadCheckRatio = 0.1;
inline constexpr double kThreadSin2 = 0.05;
bool is_thread(const PcaNormal& pca, std::span<const Vec3f> positions, uint32_t centre,
               std::span<const uint32_t> indices);

// The sign convention of neighborhood_pca: n or -n, whichever has its largest-magnitude component
// positive (first of x, y, z on ties).
Vec3f canonical_sign(const Vec3f& n);

}  // namespace splatkit
