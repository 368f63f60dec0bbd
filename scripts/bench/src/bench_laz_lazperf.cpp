// bench_laz_lazperf IN.laz [THREADS]: native laz-perf (hobuinc/laz-perf 3.4, built from source,
// Release) on a file in memory: its chunk table decoder (lazperf::decompress_chunk_table), then
// every chunk by its own lazperf::reader::chunk_decompressor writing the chunk's records straight
// into the output (the per-chunk decompressor laz-perf offers for parallel use); THREADS
// std::threads take chunks in turn from a shared counter. Timed: the chunk table and the chunks.
// Prints laz_bench::report's line. scripts/bench/laz.sh.
#include <lazperf/lazperf.hpp>
#include <lazperf/readers.hpp>

#include <atomic>
#include <exception>
#include <thread>

#include "laz_bench_file.h"

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_laz_lazperf IN.laz [THREADS]\n");
    return 2;
  }
  const laz_bench::File f = laz_bench::load(argv[1]);
  const int threads = laz_bench::threads_arg(argc, argv);
  std::vector<unsigned char> out = laz_bench::touched_output(f);
  static constexpr int kBaseSize[] = {20, 28, 26, 34, 0, 0, 30, 36, 38};
  const int eb_count = f.record_length - kBaseSize[f.format];
  const bool variable = f.chunk_size == 0xFFFFFFFFu;
  const double c0 = laz_bench::cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  const uint64_t table = laz_bench::get<uint64_t>(f.bytes, f.point_offset);
  const uint32_t n = laz_bench::get<uint32_t>(f.bytes, table + 4);
  const unsigned char* src = f.bytes.data() + table + 8;
  std::vector<lazperf::chunk> chunks = lazperf::decompress_chunk_table(
      [&src](unsigned char* b, size_t len) {
        std::memcpy(b, src, len);
        src += len;
      },
      n, variable);
  std::vector<uint64_t> offset(n), first(n);  // the table holds sizes: offsets by summing
  uint64_t at = f.point_offset + 8, p = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (!variable) chunks[i].count = std::min<uint64_t>(f.chunk_size, f.count - p);
    offset[i] = at;
    first[i] = p;
    at += chunks[i].offset;
    p += chunks[i].count;
  }
  std::atomic<uint32_t> next{0};
  auto work = [&] {
    for (uint32_t i; (i = next.fetch_add(1)) < n;) {
      lazperf::reader::chunk_decompressor d(
          f.format, eb_count, reinterpret_cast<const char*>(f.bytes.data() + offset[i]));
      char* rec = reinterpret_cast<char*>(out.data() + first[i] * f.record_length);
      for (uint64_t k = 0; k < chunks[i].count; ++k, rec += f.record_length) d.decompress(rec);
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  const double s = laz_bench::seconds_since(t0);
  const double cpu = laz_bench::cpu_seconds() - c0;
  laz_bench::report("laz-perf", f, s, cpu, out);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_laz_lazperf: %s\n", e.what());
  return 1;
}
