// Accuracy of estimate-normals' pca and robust methods on the CAD-like synthetic part (exact
// normals, creases of 60°, 90° and 120°), per distance band from the nearest crease, and the cost
// of MST orientation on a torus (normals-accuracy.sh).
//
// usage: bench_normals_accuracy cad POINTS NOISE [K] [THREADS]
//          prints a JSON object: per method {band: {count, rms_deg, within5, within10}}, seconds
//          per method (estimate_normals with --orient none, the whole call) and robust / pca.
//        bench_normals_accuracy orient POINTS [THREADS]
//          PCA normals of a torus with random signs, then orient_normals_mst: seconds and the
//          fraction pointing outward.
// Bands use s = the mean distance from a point to its nearest neighbour. Angles are up to sign.
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "normals/estimate_normals.h"
#include "normals/orient_normals_mst.h"
#include "splatkit/deterministic_rng.h"
#include "splatkit/spatial_index.h"
#include "splatkit/synthetic_shapes.h"

using namespace splatkit;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// CPU seconds of the whole process (all threads): on a machine shared with other jobs, wall time
// says more about the load than about the code.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double mean_spacing(const SpatialIndex& index) {
  const std::size_t n = index.size();
  std::vector<uint32_t> ids(n * 2);
  std::vector<float> d2(n * 2);
  index.knn_all(2, ids, d2);
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += std::sqrt(double{d2[2 * i + 1]});
  return sum / static_cast<double>(n);
}

struct Band {
  const char* name;
  double lo, hi;  // in units of s
  std::size_t count = 0, within5 = 0, within10 = 0;
  double sum_sq = 0;
};

nlohmann::json accuracy(const SplatCloud& truth, const std::vector<Vec3f>& normals,
                        const std::vector<float>& crease_s) {
  std::vector<Band> bands = {{"<1s", 0, 1},  {"1-2s", 1, 2},       {"<2s", 0, 2},
                             {"2-4s", 2, 4}, {">4s", 4, INFINITY}, {"all", 0, INFINITY}};
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double c = std::min(1.0, std::fabs(double{dot(normals[i], truth.normals[i])}));
    const double deg = std::acos(c) * 180.0 / std::numbers::pi;
    for (Band& b : bands) {
      if (!(crease_s[i] >= b.lo && crease_s[i] < b.hi)) continue;
      ++b.count;
      b.sum_sq += deg * deg;
      b.within5 += deg <= 5;
      b.within10 += deg <= 10;
    }
  }
  nlohmann::json out = nlohmann::json::object();
  for (const Band& b : bands) {
    const double n = static_cast<double>(std::max<std::size_t>(b.count, 1));
    out[b.name] = {{"count", b.count},
                   {"rms_deg", std::sqrt(b.sum_sq / n)},
                   {"within5", static_cast<double>(b.within5) / n},
                   {"within10", static_cast<double>(b.within10) / n}};
  }
  return out;
}

