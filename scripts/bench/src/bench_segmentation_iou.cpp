// bench_segmentation_iou: the per-patch score of scripts/bench/segmentation-quality.sh — reads a
// cloud with the vertex attributes patch_id (the truth, from splat-synth) and surface_id (from
// segment-surfaces' PLY output) and prints, for every true patch, its best-matching surface by
// intersection over union (graph::patch_iou).
//
// usage: bench_segmentation_iou IN [--threshold 0.95]
//
// Prints one line per patch, "patch P splats N surface S overlap K iou X", then
// "segments S", "recovered R of P" (patches with iou >= threshold) and "min_iou X".
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "formats/read_cloud.h"
#include "graph/patch_iou.h"

namespace {

std::vector<uint32_t> labels(const splatkit::SplatCloud& cloud, const std::string& name) {
  const splatkit::ExtraAttribute* a = cloud.find_extra(name);
  if (a == nullptr) throw std::runtime_error("no vertex attribute " + name);
  const std::vector<double> ids = a->values.doubles();
  return std::vector<uint32_t>(ids.begin(), ids.end());
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc != 2 && !(argc == 4 && std::string(argv[2]) == "--threshold"))
      throw std::runtime_error("usage: bench_segmentation_iou IN [--threshold T]");
    const double threshold = argc == 4 ? std::stod(argv[3]) : 0.95;
    const splatkit::LoadedCloud doc = splatkit::read_cloud(argv[1]);
    const std::vector<uint32_t> truth = labels(doc.cloud, "patch_id");
    const std::vector<uint32_t> surfaces = labels(doc.cloud, "surface_id");
    const auto matches = splatkit::graph::patch_iou(truth, surfaces);
    double min_iou = 1;
    std::size_t ok = 0;
    for (const auto& m : matches) {
      std::printf("patch %u splats %llu surface %d overlap %llu iou %.4f\n", m.patch,
                  (unsigned long long)m.size, m.surface == 0xFFFFFFFFu ? -1 : int(m.surface),
                  (unsigned long long)m.overlap, m.iou);
      min_iou = std::min(min_iou, m.iou);
      ok += m.iou >= threshold;
    }
    std::set<uint32_t> distinct(surfaces.begin(), surfaces.end());
    distinct.erase(0xFFFFFFFFu);
    std::printf("segments %zu\nrecovered %zu of %zu\nmin_iou %.4f\n", distinct.size(), ok,
                matches.size(), min_iou);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_segmentation_iou: %s: %s\n", argc > 1 ? argv[1] : "", e.what());
    return 1;
  }
}
