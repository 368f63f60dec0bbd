// SpatialIndex: exact k-nearest-neighbour, fixed-radius and sphere-overlap queries over a static
// set of 3D points, built for the batch case "for every point, find its neighbours".
//
// Design: a balanced kd-tree (median split on the widest axis of each node's tight bounding box)
// with 2^D leaves of (about) max_leaf_size / 2 to max_leaf_size points. The points are copied in
// the tree's own order into three coordinate arrays (structure of arrays), so a leaf is a
// contiguous run scanned four points at a time, and the batch queries walk the points in that
// order, so consecutive queries share cache lines and tree paths. Every node stores its tight box;
// the layout is implicit (heap order), so there are no child pointers. Batch kNN works leaf by
// leaf: the leaf's queries share one candidate set, the points within a guessed reach of the
// leaf's box (the previous leaf's largest squared k-th distance + 10 %), and each query ranks those
// candidates (with AVX2, when the CPU has it, without data-dependent branches); a query whose
// k-th neighbour lies beyond the reach — its answer could be outside the set — falls back to an
// ordinary search that starts in its own leaf and climbs. Candidates are (squared distance,
// index) packed in one uint64_t.
//
// Memory: 16 bytes/point (12 for coordinates, 4 for the original index) plus 48 bytes per leaf
// for the boxes (≈ 2 bytes/point at the default max_leaf_size of 32). Building needs another
// 16 bytes/point transiently.
//
// Every answer is exact and fully determined: neighbours are ordered by (squared distance,
// original index), squared distances are computed in float as dx*dx + dy*dy + dz*dz (the same
// expression as splatkit::squared_distance), and ties at the k-th place go to the smaller index.
// So results are identical for any thread count and any max_leaf_size, and equal to brute force.
//
// Indices are uint32_t positions in the span given to the constructor; a cloud may hold at most
// 2^32 - 2 points. Queries are const and may run concurrently from any number of threads. The
// batch functions run in parallel with TBB (they honour tbb::global_control / task_arena limits).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <vector>

#include "splatkit/neighbor_graph.h"
#include "splatkit/vec3.h"

namespace splatkit {

// Error(kBadInput) for a sphere-overlap graph of more than max_entries row entries over
// `spheres` spheres (SpatialIndex::sphere_overlaps, graph/sphere_overlap_graph.h).
[[noreturn]] void throw_too_many_overlaps(std::size_t max_entries, std::size_t spheres,
                                          float largest_radius);

class SpatialIndex {
 public:
  // Marks an unused slot in a k-row when the cloud has fewer than k points (its distance is +inf).
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  static constexpr std::size_t kDefaultLeafSize = 32;

  // Called by for_each_knn_block, concurrently from several threads, each call for a different
  // block of query points. `queries` holds the original indices of the block's points (in tree
  // order, not ascending); `indices` and `sq_dists` hold queries.size() rows of k entries, row r
  // for point queries[r], laid out as in knn_all. The spans are valid only during the call.
  using KnnBlockFn =
      std::function<void(std::span<const uint32_t> queries, std::span<const uint32_t> indices,
                         std::span<const float> sq_dists)>;

  SpatialIndex() = default;  // an empty index: every query returns nothing
  // Copies the points. Throws splatkit::Error (kBadInput) if a coordinate is NaN or infinite and
  // std::invalid_argument if there are more than 2^32 - 2 points or max_leaf_size is 0.
  explicit SpatialIndex(std::span<const Vec3f> points,
                        std::size_t max_leaf_size = kDefaultLeafSize);

  std::size_t size() const { return ids_.size(); }
  // Bytes held by the index (its arrays' capacities), for memory budgets.
  std::size_t memory_bytes() const;

  // The min(k, size()) points nearest to q, ordered by (squared distance, index), written to
  // out_indices[0..) and out_sq_dists[0..) (each must have room for k entries; out_sq_dists may be
  // null). Returns the count written. A point equal to q is included, at distance 0. A q with a
  // NaN or infinite coordinate finds nothing (returns 0).
  std::size_t knn(const Vec3f& q, std::size_t k, uint32_t* out_indices, float* out_sq_dists) const;

