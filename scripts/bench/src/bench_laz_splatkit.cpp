// bench_laz_splatkit IN.laz [THREADS]: splatkit's LAZ decoder as splat-convert runs it
// (read_laz_points: chunk table, checks, runs of chunks decoded in parallel in a TBB pipeline and
// handed to the sink in order while later runs are decoded) on a file in memory; the sink copies
// each run into the output records. Prints laz_bench::report's line. scripts/bench/laz.sh.
#include <tbb/global_control.h>

#include <cstring>
#include <exception>

#include "formats/laz.h"
#include "laz_bench_file.h"
#include "splatkit/input_stream.h"

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_laz_splatkit IN.laz [THREADS]\n");
    return 2;
  }
  const laz_bench::File f = laz_bench::load(argv[1]);
  const int threads = laz_bench::threads_arg(argc, argv);
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  std::vector<unsigned char> out = laz_bench::touched_output(f);
  splatkit::LazPointsInfo info;
  info.format = f.format;
  info.record_length = f.record_length;
  info.count = f.count;
  info.point_offset = f.point_offset;
  info.laszip_vlr = std::span(f.bytes).subspan(f.laszip_vlr, f.laszip_vlr_size);
  info.has_laszip_vlr = true;
  info.evlr_start = f.evlr_start;
  info.evlr_count = f.evlr_count;
  const double c0 = laz_bench::cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  splatkit::check_laz_vlr(argv[1], info);
  splatkit::InputStream in(argv[1], f.bytes.data() + f.point_offset,
                           f.bytes.size() - f.point_offset);
  std::size_t at = 0;
  splatkit::read_laz_points(in, info, [&](const unsigned char* records, std::size_t n) {
    std::memcpy(out.data() + at, records, n * f.record_length);
    at += n * f.record_length;
  });
  const double s = laz_bench::seconds_since(t0);
  const double cpu = laz_bench::cpu_seconds() - c0;
  laz_bench::report("splatkit", f, s, cpu, out);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_laz_splatkit: %s\n", e.what());
  return 1;
}
