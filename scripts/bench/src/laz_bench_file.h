// The shared part of the LAZ decoding benchmarks (scripts/bench/laz.sh): a LAZ file read whole
// into memory with the few LAS header fields the decoders need, the output buffer every
// harness decodes into (allocated and touched before the clock starts), a checksum of the
// decoded records (so that the script can check the three decoders produce the same records and
// no compiler drops the work) and the one output line. Bench code only: no bounds checks beyond
// what keeps a well-formed file from crashing; the inputs are made by splat-convert.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace laz_bench {

struct File {
  std::vector<unsigned char> bytes;   // the whole file
  int format = 0;                     // point data format (compression bits cleared)
  uint16_t record_length = 0;         // bytes per record
  uint64_t count = 0;                 // points
  uint64_t point_offset = 0;          // file offset of the point data
  uint64_t laszip_vlr = 0;            // file offset of the LASzip VLR's payload
  uint16_t laszip_vlr_size = 0;       // and its size
  uint64_t evlr_start = 0;            // LAS 1.4
  uint32_t evlr_count = 0;
  uint32_t chunk_size = 0;            // from the LASzip VLR (0xFFFFFFFF: variable)
};

template <class T>
T get(const std::vector<unsigned char>& b, uint64_t at) {
  if (at + sizeof(T) > b.size()) throw std::runtime_error("LAZ bench: file too short");
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));  // x86-64: little-endian like the file
  return v;
}

inline File load(const char* path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(std::string("cannot open ") + path);
  File f;
  f.bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  const auto& b = f.bytes;
  const uint8_t minor = get<uint8_t>(b, 25);
  const uint16_t header_size = get<uint16_t>(b, 94);
  f.point_offset = get<uint32_t>(b, 96);
  const uint32_t vlrs = get<uint32_t>(b, 100);
  f.format = get<uint8_t>(b, 104) & 0x3F;
  f.record_length = get<uint16_t>(b, 105);
  f.count = get<uint32_t>(b, 107);
  if (minor >= 4) {
    f.evlr_start = get<uint64_t>(b, 235);
    f.evlr_count = get<uint32_t>(b, 243);
    f.count = get<uint64_t>(b, 247);
  }
  uint64_t at = header_size;
  for (uint32_t i = 0; i < vlrs; ++i) {
    const uint16_t id = get<uint16_t>(b, at + 18), length = get<uint16_t>(b, at + 20);
    if (std::memcmp(b.data() + at + 2, "laszip encoded", 14) == 0 && id == 22204) {
      f.laszip_vlr = at + 54;
      f.laszip_vlr_size = length;
      f.chunk_size = get<uint32_t>(b, at + 54 + 12);
    }
    at += 54 + length;
  }
  if (f.laszip_vlr == 0) throw std::runtime_error(std::string(path) + ": no LASzip VLR");
  return f;
}

// The records' buffer, written once before timing (its pages are mapped: no page fault is timed).
inline std::vector<unsigned char> touched_output(const File& f) {
  return std::vector<unsigned char>(f.count * f.record_length, 0xAB);
}

inline uint64_t checksum(const std::vector<unsigned char>& out) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a over 8-byte words
  std::size_t i = 0;
  for (; i + 8 <= out.size(); i += 8) {
    uint64_t w;
    std::memcpy(&w, out.data() + i, 8);
    h = (h ^ w) * 1099511628211ull;
  }
  for (; i < out.size(); ++i) h = (h ^ out[i]) * 1099511628211ull;
  return h;
}

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// CPU seconds of the whole process so far (all threads).
inline double cpu_seconds() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// "NAME POINTS SECONDS CHECKSUM CPU-SECONDS", parsed by laz.sh.
inline void report(const char* name, const File& f, double seconds, double cpu,
                   const std::vector<unsigned char>& out) {
  std::printf("%s %llu %.6f %016llx %.6f\n", name, static_cast<unsigned long long>(f.count),
              seconds, static_cast<unsigned long long>(checksum(out)), cpu);
}

inline int threads_arg(int argc, char** argv) {
  const int t = argc > 2 ? std::atoi(argv[2]) : 1;
  return t < 1 ? 1 : t;
}

}  // namespace laz_bench
