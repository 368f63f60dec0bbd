// bench_graph_pcl: the PCL peer of scripts/bench/graph.sh — the sphere-overlap graph
// E = {(i, j) : |C_i - C_j| < r_i + r_j} built with pcl::KdTreeFLANN:
// kd-tree build, then for every splat radiusSearch(C_i, r_i + r_max) and keep the candidates with
// |C_i - C_j|² < (r_i + r_j)², in parallel (TBB, --threads), into the same compressed rows as
// splatkit::SpatialIndex::sphere_overlaps (ascending neighbours, no self). Timed inside the
// program after the file was read: tree build + queries + rows. In the same process, first,
// splatkit::graph::sphere_overlap_graph builds the same graph (build-splat-graph's first phase
// without the sharp edges), timed the same way, and the two graphs are compared.
//
// usage: bench_graph_pcl IN [--threads 2] [--compare OURS.splk]
//
// IN: splats with radii, any format. Prints one JSON object on stdout: {"splats", "threads",
// "edges" (undirected), "read_s", "ours_s", "pcl_s", "build_tree_s", "query_s", "same_as_ours"},
// and with --compare
// (build-splat-graph's output for the same IN) "same_graph": true when every row of its GRPH chunk
// equals PCL's here, edge for edge. Exit 1 when a graph differs or OURS does not hold IN's splats.
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "formats/read_cloud.h"
#include "graph_io/graph_chunks.h"
#include "graph/sphere_overlap_graph.h"
#include "splatkit/seconds_since.h"
#include "splatkit/spatial_index.h"

namespace {

using splatkit::Clock;
using splatkit::seconds_since;

struct Args {
  std::string input, compare;
  int threads = 2;
};

Args parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    std::string s = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error("missing value after " + s);
      return argv[++i];
    };
    if (s == "--threads")
      a.threads = std::stoi(next());
    else if (s == "--compare")
      a.compare = next();
    else if (a.input.empty())
      a.input = s;
    else
      throw std::runtime_error("unexpected argument " + s);
  }
  if (a.input.empty())
    throw std::runtime_error("usage: bench_graph_pcl IN [--threads N] [--compare OURS.splk]");
  return a;
}

// Splats per task and per output block, as in sphere_overlaps.
constexpr std::size_t kBlock = 4096;

struct Block {
  std::vector<uint32_t> counts, neighbors;
};

// One block of rows: radius search with the largest possible partner radius, then the exact test
// in float, written the way splatkit::squared_distance and sphere_overlaps write it.
void query_block(const pcl::KdTreeFLANN<pcl::PointXYZ>& tree,
                 const pcl::PointCloud<pcl::PointXYZ>& cloud, const std::vector<float>& radii,
                 float r_max, std::size_t begin, std::size_t end, Block& out) {
  std::vector<int> found;
  std::vector<float> sq;
  std::vector<uint32_t> row;
  for (std::size_t i = begin; i < end; ++i) {
    const pcl::PointXYZ& c = cloud[i];
    // A hair more than r_i + r_max, so FLANN's own rounding cannot drop a true neighbour.
    tree.radiusSearch(c, double(radii[i] + r_max) * (1 + 1e-6), found, sq);
    row.clear();
    for (int j : found) {
      if (std::size_t(j) == i) continue;
      const pcl::PointXYZ& d = cloud[j];
      const float dx = c.x - d.x, dy = c.y - d.y, dz = c.z - d.z;
      const float r = radii[i] + radii[j];
      if (dx * dx + dy * dy + dz * dz < r * r) row.push_back(uint32_t(j));
    }
    std::sort(row.begin(), row.end());
    out.counts.push_back(uint32_t(row.size()));
    out.neighbors.insert(out.neighbors.end(), row.begin(), row.end());
  }
}

