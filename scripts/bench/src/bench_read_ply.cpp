// bench_read_ply: times reading a PLY file with splatkit's read_ply, or with PCL as the peer.
//
//   bench_read_ply FILE          read with splatkit::read_ply
//   bench_read_ply --pcl FILE    read with pcl::PLYReader into pcl::PointCloud<pcl::PointNormal>
//   bench_read_ply --make N FILE write N points (x y z nx ny nz radius red green blue, binary
//                                little-endian) with splatkit::write_ply, seeded and deterministic
// Prints one line: reader, points, file MB, wall seconds, MB/s, CPU seconds (user + system) and
// MB per CPU second (steadier than wall time on a loaded machine), peak RSS (MiB). Run each reader
// in its own process so that peak RSS belongs to that reader alone.
#include <pcl/PCLPointCloud2.h>
#include <pcl/conversions.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "formats/ply.h"
#include "splatkit/error.h"

namespace {

double peak_rss_mib() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

double cpu_seconds() {
  struct rusage ru {};
  getrusage(RUSAGE_SELF, &ru);
  auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + t.tv_usec * 1e-6; };
  return s(ru.ru_utime) + s(ru.ru_stime);
}

// Wall and CPU time since construction.
struct Timer {
  std::chrono::steady_clock::time_point wall0 = std::chrono::steady_clock::now();
  double cpu0 = cpu_seconds();
  double wall() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  }
  double cpu() const { return cpu_seconds() - cpu0; }
};

double file_mb(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return 0;
  return static_cast<double>(st.st_size) / 1e6;
}

void report(const char* reader, std::size_t points, const std::string& path, const Timer& t) {
  const double mb = file_mb(path), wall = t.wall(), cpu = t.cpu();
  std::printf(
      "%-9s points=%zu size_mb=%.1f seconds=%.3f mb_per_s=%.0f cpu_seconds=%.3f "
      "mb_per_cpu_s=%.0f peak_rss_mib=%.0f\n",
      reader, points, mb, wall, mb / wall, cpu, mb / cpu, peak_rss_mib());
}

int read_ours(const std::string& path) {
  const Timer t;
  splatkit::InputStream in(path);
  splatkit::LoadedCloud doc = splatkit::read_ply(in);
  report("splatkit", doc.cloud.size(), path, t);
  return 0;
}

// PCL keeps PLY property names as field names; nx/ny/nz and radius are renamed to PointNormal's
// normal_x/normal_y/normal_z and curvature so that the conversion fills them (the peer decodes
// as much of the file as splatkit does, except colours, which PointNormal has no field for).
int read_pcl(const std::string& path) {
  const Timer t;
  pcl::PCLPointCloud2 blob;
  pcl::PLYReader reader;
  if (reader.read(path, blob) < 0) {
    std::fprintf(stderr, "bench_read_ply: PCL could not read %s\n", path.c_str());
    return 1;
  }
  for (pcl::PCLPointField& f : blob.fields) {
    if (f.name == "nx")
      f.name = "normal_x";
    else if (f.name == "ny")
      f.name = "normal_y";
    else if (f.name == "nz")
      f.name = "normal_z";
    else if (f.name == "radius")
      f.name = "curvature";
  }
  pcl::PointCloud<pcl::PointNormal> cloud;
  pcl::fromPCLPointCloud2(blob, cloud);
  report("pcl", cloud.size(), path, t);
  return 0;
}

int make(std::size_t n, const std::string& path) {
  splatkit::SplatCloud c;
  c.positions.resize(n);
  c.normals.resize(n);
  c.radii.resize(n);
  c.colors.resize(n);
  uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&] {  // xorshift64*: fixed seed, same file every time
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    return static_cast<double>((state * 0x2545F4914F6CDD1Dull) >> 11) * 0x1p-53;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const double phi = next() * 2 * M_PI, z = next() * 2 - 1, r = std::sqrt(1 - z * z);
    const splatkit::Vec3f nrm{static_cast<float>(r * std::cos(phi)),
                              static_cast<float>(r * std::sin(phi)), static_cast<float>(z)};
    c.normals[i] = nrm;
    c.positions[i] = nrm * 50.0f + splatkit::Vec3f{100, 100, 100};
    c.radii[i] = static_cast<float>(0.01 + 0.04 * next());
    c.colors[i] = {static_cast<uint16_t>(i % 256), static_cast<uint16_t>((i / 256) % 256), 128};
  }
  splatkit::OutputFile out(path);
  splatkit::write_ply(c, out);
  out.commit();
  std::printf("wrote %zu points to %s (%.1f MB)\n", n, path.c_str(), file_mb(path));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc == 2) return read_ours(argv[1]);
    if (argc == 3 && std::strcmp(argv[1], "--pcl") == 0) return read_pcl(argv[2]);
    if (argc == 4 && std::strcmp(argv[1], "--make") == 0)
      return make(static_cast<std::size_t>(std::strtoull(argv[2], nullptr, 10)), argv[3]);
  } catch (const splatkit::Error& e) {
    std::fprintf(stderr, "bench_read_ply: %s\n", e.what());
    return e.exit_code();
  }
  std::fprintf(stderr, "usage: bench_read_ply [--pcl] FILE | --make N FILE\n");
  return 1;
}