  // The neighbourhood of every point, in parallel. Row i (k entries) starts with i itself at
  // distance 0, followed by the k - 1 points nearest to point i other than i, ordered by
  // (squared distance, index) — so columns 1..k-1 are "the k - 1 nearest neighbours" and the whole
  // row is what PCA over "the k nearest points of the cloud" uses. If size() < k, the last
  // k - size() slots of every row hold kNone and +inf.
  // out_indices must hold size() * k entries (row-major, size() by k); out_sq_dists likewise, or
  // be empty to skip the distances. Throws std::invalid_argument on a size mismatch.
  void knn_all(std::size_t k, std::span<uint32_t> out_indices,
               std::span<float> out_sq_dists = {}) const;

  // The same rows as knn_all, streamed: fn receives blocks of at most 1024 points, so the caller
  // never holds all size() * k entries (64 bytes/point at k = 16). fn must be thread-safe; the
  // order of the calls is unspecified, their contents are not.
  void for_each_knn_block(std::size_t k, const KnnBlockFn& fn) const;

  // All points p with squared_distance(p, q) <= r * r (r * r computed in float), ordered by
  // (squared distance, index). out_sq_dists may be null. Throws std::invalid_argument if r is
  // negative or not finite; a non-finite q finds nothing.
  void radius(const Vec3f& q, float r, std::vector<uint32_t>& out_indices,
              std::vector<float>* out_sq_dists = nullptr) const;

  // The sphere-overlap graph of the indexed points as centres C_i with radii[i]: j is a neighbour
  // of i (j != i) iff squared_distance(C_i, C_j) < (radii[i] + radii[j])^2, computed in float —
  // bounding spheres that strictly overlap. Prunes by each node's largest radius, so a few huge
  // radii do not slow down the rest; a leaf's points share one candidate set when it is small.
  // radii must have size() entries, each finite and >= 0, else std::invalid_argument. Runs in
  // parallel; the result does not depend on the thread count. Memory: the result (8 bytes/point + 4
  // bytes per row entry) plus about as much transiently. More than max_entries row entries in all
  // (spheres far larger than the spacing of their centres, which would fill the memory):
  // Error(kBadInput), found after about max_entries plus a row per thread.
  NeighborGraph sphere_overlaps(std::span<const float> radii,
                                std::size_t max_entries = SIZE_MAX) const;

 private:
  struct Box {
    float lo[3];
    float hi[3];
  };
  struct KnnState;
  struct KnnSearch;
  struct LeafBatch;
  struct OverlapBatch;
  struct Builder;

  // Depth-first over the subtree of node `root`, children in order: skips a node when
  // far(node), calls leaf(l) on each leaf l reached; stops and returns false as soon as leaf(l)
  // does (defined in the .cpp, where its only callers are).
  template <class Far, class Leaf>
  bool visit_leaves(uint32_t root, Far&& far, Leaf&& leaf) const;
  void knn_rows(std::size_t begin, std::size_t end, std::size_t k, uint32_t* indices,
                float* sq_dists) const;
  // Stops early (false) once `entries`, the rows' lengths summed across calls, exceeds `max`.
  bool overlap_rows(std::size_t begin, std::size_t end, const float* tree_radii,
                    const float* node_max_radius, std::vector<uint32_t>& neighbors,
                    std::vector<uint32_t>& counts, std::atomic<std::size_t>& entries,
                    std::size_t max) const;

  std::vector<float> xs_, ys_, zs_;   // coordinates in tree order
  std::vector<uint32_t> ids_;         // tree position -> original index
  std::vector<Box> boxes_;            // tight box of every node, heap order (children 2i+1, 2i+2)
  std::vector<uint32_t> leaf_start_;  // first tree position of each leaf, plus size() at the end
  uint32_t first_leaf_ = 0;           // node number of leaf 0 (= number of inner nodes)
};

}  // namespace splatkit
