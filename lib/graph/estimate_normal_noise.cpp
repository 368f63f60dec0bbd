#include "graph/estimate_normal_noise.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "graph/vec3d.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kMinNeighbours = 6;  // 3 unknowns per fit, and some to spare

// Solves the symmetric 3x3 system m x = r (Cramer's rule); false when it is singular.
bool solve3(const std::array<double, 9>& m, const std::array<double, 3>& r,
            std::array<double, 3>& x) {
  auto det = [](const std::array<double, 9>& a) {
    return a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
           a[2] * (a[3] * a[7] - a[4] * a[6]);
  };
  const double d = det(m);
  if (!(std::fabs(d) > 1e-300)) return false;
  for (int c = 0; c < 3; ++c) {
    std::array<double, 9> t = m;
    for (int row = 0; row < 3; ++row) t[row * 3 + c] = r[row];
    x[c] = det(t) / d;
  }
  return true;
}

// RMS residual (radians) of the affine fit of S_i's continuous neighbours' normals; < 0 when
// there are too few neighbours or they are degenerate (collinear).
double fit_residual(std::size_t i, const NeighborGraph& g, std::span<const uint8_t> flags,
                    uint8_t sharp, std::span<const Vec3f> positions, std::span<const Vec3f> normals,
                    std::vector<std::array<double, 5>>& rows) {
  const Vec3d n = to_vec3d(normals[i]);
  // Any tangent frame will do: the fit is affine in (a, b), so the residual does not depend on it.
  const Vec3d w = std::fabs(n.x) < 0.6 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d u = cross(n, w) / norm(cross(n, w)), v = cross(n, u);
  rows.clear();
  for (uint64_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k) {
    if (flags[k] & sharp) continue;
    const uint32_t j = g.neighbors[k];
    const Vec3d d = to_vec3d(positions[j]) - to_vec3d(positions[i]);
    const Vec3d m = to_vec3d(normals[j]);
    rows.push_back({dot(d, u), dot(d, v), m.x, m.y, m.z});
  }
  if (rows.size() < kMinNeighbours) return -1;
  // The tangent coordinates are scaled by their RMS so the system is well conditioned.
  double scale = 0;
  for (const auto& r : rows) scale += r[0] * r[0] + r[1] * r[1];
  scale = std::sqrt(scale / double(rows.size()));
  if (!(scale > 0)) return -1;
  std::array<double, 9> m{};
  std::array<std::array<double, 3>, 3> rhs{};
  for (const auto& r : rows) {
    const double p[3] = {1, r[0] / scale, r[1] / scale};
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) m[a * 3 + b] += p[a] * p[b];
      for (int c = 0; c < 3; ++c) rhs[c][a] += p[a] * r[2 + c];
    }
  }
  std::array<std::array<double, 3>, 3> coef;
  for (int c = 0; c < 3; ++c)
    if (!solve3(m, rhs[c], coef[c])) return -1;
  double sum = 0;
  for (const auto& r : rows) {
    const double p[3] = {1, r[0] / scale, r[1] / scale};
    for (int c = 0; c < 3; ++c) {
      const double e = r[2 + c] - (coef[c][0] * p[0] + coef[c][1] * p[1] + coef[c][2] * p[2]);
      sum += e * e;
    }
  }
  return std::sqrt(sum / double(rows.size()));
}

}  // namespace

double estimate_normal_noise(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                             uint8_t sharp_mask, std::span<const Vec3f> positions,
                             std::span<const Vec3f> normals, std::size_t samples) {
  if (edge_flags.size() != graph.neighbors.size() || positions.size() != graph.num_points() ||
      normals.size() != graph.num_points())
    throw std::invalid_argument("estimate_normal_noise: sizes differ");
  if (samples == 0) throw std::invalid_argument("estimate_normal_noise: samples must be >= 1");
  const std::size_t stride = std::max<std::size_t>((graph.num_points() + samples - 1) / samples, 1);
  const std::size_t fits = (graph.num_points() + stride - 1) / stride;
  std::vector<double> residuals(fits);  // < 0 where the fit failed
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, fits, 256), [&](const tbb::blocked_range<std::size_t>& r) {
        std::vector<std::array<double, 5>> rows;
        for (std::size_t f = r.begin(); f < r.end(); ++f)
          residuals[f] =
              fit_residual(f * stride, graph, edge_flags, sharp_mask, positions, normals, rows);
      });
  std::erase_if(residuals, [](double r) { return !(r >= 0); });
  if (residuals.empty()) return 0;
  auto mid = residuals.begin() + std::ptrdiff_t(residuals.size() / 2);
  std::nth_element(residuals.begin(), mid, residuals.end());
  return *mid * 180 / std::numbers::pi;
}

}  // namespace splatkit::graph
