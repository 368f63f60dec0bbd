// Test helper for the LAZ tests (tests/e2e/laz.sh):
//   laz_records make FORMAT COUNT CHUNK SEED EXTRA_BYTES OUT.las OUT.laz
//     random but scan-like point records of LAS point data format FORMAT (0-3, 6-8) with
//     EXTRA_BYTES extra bytes per record, written uncompressed and as LAZ (chunks of CHUNK points;
//     "vN": variable chunks of N, N + 1, ... points) by splatkit's writer;
//   laz_records dump IN OUT.bin [THREADS]
//     the records of a LAS/LAZ file as splatkit decodes them (LAZ decompressed), concatenated;
//   laz_records cut IN.laz OUT.laz K NBYTES
//     a copy of a LAZ file written by `make` whose chunk K lost its last NBYTES bytes, with a chunk
//     table that agrees (a truncated chunk the table cannot reveal).
// The records exercise every field and every branch of the LASzip models: coordinate jumps up to
// the full 32-bit range, return-number contexts, flag changes, classification flags, scan-angle
// wrap-around, several interleaved GPS time sequences with 64-bit jumps, grey and coloured RGB;
// for formats 6-8 also the four scanner channels (each its own context in the layered models),
// 4-bit return counts, classification flags, 16-bit scan angles, NIR, and fields that stay
// constant over a whole chunk (empty layers).
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "formats/las.h"
#include "formats/las_writer.h"
#include "formats/laz_chunk.h"
#include "formats/little_endian.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"
#include "splatkit/output_file.h"

