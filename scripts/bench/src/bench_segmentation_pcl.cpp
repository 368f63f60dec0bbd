// bench_segmentation_pcl: the peer of segment-surfaces in scripts/bench/segmentation-real.sh —
// pcl::RegionGrowing with its defaults (smoothness 30°, curvature 0.05, 30 neighbours, min
// cluster size 1, residual test off) on normals and curvature from pcl::NormalEstimation over the
// same 30 nearest neighbours, as PCL's region growing tutorial sets it up. Reads any cloud
// splatkit reads (its own normals are not used) and writes it with a surface_id attribute (PCL's
// cluster, 0xFFFFFFFF for points in no cluster) for bench_segmentation_iou.
//
// usage: bench_segmentation_pcl IN OUT.ply
#include <pcl/features/normal_3d.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <vector>

#include "formats/read_cloud.h"
#include "formats/write_cloud.h"

int main(int argc, char** argv) {
  try {
    if (argc != 3) throw std::runtime_error("usage: bench_segmentation_pcl IN OUT.ply");
    splatkit::LoadedCloud doc = splatkit::read_cloud(argv[1]);
    const std::size_t n = doc.cloud.size();
    pcl::PointCloud<pcl::PointXYZ>::Ptr points(new pcl::PointCloud<pcl::PointXYZ>);
    points->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const splatkit::Vec3f& p = doc.cloud.positions[i];
      (*points)[i] = pcl::PointXYZ(p.x, p.y, p.z);
    }
    const auto t0 = std::chrono::steady_clock::now();
    pcl::search::Search<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
    pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
    ne.setSearchMethod(tree);
    ne.setInputCloud(points);
    ne.setKSearch(30);
    ne.compute(*normals);
    pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> rg;
    rg.setSearchMethod(tree);
    rg.setInputCloud(points);
    rg.setInputNormals(normals);
    std::vector<pcl::PointIndices> clusters;
    rg.extract(clusters);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<double> id(n, double(0xFFFFFFFFu));
    for (std::size_t c = 0; c < clusters.size(); ++c)
      for (int i : clusters[c].indices) id[std::size_t(i)] = double(c);
    doc.cloud.set_extra(splatkit::ExtraAttribute("surface_id", splatkit::ScalarType::kUInt32, id));
    splatkit::write_cloud(doc, argv[2]);
    std::fprintf(stderr, "pcl RegionGrowing: %zu clusters in %.3f s\n", clusters.size(), seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_segmentation_pcl: %s\n", e.what());
    return 1;
  }
}
