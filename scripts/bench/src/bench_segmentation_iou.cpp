// bench_segmentation_iou: the per-patch score of scripts/bench/segmentation-quality.sh and
// segmentation-real.sh — reads a cloud with a truth attribute (patch_id from splat-synth by
// default) and surface_id (from segment-surfaces' PLY output) and prints, for every true patch,
// its best-matching surface by intersection over union (graph::patch_iou).
//
// usage: bench_segmentation_iou IN [--threshold 0.95] [--truth NAME] [--unlabelled V]
//   --truth NAME    the truth attribute (default patch_id; segment_index for CGAL's scans)
//   --unlabelled V  splats whose truth is V (e.g. -1) carry no label: they are left out of every
//                   count, so a surface is scored only on its labelled splats
//
// Prints one line per patch, "patch P splats N surface S overlap K iou X", then
// "segments S" (distinct surfaces over all splats), "recovered R of P" (patches with
// iou >= threshold), "min_iou X" and "mean_iou X".
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "formats/read_cloud.h"
#include "graph/patch_iou.h"

namespace {

std::vector<double> values(const splatkit::SplatCloud& cloud, const std::string& name) {
  const splatkit::ExtraAttribute* a = cloud.find_extra(name);
  if (a == nullptr) throw std::runtime_error("no vertex attribute " + name);
  return a->values.doubles();
}

uint32_t to_label(double v, const std::string& name) {
  if (!(v >= 0 && v <= 4294967295.0) || v != std::floor(v))
    throw std::runtime_error(name + " holds " + std::to_string(v) +
                             ", not a label (use --unlabelled for the value of unlabelled splats)");
  return uint32_t(v);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) throw std::runtime_error("usage: bench_segmentation_iou IN [options]");
    double threshold = 0.95;
    std::string truth_name = "patch_id";
    std::optional<double> unlabelled;
    for (int a = 2; a < argc; a += 2) {
      const std::string opt = argv[a];
      if (a + 1 >= argc) throw std::runtime_error(opt + " needs a value");
      if (opt == "--threshold") {
        threshold = std::stod(argv[a + 1]);
      } else if (opt == "--truth") {
        truth_name = argv[a + 1];
      } else if (opt == "--unlabelled") {
        unlabelled = std::stod(argv[a + 1]);
      } else {
        throw std::runtime_error("unknown option " + opt);
      }
    }
    const splatkit::LoadedCloud doc = splatkit::read_cloud(argv[1]);
    const std::vector<double> truth_values = values(doc.cloud, truth_name);
    const std::vector<double> surface_values = values(doc.cloud, "surface_id");
    std::vector<uint32_t> truth, surfaces;
    std::set<uint32_t> distinct;
    for (std::size_t i = 0; i < truth_values.size(); ++i) {
      const uint32_t s = to_label(surface_values[i], "surface_id");
      distinct.insert(s);
      if (unlabelled && truth_values[i] == *unlabelled) continue;
      truth.push_back(to_label(truth_values[i], truth_name));
      surfaces.push_back(s);
    }
    const auto matches = splatkit::graph::patch_iou(truth, surfaces);
    double min_iou = 1, sum = 0;
    std::size_t ok = 0;
    for (const auto& m : matches) {
      std::printf("patch %u splats %llu surface %d overlap %llu iou %.4f\n", m.patch,
                  (unsigned long long)m.size, m.surface == 0xFFFFFFFFu ? -1 : int(m.surface),
                  (unsigned long long)m.overlap, m.iou);
      min_iou = std::min(min_iou, m.iou);
      sum += m.iou;
      ok += m.iou >= threshold;
    }
    distinct.erase(0xFFFFFFFFu);
    std::printf("segments %zu\nrecovered %zu of %zu\nmin_iou %.4f\nmean_iou %.4f\n",
                distinct.size(), ok, matches.size(), min_iou,
                matches.empty() ? 1.0 : sum / double(matches.size()));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_segmentation_iou: %s: %s\n", argc > 1 ? argv[1] : "", e.what());
    return 1;
  }
}
