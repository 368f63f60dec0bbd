#include "splatkit/splat_cloud.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "splatkit/for_each_chunk.h"

namespace splatkit {

float Bounds::diagonal() const { return empty() ? 0.0f : norm(max - min); }

const ExtraAttribute* SplatCloud::find_extra(const std::string& name) const {
  for (const auto& e : extras)
    if (e.name == name) return &e;
  return nullptr;
}

ExtraAttribute* SplatCloud::find_extra(const std::string& name) {
  for (auto& e : extras)
    if (e.name == name) return &e;
  return nullptr;
}

void SplatCloud::set_extra(ExtraAttribute a) {
  if (ExtraAttribute* old = find_extra(a.name))
    *old = std::move(a);
  else
    extras.push_back(std::move(a));
}

void SplatCloud::check_consistent() const {
  const std::size_t n = size();
  auto check = [n](std::size_t m, const char* what) {
    if (m != 0 && m != n)
      throw std::logic_error(std::string("splat cloud: ") + what + " has " + std::to_string(m) +
                             " entries for " + std::to_string(n) + " points");
  };
  check(normals.size(), "normals");
  check(radii.size(), "radii");
  check(colors.size(), "colors");
  check(axes.size(), "axes");
  check(minor_radii.size(), "minor radii");
  if (axes.empty() != minor_radii.empty() || (!axes.empty() && (radii.empty() || normals.empty())))
    throw std::logic_error("splat cloud: ellipse axes need minor radii, radii and normals");
  for (const auto& e : extras)
    if (e.values.size() != n)
      throw std::logic_error("splat cloud: extra attribute '" + e.name + "' has " +
                             std::to_string(e.values.size()) + " entries for " + std::to_string(n) +
                             " points");
  if (color_bits != 8 && color_bits != 16) throw std::logic_error("splat cloud: color_bits");
  if (!face_offsets.empty()) {
    if (face_offsets.front() != 0 || face_offsets.back() != face_indices.size())
      throw std::logic_error("splat cloud: face offsets do not span the indices");
    // Any violation, in parallel chunks of branch-free (vectorisable) loops: a mesh's faces are
    // tens of MB, and these checks ran on one thread while the other waited.
    constexpr std::size_t kChunk = std::size_t{1} << 18;
    const auto any_in_chunks = [](std::size_t count, auto&& bad) {
      std::vector<uint8_t> hit(chunk_count(count, kChunk), 0);
      for_each_chunk(count, kChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
        bool h = false;
        for (std::size_t i = b; i < e; ++i) h |= bad(i);
        hit[c] = h;
      });
      return std::find(hit.begin(), hit.end(), 1) != hit.end();
    };
    if (any_in_chunks(face_offsets.size() - 1,
                      [&](std::size_t f) { return face_offsets[f + 1] < face_offsets[f]; }))
      throw std::logic_error("splat cloud: face offsets decrease");
    const uint32_t* idx = face_indices.data();
    if (any_in_chunks(face_indices.size(), [&](std::size_t i) { return idx[i] >= n; }))
      throw std::logic_error("splat cloud: face index out of range");
  }
}

Bounds compute_bounds(const SplatCloud& cloud) { return compute_bounds(cloud.positions); }

Bounds compute_bounds(std::span<const Vec3f> positions) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  auto add = [](Bounds b, const Vec3f& lo, const Vec3f& hi) {
    b.min = {std::min(b.min.x, lo.x), std::min(b.min.y, lo.y), std::min(b.min.z, lo.z)};
    b.max = {std::max(b.max.x, hi.x), std::max(b.max.y, hi.y), std::max(b.max.z, hi.z)};
    return b;
  };
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, positions.size(), 1 << 16),
      Bounds{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}},
      [&](const auto& r, Bounds b) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) b = add(b, positions[i], positions[i]);
        return b;
      },
      [&](const Bounds& a, const Bounds& b) { return add(a, b.min, b.max); });
}

std::array<double, 3> choose_origin(const std::array<double, 3>& p) {
  const double m = std::max({std::fabs(p[0]), std::fabs(p[1]), std::fabs(p[2])});
  if (!(m >= 1e4) || !std::isfinite(m)) return {0, 0, 0};
  return {std::trunc(p[0] / 1000) * 1000, std::trunc(p[1] / 1000) * 1000,
          std::trunc(p[2] / 1000) * 1000};
}

std::array<double, 3> choose_origin_from_sample(
    std::span<const std::array<double, 3>> first_points) {
  if (first_points.empty()) return {0, 0, 0};
  const auto sample = first_points.first(std::min(first_points.size(), kOriginSampleSize));
  const std::array<double, 3> first = choose_origin(sample.front());
  // Beyond this distance from the bulk of the sample a first point is a stray one: choose_origin
  // keeps coordinates up to 1e4 unshifted, so nearer than that the first point's origin costs no
  // precision that matters.
  constexpr double kSlack = 1e4;
  const std::size_t n = sample.size();
  std::vector<double> v(n);
  std::array<double, 3> median{};
  bool representative = true;
  for (int k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < n; ++i) v[i] = sample[i][k];
    const std::size_t lo = n / 20, mid = n / 2, hi = n - 1 - n / 20;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    median[k] = v[mid];
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(lo), v.end());
    const double q_lo = v[lo];
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(hi), v.end());
    const double q_hi = v[hi];
    representative = representative && first[k] >= q_lo - kSlack && first[k] <= q_hi + kSlack;
  }
  return representative ? first : choose_origin(median);
}

}  // namespace splatkit
