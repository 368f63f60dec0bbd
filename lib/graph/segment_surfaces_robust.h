// Segmentation into smooth surfaces that does not leak across noisy creases (beyond the
// breadth-first segmentation of [IvoMSc] §5.4, docs/references.md; the default of
// build_splat_graph and segment-surfaces).
//
// segment_surfaces (the thesis's BFS) joins every continuous edge, so one chain of splats whose
// normals turn by less than the sharp angle per step merges two faces. Noisy creases are made of
// such chains: near a crease the estimated normals blend from one face to the other over a band
// a few splats wide (robust normals at 0.125 % noise: RMS error 30° within 2 spacings of a
// crease, 3.6° beyond), so every patch of a noisy CAD part ends up in one surface.
//
// Here a splat is a *core* splat when every continuous neighbour's normal is within the core
// angle of its own, n_i·n_j >= core_threshold (a stricter test than the sharp one; sharp
// neighbours are ignored, so surfaces that cross each other keep their cores). Then:
//   1. cores are joined over continuous edges between two cores (union-find); components with
//      fewer than min_core_size splats are not cores (islands of agreeing normals in a band);
//   2. every other splat takes the surface of the nearest core (in hops) by a breadth-first
//      search over continuous edges from all cores at once, one hop per round; within a round
//      the givers go in ascending index order and the first one wins, so the result is fixed;
//   3. splats that no core reaches form surfaces of their own: components of their continuous
//      edges (what segment_surfaces would give them).
// Ids are given in the order of each surface's lowest splat index. Where each component of the
// continuous edges holds one core component the result equals segment_surfaces' exactly; where
// a component holds several (a leak), it is split between them. With noisy normals, a smooth
// but strongly curved strip (normals turning by more than the core angle between neighbours,
// e.g. a fillet or a thin cylinder sampled with few splats across) splits too.
#pragma once

#include <cstdint>
#include <optional>
#include <span>

#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

struct RobustSegmentOptions {
  // n_i·n_j every continuous neighbour of a core splat reaches, in [-1, 1]. None: automatic —
  // default_core_threshold(sharp_threshold) when estimate_normal_noise finds the normals noisy
  // (>= noisy_degrees); for clean normals sharp_threshold itself, which makes every splat a core
  // and the result exactly segment_surfaces' (a curved patch sampled coarsely — neighbours
  // 13°–26° apart — would otherwise fall apart into islands), unless those components run across
  // the creases: when at least leak_share of the sharp edges join two splats of one component,
  // default_core_threshold again. (PCA normals of a clean scan are exact on the faces, so not
  // noisy, but blend from face to face across every crease: components merged all faces of a
  // clean cube, CAD part or pair of crossing spheres into one.)
  std::optional<float> core_threshold;
  float sharp_threshold = 0.9f;  // w_s the edge flags were computed with
  double noisy_degrees = 0.75;   // measured: exact or clean robust normals <= 0.4° (a torus of
                                 // 10 k splats), the noisy CAD part >= 1.25° (50 k–1 M splats)
  double leak_share = 0.5;       // measured on clean cube, CAD part and crossing spheres, random
                                 // and scan-line samplings, 6 k–300 k splats: PCA normals
                                 // 0.74–1.0 (every one a single surface), exact normals <= 0.09,
                                 // robust normals <= 0.47 except a scan-line cube at 0.87 (which
                                 // leaked too)
  uint32_t min_core_size = 10;   // smaller core components are not cores (>= 1)
};

// What the automatic choice saw and chose.
struct RobustSegmentInfo {
  double normal_noise_degrees = 0;  // estimate_normal_noise (0 when not needed: threshold given)
  double sharp_edges_within = 0;    // share of the sharp edges inside one component (0 when not
                                    // needed: threshold given or noisy normals)
  float core_threshold = 0;         // the threshold used
};

// The default core threshold for a sharp threshold w_s: the cosine of half its angle,
// sqrt((1 + w_s) / 2) (0.9747, 12.9° for w_s = 0.9). Chosen on the noisy CAD part
// (segmentation-quality.sh): at 1 M splats 10° splits curved patches into islands and 16° leaks
// across the 120° creases.
float default_core_threshold(float sharp_threshold);

// graph, edge_flags, sharp_mask as for segment_surfaces (symmetric flags). positions, normals:
// #N each, the splats the graph was built from (a NaN normal makes its splat not a core).
// Throws std::invalid_argument when the sizes do not match or min_core_size is 0. Independent of
// thread count; O(E α(N)) plus the noise estimate on 8192 splats.
Segmentation segment_surfaces_robust(const NeighborGraph& graph,
                                     std::span<const uint8_t> edge_flags, uint8_t sharp_mask,
                                     std::span<const Vec3f> positions,
                                     std::span<const Vec3f> normals,
                                     const RobustSegmentOptions& options,
                                     RobustSegmentInfo* info = nullptr);

}  // namespace splatkit::graph
