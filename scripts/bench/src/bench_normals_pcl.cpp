// bench_normals_pcl: the PCL peer of scripts/bench/normals.sh — pcl::NormalEstimationOMP (k nearest
// points, kd-tree build included) on a cloud file, timed inside the program after the file was
// read, and the agreement of estimate-normals' output with PCL's normals.
//
// usage: bench_normals_pcl IN [-k 16] [--threads 2] [--compare OURS.ply] [--max-deg 0.5]
//
// Prints one JSON object on stdout: {"points", "k", "threads", "read_s", "pcl_s" (kd-tree build +
// normals), "pcl_nan" (points PCL gave no normal), and with --compare: "agree_fraction" (points
// whose normals agree within max-deg, up to sign), "max_deg", "p999_deg"}. OURS must hold the
// same points in the same order (estimate-normals keeps the order; the input must have no
// duplicates). Exit 1 when OURS does not match IN.
#include <pcl/features/normal_3d_omp.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "formats/read_cloud.h"
#include "splatkit/error.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct Args {
  std::string input, compare;
  int k = 16, threads = 2;
  double max_deg = 0.5;
};

Args parse_args(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    std::string s = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error("missing value after " + s);
      return argv[++i];
    };
    if (s == "-k")
      a.k = std::stoi(next());
    else if (s == "--threads")
      a.threads = std::stoi(next());
    else if (s == "--compare")
      a.compare = next();
    else if (s == "--max-deg")
      a.max_deg = std::stod(next());
    else if (a.input.empty())
      a.input = s;
    else
      throw std::runtime_error("unexpected argument " + s);
  }
  if (a.input.empty())
    throw std::runtime_error(
        "usage: bench_normals_pcl IN [-k K] [--threads N] [--compare OURS.ply] [--max-deg D]");
  return a;
}

// Angles (degrees, up to sign) between PCL's normals and ours; NaN normals count as 180°.
std::vector<double> angles(const pcl::PointCloud<pcl::Normal>& pcl_normals,
                           const splatkit::SplatCloud& ours) {
  std::vector<double> deg(ours.size());
  for (std::size_t i = 0; i < ours.size(); ++i) {
    const pcl::Normal& p = pcl_normals[i];
    const splatkit::Vec3f& o = ours.normals[i];
    double d =
        std::fabs(double(p.normal_x) * o.x + double(p.normal_y) * o.y + double(p.normal_z) * o.z);
    deg[i] = std::isfinite(d) ? std::acos(std::min(d, 1.0)) * 180.0 / M_PI : 180.0;
  }
  return deg;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Args args = parse_args(argc, argv);
    Clock::time_point t0 = Clock::now();
    splatkit::LoadedCloud doc = splatkit::read_cloud(args.input);
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    cloud->resize(doc.cloud.size());
    for (std::size_t i = 0; i < doc.cloud.size(); ++i) {
      const splatkit::Vec3f& p = doc.cloud.positions[i];
      (*cloud)[i] = pcl::PointXYZ(p.x, p.y, p.z);
    }
    const double read_s = seconds_since(t0);

    pcl::PointCloud<pcl::Normal> normals;
    t0 = Clock::now();
    pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> estimator(args.threads);
    estimator.setInputCloud(cloud);
    estimator.setSearchMethod(std::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
    estimator.setKSearch(args.k);
    estimator.compute(normals);  // builds the kd-tree (initCompute) and estimates
    const double pcl_s = seconds_since(t0);

    std::size_t nan = 0;
    for (const pcl::Normal& n : normals)
      if (!std::isfinite(n.normal_x)) ++nan;
    nlohmann::json out = {{"points", cloud->size()}, {"k", args.k},    {"threads", args.threads},
                          {"read_s", read_s},        {"pcl_s", pcl_s}, {"pcl_nan", nan}};
    if (!args.compare.empty()) {
      splatkit::LoadedCloud ours = splatkit::read_cloud(args.compare);
      if (ours.cloud.size() != doc.cloud.size() || ours.cloud.positions != doc.cloud.positions ||
          !ours.cloud.has_normals()) {
        std::fprintf(stderr, "bench_normals_pcl: %s does not hold IN's points with normals\n",
                     args.compare.c_str());
        return 1;
      }
      std::vector<double> deg = angles(normals, ours.cloud);
      const std::size_t agree = static_cast<std::size_t>(
          std::count_if(deg.begin(), deg.end(), [&](double d) { return d <= args.max_deg; }));
      std::sort(deg.begin(), deg.end());
      out["agree_fraction"] = deg.empty() ? 1.0 : double(agree) / double(deg.size());
      out["max_deg"] = deg.empty() ? 0.0 : deg.back();
      out["p999_deg"] = deg.empty() ? 0.0 : deg[std::min(deg.size() - 1, deg.size() * 999 / 1000)];
      out["tolerance_deg"] = args.max_deg;
    }
    std::printf("%s\n", out.dump().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_normals_pcl: %s\n", e.what());
    return 1;
  }
}