namespace {

using splatkit::le::put16;
using splatkit::le::put32;
using splatkit::le::put64;

using splatkit::LasRecordsLayout;

// Formats 6-8 (LAS 1.4 records). `seed` odd: intensity, user data and point source stay constant
// (their layers are empty).
std::vector<unsigned char> make_records14(int format, uint64_t count, unsigned seed, int extra,
                                          LasRecordsLayout& layout) {
  static constexpr uint16_t kSize[3] = {30, 36, 38};
  layout.format = format;
  layout.record_length = static_cast<uint16_t>(kSize[format - 6] + extra);
  const std::size_t rl = layout.record_length;
  std::vector<unsigned char> out(count * rl);
  std::mt19937_64 rng(seed);
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  auto chance = [&](double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; };
  const bool constant = seed % 2 == 1;
  struct Channel {
    int32_t x = 1000000, y = -2000000, z = 5000;
    double t = 300000.0;
    unsigned ret = 1, nret = 1;
  } ch[4];
  uint16_t intensity = 300, source = 7, rgb[3] = {1000, 2000, 3000}, nir = 500;
  unsigned char cls = 2, cflags = 0, user = 0;
  int16_t angle = -2000;
  unsigned channel = 0;
  double time_jump[2] = {1.0e9, -5.0};
  for (uint64_t i = 0; i < count; ++i) {
    unsigned char* r = out.data() + i * rl;
    if (chance(0.03)) channel = static_cast<unsigned>(uni(0, 3));
    Channel& c = ch[channel];
    c.x += static_cast<int32_t>(uni(-30, 60));
    c.y += static_cast<int32_t>(uni(-5, 5));
    c.z += static_cast<int32_t>(uni(-40, 40));
    if (chance(0.01)) c.y += static_cast<int32_t>(uni(100, 5000));
    if (chance(0.002)) {
      c.x = static_cast<int32_t>(uni(INT32_MIN, INT32_MAX));
      c.z = static_cast<int32_t>(uni(INT32_MIN, INT32_MAX));
    }
    put32(r, static_cast<uint32_t>(c.x));
    put32(r + 4, static_cast<uint32_t>(c.y));
    put32(r + 8, static_cast<uint32_t>(c.z));
    if (!constant && chance(0.7))
      intensity = static_cast<uint16_t>(chance(0.05) ? uni(0, 65535) : intensity + uni(-20, 20));
    put16(r + 12, intensity);
    // Returns of a pulse in order (same time), new pulses, rare odd combinations (0, > n, 15).
    bool new_pulse = true;
    if (c.ret < c.nret && chance(0.9)) {
      ++c.ret;
      new_pulse = false;
    } else if (chance(0.9)) {
      c.nret = static_cast<unsigned>(chance(0.8) ? uni(1, 3) : uni(1, 15));
      c.ret = 1;
    } else {
      c.nret = static_cast<unsigned>(uni(0, 15));
      c.ret = static_cast<unsigned>(uni(0, 15));
    }
    r[14] = static_cast<unsigned char>(c.ret | c.nret << 4);
    if (chance(0.02)) cflags = static_cast<unsigned char>(uni(0, 15));
    const unsigned dir = chance(0.5) ? 1 : 0, edge = chance(0.02) ? 1 : 0;
    r[15] = static_cast<unsigned char>(cflags | channel << 4 | dir << 6 | edge << 7);
    if (chance(0.05)) cls = static_cast<unsigned char>(chance(0.8) ? uni(0, 31) : uni(32, 255));
    r[16] = cls;
    if (!constant && chance(0.02)) user = static_cast<unsigned char>(uni(0, 255));
    r[17] = user;
    if (chance(0.2)) angle = static_cast<int16_t>(angle + uni(-300, 300));
    if (chance(0.01)) angle = static_cast<int16_t>(uni(-30000, 30000));
    put16(r + 18, static_cast<uint16_t>(angle));
    if (!constant && chance(0.01)) source = static_cast<uint16_t>(uni(0, 65535));
    put16(r + 20, source);
    if (new_pulse) {
      if (chance(0.9)) c.t += 1.0e-5 * static_cast<double>(uni(1, 3));
      if (chance(0.01)) c.t += static_cast<double>(uni(-1000000, 1000000));
      if (chance(0.005)) std::swap(c.t, time_jump[uni(0, 1)]);
      if (chance(0.005)) c.t = static_cast<double>(uni(-1000000000, 1000000000)) * 1.5;
      if (chance(0.01)) c.t -= 3.0e-5;
    }
    uint64_t bits;
    std::memcpy(&bits, &c.t, 8);
    put64(r + 22, bits);
    std::size_t at = 30;
    if (format >= 7) {
      if (chance(0.6)) {
        if (chance(0.3)) {
          rgb[0] = rgb[1] = rgb[2] = static_cast<uint16_t>(uni(0, 65535));
        } else {
          for (uint16_t& v : rgb)
            v = static_cast<uint16_t>(chance(0.5) ? v + uni(-300, 300)
                                                  : (v & 0xFF00) | uni(0, 255));
        }
      }
      for (int k = 0; k < 3; ++k) put16(r + at + 2 * k, rgb[k]);
      at += 6;
    }
    if (format == 8) {
      if (chance(0.5))
        nir = static_cast<uint16_t>(chance(0.5) ? nir + uni(-50, 50) : uni(0, 65535));
      put16(r + at, nir);
      at += 2;
    }
    for (int e = 0; e < extra; ++e)
      r[at + e] = static_cast<unsigned char>(e == 0 ? 42  // one byte constant (an empty layer)
                                             : chance(0.5) && i > 0 ? (r - rl)[at + e] + uni(-2, 2)
                                                                    : uni(0, 255));
  }
  layout.scale[0] = layout.scale[1] = layout.scale[2] = 0.01;
  return out;
}

std::vector<unsigned char> make_records(int format, uint64_t count, unsigned seed, int extra,
                                        LasRecordsLayout& layout) {
  if (format >= 6) return make_records14(format, count, seed, extra, layout);
  static constexpr uint16_t kSize[4] = {20, 28, 26, 34};
  layout.format = format;
  layout.record_length = static_cast<uint16_t>(kSize[format] + extra);
  const std::size_t rl = layout.record_length;
  std::vector<unsigned char> out(count * rl);
  std::mt19937_64 rng(seed);
  auto uni = [&](int64_t lo, int64_t hi) {
    return std::uniform_int_distribution<int64_t>(lo, hi)(rng);
  };
  auto chance = [&](double p) { return std::uniform_real_distribution<double>(0, 1)(rng) < p; };
  int32_t x = 1000000, y = -2000000, z = 5000;
  uint16_t intensity = 300, source = 7, rgb[3] = {1000, 2000, 3000};
  unsigned char flags = 0x09, cls = 2, user = 0;
  int8_t angle = -20;
  double time_base[3] = {300000.0, 1.0e9, -5.0};
  int seq = 0;
  for (uint64_t i = 0; i < count; ++i) {
    unsigned char* r = out.data() + i * rl;
    // Scan lines: small steps, a new line now and then, rare wild jumps (full 32-bit range).
    x += static_cast<int32_t>(uni(-30, 60));
    y += static_cast<int32_t>(uni(-5, 5));
    z += static_cast<int32_t>(uni(-40, 40));
    if (chance(0.01)) y += static_cast<int32_t>(uni(100, 5000));
    if (chance(0.002)) {
      x = static_cast<int32_t>(uni(INT32_MIN, INT32_MAX));
      z = static_cast<int32_t>(uni(INT32_MIN, INT32_MAX));
    }
    put32(r, static_cast<uint32_t>(x));
    put32(r + 4, static_cast<uint32_t>(y));
    put32(r + 8, static_cast<uint32_t>(z));
    if (chance(0.7))
      intensity = static_cast<uint16_t>(chance(0.05) ? uni(0, 65535) : intensity + uni(-20, 20));
    put16(r + 12, intensity);
    if (chance(0.3)) {  // returns r of n (sometimes invalid combinations), scan direction, edge
      const int n = static_cast<int>(chance(0.9) ? uni(1, 5) : uni(0, 7));
      const int ret = static_cast<int>(chance(0.9) ? uni(1, n > 0 ? n : 1) : uni(0, 7));
      flags = static_cast<unsigned char>(ret | n << 3 | (chance(0.5) ? 0x40 : 0) |
                                         (chance(0.02) ? 0x80 : 0));
    }
    r[14] = flags;
    if (chance(0.05))
      cls = static_cast<unsigned char>(uni(0, 31) | (chance(0.1) ? uni(1, 7) << 5 : 0));
    r[15] = cls;
    if (chance(0.2)) angle = static_cast<int8_t>(angle + uni(-3, 3));
    if (chance(0.01)) angle = static_cast<int8_t>(uni(-128, 127));
    r[16] = static_cast<unsigned char>(angle);
    if (chance(0.02)) user = static_cast<unsigned char>(uni(0, 255));
    r[17] = user;
    if (chance(0.01)) source = static_cast<uint16_t>(uni(0, 65535));
    put16(r + 18, source);
    std::size_t at = 20;
    if (format == 1 || format == 3) {
      // Mostly regular pulses; repeats; other sequences; huge jumps; negative steps.
      if (chance(0.05)) seq = static_cast<int>(uni(0, 2));
      if (chance(0.8)) time_base[seq] += 1.0e-5 * static_cast<double>(uni(1, 3));
      if (chance(0.01)) time_base[seq] += static_cast<double>(uni(-1000000, 1000000));
      if (chance(0.005)) time_base[seq] = static_cast<double>(uni(-1000000000, 1000000000)) * 1.5;
      if (chance(0.01)) time_base[seq] -= 3.0e-5;
      uint64_t bits;
      std::memcpy(&bits, &time_base[seq], 8);
      put64(r + at, bits);
      at += 8;
    }
    if (format == 2 || format == 3) {
      if (chance(0.6)) {
        if (chance(0.3)) {  // grey
          rgb[0] = rgb[1] = rgb[2] = static_cast<uint16_t>(uni(0, 65535));
        } else {
          for (uint16_t& c : rgb)
            c = static_cast<uint16_t>(chance(0.5) ? c + uni(-300, 300)
                                                  : (c & 0xFF00) | uni(0, 255));
        }
      }
      for (int k = 0; k < 3; ++k) put16(r + at + 2 * k, rgb[k]);
      at += 6;
    }
    for (int e = 0; e < extra; ++e)
      r[at + e] = static_cast<unsigned char>(chance(0.5) && i > 0 ? (r - rl)[at + e] + uni(-2, 2)
                                                                  : uni(0, 255));
  }
  layout.scale[0] = layout.scale[1] = layout.scale[2] = 0.01;
  return out;
}

int make(int argc, char** argv) {
  if (argc != 9) return 1;
  const int format = std::stoi(argv[2]);
  const uint64_t count = std::stoull(argv[3]);
  // CHUNK "v5000": variable-size chunks (5000, 5001, 5002, ... points, counts in the table).
  const bool variable = argv[4][0] == 'v';
  const auto chunk = static_cast<uint32_t>(std::stoul(argv[4] + (variable ? 1 : 0)));
  const auto seed = static_cast<unsigned>(std::stoul(argv[5]));
  const int extra = std::stoi(argv[6]);
  if (format < 0 || format > 8 || (format > 3 && format < 6) || extra < 0 || extra > 64 ||
      chunk == 0)
    return 1;
  LasRecordsLayout layout;
  const std::vector<unsigned char> records = make_records(format, count, seed, extra, layout);
  for (int compressed = 0; compressed < 2; ++compressed) {
    splatkit::OutputFile out(argv[7 + compressed]);
    splatkit::write_las_records(out, layout, records.data(), count, compressed != 0, chunk,
                                variable);
    out.commit();
  }
  return 0;
}

int dump(int argc, char** argv) {
  if (argc != 4 && argc != 5) return 1;
  // Optional worker thread count (the chunks are decoded in parallel), for the bench.
  const int threads = argc == 5 ? std::stoi(argv[4]) : 0;
  std::optional<tbb::global_control> limit;
  if (threads > 0)
    limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  splatkit::InputStream in(argv[2]);
  splatkit::OutputFile out(argv[3]);
  std::size_t rl = 0;
  const splatkit::LasRecordsInfo info = splatkit::read_las_records(
      in, [&](const unsigned char* records, std::size_t n) { out.write(records, n * rl); },
      [&](const splatkit::LasRecordsInfo& i) { rl = i.record_length; });
  out.commit();
  std::printf("%llu %u %d\n", static_cast<unsigned long long>(info.count), info.record_length,
              info.format);
  return 0;
}

uint64_t get64(const std::vector<unsigned char>& d, std::size_t at) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = v << 8 | d[at + static_cast<std::size_t>(i)];
  return v;
}

