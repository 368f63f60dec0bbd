#include "qsplat/make_qsplat_leaves.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/sized_in_parallel.h"
#include "splatkit/slot_array.h"
#include "splatkit/vertex_normals.h"

namespace splatkit::qsplat {

namespace {

std::array<uint8_t, 3> to_rgb8(const std::array<uint16_t, 3>& c, int bits) {
  std::array<uint8_t, 3> out{};
  for (int k = 0; k < 3; ++k)
    out[k] = static_cast<uint8_t>(bits == 16 ? (c[k] * 255 + 32767) / 65535 : c[k]);
  return out;
}

// Squared radius of the smallest sphere around triangle (a, b, c), n its (unnormalised) normal:
// a quarter of the longest edge's square when the triangle is right or obtuse, else the squared
// circumradius. Squared, so that a vertex takes one square root for all its triangles (the root
// is monotonic and correctly rounded: the root of the largest square is the largest root, and
// sqrt(x / 4) is sqrt(x) / 2 to the bit).
double triangle_sphere_radius2(const Vec3f& a, const Vec3f& b, const Vec3f& c, const Vec3f& n) {
  const double ab = squared_distance(a, b), bc = squared_distance(b, c),
               ca = squared_distance(c, a);
  const double longest = std::max({ab, bc, ca});
  if (2 * longest >= ab + bc + ca) return 0.25 * longest;
  const double area2 = squared_norm(n);  // (2·area)²
  if (!(area2 > 0)) return 0.25 * longest;
  return ab * bc * ca / (4.0 * area2);
}

void add_leaf(QSplatLeaves& out, const SplatCloud& cloud, std::size_t i, const Vec3f& n, float r) {
  out.positions.push_back(cloud.positions[i]);
  out.normals.push_back(n);
  out.radii.push_back(r);
  if (cloud.has_colors()) out.colors.push_back(to_rgb8(cloud.colors[i], cloud.color_bits));
}

// Why a mesh vertex is no leaf, or kUsable.
enum Drop : uint8_t { kUsable, kUnused, kZeroRadius, kZeroNormal };

QSplatLeaves from_mesh(SplatCloud& cloud) {
  const std::size_t n = cloud.size();
  // vertex_normals' sums and each vertex's largest triangle sphere (its squared radius), in one
  // pass over the faces.
  // Uninitialised, then set in parallel chunks: their pages (20 bytes a vertex) are faulted in
  // on both threads instead of by one zeroing pass.
  SlotArray<Vec3f> normal;
  SlotArray<double> radius;  // -1: no face uses the vertex
  normal.allocate(n);
  radius.allocate(n);
  for_each_chunk(n, std::size_t{1} << 16, [&](std::size_t, std::size_t b, std::size_t e) {
    std::fill(normal.get() + b, normal.get() + e, Vec3f{0, 0, 0});
    std::fill(radius.get() + b, radius.get() + e, -1.0);
  });
  for_each_triangle_by_vertex_range(
      cloud, [&](const std::array<uint32_t, 3>& t, uint32_t lo, uint32_t hi) {
        const Vec3f &p0 = cloud.positions[t[0]], &p1 = cloud.positions[t[1]],
                    &p2 = cloud.positions[t[2]];
        const Vec3f fn = cross(p1 - p0, p2 - p0);
        const double r2 = triangle_sphere_radius2(p0, p1, p2, fn);
        for (uint32_t v : t)
          if (v >= lo && v < hi) {
            normal[v] += fn;
            radius[v] = std::max(radius[v], r2);
          }
      });
  // A face of fewer than 3 vertices has no triangle but uses its vertices (rare: found first,
  // in parallel, the faces then walked on one thread only when there is one).
  const std::size_t faces = cloud.face_count();
  const auto short_face = [&](std::size_t f) {
    return cloud.face_offsets[f + 1] - cloud.face_offsets[f] < 3;
  };
  for (std::size_t f = first_in_chunks(faces, std::size_t{1} << 18, short_face); f < faces; ++f)
    if (short_face(f))
      for (uint32_t k = cloud.face_offsets[f]; k < cloud.face_offsets[f + 1]; ++k)
        radius[cloud.face_indices[k]] = std::max(radius[cloud.face_indices[k]], 0.0);
  // Leaves in vertex order: each chunk counts its usable vertices, then writes them after the
  // earlier chunks' (the arrays sized once, in parallel).
  constexpr std::size_t kChunk = std::size_t{1} << 16;
  std::vector<uint8_t> drop(n);
  std::vector<std::size_t> first(chunk_count(n, kChunk) + 1, 0);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    std::size_t kept = 0;
    for (std::size_t i = b; i < e; ++i) {
      drop[i] = radius[i] < 0                    ? kUnused
                : !(radius[i] > 0)               ? kZeroRadius
                : !(squared_norm(normal[i]) > 0) ? kZeroNormal
                                                 : kUsable;
      kept += drop[i] == kUsable;
    }
    first[c + 1] = kept;
  });
  for (std::size_t c = 1; c < first.size(); ++c) first[c] += first[c - 1];
  QSplatLeaves out;
  const std::size_t m = first.back();
  // Every vertex kept (the usual mesh): the leaves take the cloud's positions as they are.
  const bool all_kept = m == n;
  if (all_kept)
    out.positions = std::move(cloud.positions);
  else
    sized_in_parallel(out.positions, m);
  sized_in_parallel(out.normals, m);
  sized_in_parallel(out.radii, m);
  if (cloud.has_colors()) sized_in_parallel(out.colors, m);
  for_each_chunk(n, kChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
    std::size_t j = first[c];
    for (std::size_t i = b; i < e; ++i) {
      if (drop[i] != kUsable) continue;
      if (!all_kept) out.positions[j] = cloud.positions[i];
      out.normals[j] = normalized(normal[i]);
      out.radii[j] = static_cast<float>(std::sqrt(radius[i]));
      if (cloud.has_colors()) out.colors[j] = to_rgb8(cloud.colors[i], cloud.color_bits);
      ++j;
    }
  });
  for (uint8_t d : drop) {
    out.dropped_unused += d == kUnused;
    out.dropped_zero_radius += d == kZeroRadius;
    out.dropped_zero_normal += d == kZeroNormal;
  }
  return out;
}