int run_cad(std::size_t points, double noise, std::size_t k) {
  ShapeOptions shape;
  shape.kind = ShapeKind::kCadPart;
  shape.points = points;
  shape.noise = noise;
  const SplatCloud truth = make_shape(shape);
  const SpatialIndex index(truth.positions);
  const double s = mean_spacing(index);
  std::vector<float> crease_s(truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    crease_s[i] =
        static_cast<float>(distance_to_crease(ShapeKind::kCadPart, truth.positions[i]) / s);

  nlohmann::json out = {{"points", truth.size()}, {"noise", noise}, {"k", k}, {"spacing", s}};
  double seconds[2] = {0, 0}, cpu[2] = {0, 0};
  for (NormalMethod method : {NormalMethod::kPca, NormalMethod::kRobust}) {
    SplatCloud cloud = truth;
    NormalOptions options;
    options.k = k;
    options.method = method;
    options.orient = NormalOrientation::kNone;
    const Clock::time_point t0 = Clock::now();
    const double c0 = cpu_seconds();
    const nlohmann::json report = estimate_normals(cloud, options).to_json();
    const double t = seconds_since(t0);
    const double c = cpu_seconds() - c0;
    seconds[method == NormalMethod::kRobust] = t;
    cpu[method == NormalMethod::kRobust] = c;
    if (cloud.size() != truth.size()) {
      std::fprintf(stderr, "estimate_normals changed the point count\n");
      return 1;
    }
    out[method_name(method)] = {{"seconds", t},
                                {"cpu_seconds", c},
                                {"report", report},
                                {"bands", accuracy(truth, cloud.normals, crease_s)}};
  }
  // Orientation of the same normals: estimate_normals with --orient mst, counted on the points
  // whose unoriented normal is within 60° of the truth (others have no meaningful side).
  for (NormalMethod method : {NormalMethod::kPca, NormalMethod::kRobust}) {
    SplatCloud cloud = truth;
    NormalOptions options;
    options.k = k;
    options.method = method;
    const NormalReport report = estimate_normals(cloud, options);
    std::size_t inward = 0, meaningless = 0;
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const float d = dot(cloud.normals[i], truth.normals[i]);
      if (std::fabs(d) < 0.5f)
        ++meaningless;
      else
        inward += d < 0;
    }
    out[method_name(method)]["mst"] = {{"inward", inward},
                                       {"off_by_more_than_60deg", meaningless},
                                       {"orient_s", report.timings.value("orient", 0.0)}};
  }
  out["robust_over_pca"] = seconds[1] / seconds[0];
  out["robust_over_pca_cpu"] = cpu[1] / cpu[0];
  std::printf("%s\n", out.dump(1).c_str());
  return 0;
}

int run_orient(std::size_t points) {
  ShapeOptions shape;
  shape.kind = ShapeKind::kTorus;
  shape.points = points;
  SplatCloud cloud = make_shape(shape);
  const std::vector<Vec3f> truth = cloud.normals;
  NormalOptions options;
  options.orient = NormalOrientation::kNone;
  estimate_normals(cloud, options);
  DeterministicRng rng(7);
  for (Vec3f& n : cloud.normals)
    if (rng.next() & 1) n = -n;
  const Clock::time_point t0 = Clock::now();
  const SpatialIndex index(cloud.positions);
  const double t_index = seconds_since(t0);
  const Clock::time_point t1 = Clock::now();
  const double c1 = cpu_seconds();
  const OrientStats stats = orient_normals_mst(index, cloud.positions, cloud.normals);
  const double t_orient = seconds_since(t1);
  const double c_orient = cpu_seconds() - c1;
  std::size_t outward = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) outward += dot(cloud.normals[i], truth[i]) > 0;
  const double n = static_cast<double>(cloud.size());
  const nlohmann::json out = {{"points", cloud.size()},
                              {"index_s", t_index},
                              {"orient_s", t_orient},
                              {"orient_s_per_million", t_orient * 1e6 / n},
                              {"orient_cpu_s_per_million", c_orient * 1e6 / n},
                              {"components", stats.components},
                              {"outward", static_cast<double>(outward) / n}};
  std::printf("%s\n", out.dump(1).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s cad POINTS NOISE [K] [THREADS] | %s orient POINTS [THREADS]\n",
                 argv[0], argv[0]);
    return 2;
  }
  const std::string mode = argv[1];
  const auto points = static_cast<std::size_t>(std::atoll(argv[2]));
  const int thread_arg = mode == "cad" ? 5 : 3;
  const int threads = argc > thread_arg ? std::atoi(argv[thread_arg]) : 2;
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                            static_cast<std::size_t>(std::max(threads, 1)));
  if (mode == "cad") {
    const double noise = std::atof(argv[3]);
    const std::size_t k = argc > 4 ? static_cast<std::size_t>(std::atoll(argv[4])) : 16;
    return run_cad(points, noise, k);
  }
  if (mode == "orient") return run_orient(points);
  std::fprintf(stderr, "unknown mode %s\n", mode.c_str());
  return 2;
}