int cut(int argc, char** argv) {
  if (argc != 6) return 1;
  std::vector<unsigned char> d;
  {
    splatkit::InputStream in(argv[2]);
    unsigned char buf[65536];
    for (std::size_t got; (got = in.read_some(buf, sizeof buf)) > 0;)
      d.insert(d.end(), buf, buf + got);
  }
  const std::size_t k = std::stoul(argv[4]), nbytes = std::stoul(argv[5]);
  const std::size_t point_offset =
      d[96] | d[97] << 8 | d[98] << 16 | static_cast<std::size_t>(d[99]) << 24;
  const std::size_t table = get64(d, point_offset);
  const uint32_t n = d[table + 4] | d[table + 5] << 8 | d[table + 6] << 16 |
                     static_cast<uint32_t>(d[table + 7]) << 24;
  std::vector<splatkit::laz::ChunkEntry> chunks =
      splatkit::laz::decode_chunk_table(std::span(d).subspan(table + 8), n, false);
  if (k >= n || chunks[k].bytes <= nbytes) return 1;
  std::size_t end = point_offset + 8;
  for (std::size_t i = 0; i <= k; ++i) end += chunks[i].bytes;
  std::vector<unsigned char> out(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(end - nbytes));
  out.insert(out.end(), d.begin() + static_cast<std::ptrdiff_t>(end),
             d.begin() + static_cast<std::ptrdiff_t>(table));
  chunks[k].bytes -= nbytes;
  const uint64_t new_table = out.size();
  for (int i = 0; i < 8; ++i)
    out[point_offset + static_cast<std::size_t>(i)] =
        static_cast<unsigned char>(new_table >> (8 * i));
  splatkit::laz::encode_chunk_table(chunks, false, out);
  splatkit::OutputFile o(argv[3]);
  o.write(out.data(), out.size());
  o.commit();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    const int rc = mode == "make"   ? make(argc, argv)
                   : mode == "dump" ? dump(argc, argv)
                   : mode == "cut"  ? cut(argc, argv)
                                    : 1;
    if (rc == 1)
      std::fprintf(stderr,
                   "usage: laz_records make FORMAT COUNT CHUNK SEED EXTRA OUT.las OUT.laz\n"
                   "       laz_records dump IN OUT.bin [THREADS]\n"
                   "       laz_records cut IN.laz OUT.laz K NBYTES\n");
    return rc;
  } catch (const splatkit::Error& e) {
    std::fprintf(stderr, "laz_records: %s\n", e.what());
    return e.exit_code();
  }
}