splatkit::NeighborGraph pcl_sphere_overlaps(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                                            const std::vector<float>& radii, double& tree_s) {
  Clock::time_point t0 = Clock::now();
  pcl::KdTreeFLANN<pcl::PointXYZ> tree(/*sorted=*/false);  // unsorted: PCL's faster mode
  tree.setInputCloud(cloud);
  tree_s = seconds_since(t0);
  const float r_max = radii.empty() ? 0.0f : *std::max_element(radii.begin(), radii.end());
  const std::size_t n = radii.size();
  std::vector<Block> blocks((n + kBlock - 1) / kBlock);
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t b) {
    query_block(tree, *cloud, radii, r_max, b * kBlock, std::min(n, (b + 1) * kBlock), blocks[b]);
  });
  splatkit::NeighborGraph g;
  g.offsets.assign(1, 0);
  g.offsets.reserve(n + 1);
  for (const Block& b : blocks)
    for (uint32_t c : b.counts) g.offsets.push_back(g.offsets.back() + c);
  g.neighbors.resize(g.offsets.back());
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t b) {
    std::copy(blocks[b].neighbors.begin(), blocks[b].neighbors.end(),
              g.neighbors.begin() + std::ptrdiff_t(g.offsets[b * kBlock]));
  });
  return g;
}

// True when OURS (build-splat-graph's .splk) holds IN's splats and a GRPH chunk with these rows.
bool same_graph(const std::string& path, const splatkit::LoadedCloud& in,
                const splatkit::NeighborGraph& g) {
  const splatkit::LoadedCloud ours = splatkit::read_cloud(path);
  if (ours.cloud.positions != in.cloud.positions) {
    std::fprintf(stderr, "bench_graph_pcl: %s does not hold IN's splats\n", path.c_str());
    return false;
  }
  const splatkit::RawChunk* chunk =
      splatkit::graph::find_chunk(ours, splatkit::graph::kGraphChunkType);
  if (chunk == nullptr) {
    std::fprintf(stderr, "bench_graph_pcl: %s has no GRPH chunk\n", path.c_str());
    return false;
  }
  const splatkit::graph::DecodedGraph d =
      splatkit::graph::decode_graph_chunk(*chunk, ours.cloud.size(), path);
  if (d.graph.offsets == g.offsets && d.graph.neighbors == g.neighbors) return true;
  for (std::size_t i = 0; i < g.num_points(); ++i) {
    const auto a = d.graph.row(i), b = g.row(i);
    if (!std::equal(a.begin(), a.end(), b.begin(), b.end())) {
      std::fprintf(stderr, "bench_graph_pcl: splat %zu: %zu neighbours in %s, %zu here\n", i,
                   a.size(), path.c_str(), b.size());
      break;
    }
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse_args(argc, argv);
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                std::size_t(std::max(1, args.threads)));
    Clock::time_point t0 = Clock::now();
    const splatkit::LoadedCloud doc = splatkit::read_cloud(args.input);
    if (!doc.cloud.has_radii()) throw std::runtime_error(args.input + ": the splats have no radii");
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    cloud->resize(doc.cloud.size());
    for (std::size_t i = 0; i < doc.cloud.size(); ++i) {
      const splatkit::Vec3f& p = doc.cloud.positions[i];
      (*cloud)[i] = pcl::PointXYZ(p.x, p.y, p.z);
    }
    const double read_s = seconds_since(t0);

    // The TBB workers start before either is timed.
    tbb::parallel_for(0, args.threads * 4, [](int) {});
    t0 = Clock::now();
    const splatkit::NeighborGraph ours =
        splatkit::graph::sphere_overlap_graph(doc.cloud.positions, doc.cloud.radii);
    const double ours_s = seconds_since(t0);

    t0 = Clock::now();
    double tree_s = 0;
    const splatkit::NeighborGraph g = pcl_sphere_overlaps(cloud, doc.cloud.radii, tree_s);
    const double pcl_s = seconds_since(t0);
    bool ok = ours.offsets == g.offsets && ours.neighbors == g.neighbors;

    nlohmann::json out = {{"splats", doc.cloud.size()},
                          {"threads", args.threads},
                          {"edges", g.neighbors.size() / 2},
                          {"read_s", read_s},
                          {"ours_s", ours_s},
                          {"pcl_s", pcl_s},
                          {"build_tree_s", tree_s},
                          {"query_s", pcl_s - tree_s},
                          {"same_as_ours", ok}};
    if (!args.compare.empty()) {
      const bool same = same_graph(args.compare, doc, g);
      out["same_graph"] = same;
      ok = ok && same;
    }
    std::printf("%s\n", out.dump().c_str());
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_graph_pcl: %s\n", e.what());
    return 1;
  }
}
