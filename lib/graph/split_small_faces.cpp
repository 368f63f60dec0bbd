#include "graph/split_small_faces.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "graph/fit_robust_plane.h"
#include "graph/off_plane_pieces.h"
#include "graph/plane_residual_scale.h"
#include "graph/renumber_surfaces.h"
#include "splatkit/pca_normal.h"

namespace splatkit::graph {
namespace {

// The noise of `piece`'s splats about planes through their neighbours in the piece (each splat
// left out of its own plane); infinity when none has 5 such neighbours. `piece` ascending.
double local_scale(const NeighborGraph& graph, std::span<const Vec3f> positions,
                   const std::vector<uint32_t>& piece) {
  PlaneResidualScale scale;
  for (uint32_t i : piece) {
    const Vec3d p = to_vec3d(positions[i]);
    for (uint64_t e = graph.offsets[i]; e < graph.offsets[i + 1]; ++e) {
      const uint32_t j = graph.neighbors[e];
      if (std::binary_search(piece.begin(), piece.end(), j)) scale.add(to_vec3d(positions[j]) - p);
    }
    scale.close();
  }
  return scale.scale();
}

// The width of the splats along their shorter in-plane axis: √12 × the root of the middle
// eigenvalue of their covariance (the width of a uniform strip from its standard deviation).
double width(std::span<const Vec3f> positions, const std::vector<uint32_t>& piece) {
  const Vec3d origin = to_vec3d(positions[piece[0]]);
  Vec3d mean;
  for (uint32_t i : piece) mean += to_vec3d(positions[i]) - origin;
  mean = mean / double(piece.size());
  std::array<double, 6> cov{};
  for (uint32_t i : piece) {
    const Vec3d d = to_vec3d(positions[i]) - origin - mean;
    cov[0] += d.x * d.x, cov[1] += d.x * d.y, cov[2] += d.x * d.z;
    cov[3] += d.y * d.y, cov[4] += d.y * d.z, cov[5] += d.z * d.z;
  }
  for (double& c : cov) c /= double(piece.size());
  return std::sqrt(12 * pca_normal(cov).eigenvalues[1]);
}

}  // namespace

Segmentation split_small_faces(const NeighborGraph& graph, std::span<const Vec3f> positions,
                               std::span<const Vec3f> normals, std::span<const float> radii,
                               Segmentation seg, const SplitSmallFacesOptions& o, uint32_t* split) {
  const std::size_t n = graph.num_points();
  if (positions.size() != n || normals.size() != n || radii.size() != n || seg.surface.size() != n)
    throw std::invalid_argument("split_small_faces: one position, normal, radius and id per splat");
  const uint32_t count = seg.count();
  for (uint32_t s : seg.surface)
    if (s >= count) throw std::invalid_argument("split_small_faces: surface id out of range");
  if (split) *split = 0;
  if (!(o.offset_scales > 0)) return seg;
  const uint32_t min_size = std::max<uint32_t>(o.min_size, 3);
  OffPlanePieces off = off_plane_pieces(graph, positions, normals, radii, seg, o.offset_scales,
                                        o.max_normal_degrees, o.max_splat_degrees, min_size);
  const std::vector<RobustPlane>& planes = off.planes;
  std::vector<std::vector<uint32_t>>& pieces = off.pieces;
  const double cos_splat = std::cos(o.max_splat_degrees * std::numbers::pi / 180);
  std::vector<uint8_t> face(pieces.size(), 0);
  tbb::parallel_for(std::size_t{0}, pieces.size(), [&](std::size_t k) {
    const std::vector<uint32_t>& piece = pieces[k];
    const RobustPlane& whole = planes[seg.surface[piece[0]]];
    const RobustPlane own = fit_robust_plane(positions, normals, radii, piece, o.max_face_degrees);
    face[k] = own.planar && std::abs(dot(own.normal, whole.normal)) < cos_splat &&
              own.scale <= 2 * local_scale(graph, positions, piece) + 1e-9 &&
              width(positions, piece) >= 2 * own.diameter;
  });
  std::vector<uint32_t> label = std::move(seg.surface);
  uint32_t labels = count;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (!face[k]) continue;
    for (uint32_t i : pieces[k]) label[i] = labels;
    ++labels;
  }
  if (split) *split = labels - count;
  return renumber_surfaces(label, labels);
}

}  // namespace splatkit::graph