QSplatLeaves from_splats(SplatCloud& cloud, const std::string& name) {
  if (cloud.size() == 0) throw_bad_input(name, "the file has no points");
  if (!cloud.has_normals() || !cloud.has_radii())
    throw_bad_input(name, std::string("the splats have no ") +
                              (cloud.has_normals() ? "radii" : "normals") +
                              " (and no faces); run estimate-normals first");
  const std::size_t n = cloud.size();
  // The usual case, every splat usable: the arrays copied in parallel. Otherwise the loop below,
  // which drops and reports in input order.
  const bool all_usable = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n, 1 << 14), true,
      [&](const auto& r, bool ok) {
        for (std::size_t i = r.begin(); ok && i < r.end(); ++i) {
          const float len2 = squared_norm(cloud.normals[i]);
          ok = std::isfinite(cloud.radii[i]) && cloud.radii[i] > 0 && std::isfinite(len2) &&
               len2 > 0;
        }
        return ok;
      },
      std::logical_and<>());
  QSplatLeaves out;
  if (all_usable) {  // the cloud's arrays become the leaves' (colours narrowed to 8 bits)
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) {
        Vec3f& nv = cloud.normals[i];
        if (squared_norm(nv) != 1.0f) nv = normalized(nv);
      }
    });
    if (cloud.has_colors()) {
      sized_in_parallel(out.colors, n);
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
        for (std::size_t i = r.begin(); i < r.end(); ++i)
          out.colors[i] = to_rgb8(cloud.colors[i], cloud.color_bits);
      });
      std::vector<std::array<uint16_t, 3>>().swap(cloud.colors);
    }
    out.positions = std::move(cloud.positions);
    out.normals = std::move(cloud.normals);
    out.radii = std::move(cloud.radii);
    return out;
  }
  out.positions.reserve(n);
  out.normals.reserve(n);
  out.radii.reserve(n);
  if (cloud.has_colors()) out.colors.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const float r = cloud.radii[i];
    const Vec3f& nv = cloud.normals[i];
    if (r == 0) {
      ++out.dropped_zero_radius;
      continue;
    }
    if (!(std::isfinite(r) && r > 0))
      throw_bad_input(name, "splat " + std::to_string(i) + ": radius " + std::to_string(r) +
                                " is not a positive number");
    const float len2 = squared_norm(nv);
    if (!(std::isfinite(len2) && len2 > 0))
      throw_bad_input(name, "splat " + std::to_string(i) + ": normal is zero or not finite");
    add_leaf(out, cloud, i, len2 == 1.0f ? nv : normalized(nv), r);
  }
  return out;
}

}  // namespace

QSplatLeaves make_qsplat_leaves(SplatCloud cloud, const std::string& name) {
  return cloud.face_count() > 0 ? from_mesh(cloud) : from_splats(cloud, name);
}

}  // namespace splatkit::qsplat
