// CGAL's documented normal pipeline, the peer of estimate-normals' orientation (orientation.sh):
// CGAL::pca_estimate_normals over the K nearest neighbours, then CGAL::mst_orient_normals over
// the K nearest (Hoppe et al.'s Riemannian graph, seeded at the top-most point, facing +z).
//
// usage: bench_orient_cgal SCENE.ply OUT.ply [K] [THREADS]
//   SCENE.ply: PLY (binary little endian or ascii) whose vertex element has x, y, z (float or
//   double); every other property is skipped, so reference normals are never read.
//   OUT.ply: binary little-endian PLY with float nx, ny, nz only, in the input's order.
//   mst_orient_normals moves the points it cannot orient (those outside the top-most point's
//   connected component) to the end of the range; each point carries its input index, so they are
//   written back in place, as (0, 0, 0): the scorer counts them as wrong. Prints one JSON line:
//   points, unoriented, pca_s, mst_s (the calls alone, without I/O).
#include <tbb/global_control.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using PointNormalIndex = std::tuple<Point, Vector, std::size_t>;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::size_t type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32")
    return 4;
  if (t == "double" || t == "float64") return 8;
  throw std::runtime_error("unknown PLY type " + t);
}

// The vertex positions of a PLY file (the vertex element must be the first element).
std::vector<Point> read_positions(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::string line, format;
  std::size_t count = 0, stride = 0;
  bool in_vertex = false, seen_element = false;
  struct Prop {
    std::string name, type;
    std::size_t offset;
  };
  std::vector<Prop> props;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "format") {
      ls >> format;
    } else if (word == "element") {
      std::string name;
      ls >> name;
      if (!seen_element && name != "vertex")
        throw std::runtime_error("the vertex element must come first in " + path);
      in_vertex = name == "vertex";
      if (in_vertex) ls >> count;
      seen_element = true;
    } else if (word == "property" && in_vertex) {
      std::string type, name;
      ls >> type;
      if (type == "list") throw std::runtime_error("list property in the vertex element");
      ls >> name;
      props.push_back({name, type, stride});
      stride += type_size(type);
    } else if (word == "end_header") {
      break;
    }
  }
  const auto find = [&](const char* name) {
    for (std::size_t i = 0; i < props.size(); ++i)
      if (props[i].name == name) return i;
    throw std::runtime_error(std::string("no vertex property ") + name + " in " + path);
  };
  const std::size_t ix = find("x"), iy = find("y"), iz = find("z");
  std::vector<Point> points;
  points.reserve(count);
  if (format == "ascii") {
    std::vector<double> v(props.size());
    for (std::size_t i = 0; i < count; ++i) {
      for (double& x : v)
        if (!(in >> x)) throw std::runtime_error("short ascii PLY " + path);
      points.emplace_back(v[ix], v[iy], v[iz]);
    }
    return points;
  }
  if (format != "binary_little_endian")
    throw std::runtime_error("unsupported PLY format " + format + " in " + path);
  std::vector<char> row(stride);
  const auto get = [&](const Prop& p) {
    if (p.type == "double" || p.type == "float64") {
      double d;
      std::memcpy(&d, row.data() + p.offset, 8);
      return d;
    }
    if (p.type != "float" && p.type != "float32")
      throw std::runtime_error("x, y, z must be float or double");
    float f;
    std::memcpy(&f, row.data() + p.offset, 4);
    return double{f};
  };
  for (std::size_t i = 0; i < count; ++i) {
    if (!in.read(row.data(), static_cast<std::streamsize>(stride)))
      throw std::runtime_error("short binary PLY " + path);
    points.emplace_back(get(props[ix]), get(props[iy]), get(props[iz]));
  }
  return points;
}

void write_normals(const std::string& path, const std::vector<float>& normals) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error("cannot write " + path);
  std::fprintf(f,
               "ply\nformat binary_little_endian 1.0\ncomment bench_orient_cgal\n"
               "element vertex %zu\nproperty float nx\nproperty float ny\nproperty float nz\n"
               "end_header\n",
               normals.size() / 3);
  const bool ok = std::fwrite(normals.data(), sizeof(float), normals.size(), f) == normals.size();
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error("cannot write " + path);
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_orient_cgal SCENE.ply OUT.ply [K] [THREADS]\n");
    return 2;
  }
  const unsigned k = argc > 3 ? static_cast<unsigned>(std::atoi(argv[3])) : 16;
  const int threads = argc > 4 ? std::atoi(argv[4]) : 2;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<std::size_t>(std::max(threads, 1)));

  const std::vector<Point> positions = read_positions(argv[1]);
  std::vector<PointNormalIndex> points;
  points.reserve(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i)
    points.emplace_back(positions[i], Vector(0, 0, 0), i);

  const auto params =
      CGAL::parameters::point_map(CGAL::Nth_of_tuple_property_map<0, PointNormalIndex>())
          .normal_map(CGAL::Nth_of_tuple_property_map<1, PointNormalIndex>());
  auto t0 = Clock::now();
  CGAL::pca_estimate_normals<CGAL::Parallel_if_available_tag>(points, k, params);
  const double pca_s = seconds_since(t0);
  t0 = Clock::now();
  const auto unoriented = CGAL::mst_orient_normals(points, k, params);
  const double mst_s = seconds_since(t0);

  std::vector<float> normals(3 * points.size(), 0.0f);
  for (auto it = points.begin(); it != unoriented; ++it) {
    const Vector& n = std::get<1>(*it);
    float* out = &normals[3 * std::get<2>(*it)];
    out[0] = static_cast<float>(n.x());
    out[1] = static_cast<float>(n.y());
    out[2] = static_cast<float>(n.z());
  }
  write_normals(argv[2], normals);
  std::printf("{\"points\": %zu, \"unoriented\": %zu, \"pca_s\": %.4f, \"mst_s\": %.4f}\n",
              points.size(), static_cast<std::size_t>(std::distance(unoriented, points.end())),
              pca_s, mst_s);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_orient_cgal: %s\n", e.what());
  return 1;
}
