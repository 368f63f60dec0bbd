// bench_laz_laszip IN.laz [THREADS]: native LASzip (LASzip/LASzip 3.5.1, built from source,
// Release) on a file in memory: its point reader (LASreadPoint over a ByteStreamInArrayLE, the
// classes laszip_dll.cpp drives) decoding each record's items straight into the output. LASzip's
// API has no per-chunk decompressor; for THREADS > 1 each std::thread gets its own reader and a
// contiguous range of whole chunks (THREADS equal shares of the chunk list), seeks to the range's
// first point (LASreadPoint::seek jumps by the chunk table) and reads its points in order. LASzip
// decodes POINT14 (formats 6-8) into its in-memory point (LAStempWritePoint10), not the record:
// the record's 30 bytes are written from it as LASzip's LASwriteItemRaw_POINT14_LE does. Timed:
// the readers' set-up (each reads the chunk table) and the decoding. Prints laz_bench::report's
// line. scripts/bench/laz.sh.
#include <lasreadpoint.hpp>
#include <bytestreamin_array.hpp>
#include <bytestreamout.hpp>
#include <laswriteitemraw.hpp>
#include <laszip.hpp>

#include <exception>
#include <thread>

#include "laz_bench_file.h"

namespace {

// LASwriteItemRaw_POINT14_LE::write, into `out` instead of a stream.
void point14_record(const LAStempWritePoint10& p, U8* out) {
  LAStempWritePoint14 r{};
  r.X = p.X;
  r.Y = p.Y;
  r.Z = p.Z;
  r.intensity = p.intensity;
  r.scan_direction_flag = p.scan_direction_flag;
  r.edge_of_flight_line = p.edge_of_flight_line;
  r.classification = p.classification & 31;
  r.user_data = p.user_data;
  r.point_source_ID = p.point_source_ID;
  if (p.extended_point_type) {
    r.classification_flags = (p.extended_classification_flags & 8) | (p.classification >> 5);
    if (r.classification == 0) r.classification = p.extended_classification;
    r.scanner_channel = p.extended_scanner_channel;
    r.return_number = p.extended_return_number;
    r.number_of_returns = p.extended_number_of_returns;
    r.scan_angle = p.extended_scan_angle;
  } else {
    r.classification_flags = p.classification >> 5;
    r.scanner_channel = 0;
    r.return_number = p.return_number;
    r.number_of_returns = p.number_of_returns;
    r.scan_angle = I16_QUANTIZE(p.scan_angle_rank / 0.006f);
  }
  std::memcpy(out, &r, 22);
  std::memcpy(out + 22, &p.gps_time, 8);
}

// Decodes points [begin, end) of the file into `out`; false when LASzip reports a failure.
bool decode_range(const laz_bench::File& f, uint64_t begin, uint64_t end,
                  std::vector<unsigned char>& out) {
  LASzip laszip;
  if (!laszip.unpack(f.bytes.data() + f.laszip_vlr, f.laszip_vlr_size)) return false;
  ByteStreamInArrayLE in(f.bytes.data(), static_cast<I64>(f.bytes.size()));
  if (!in.seek(static_cast<I64>(f.point_offset))) return false;
  LASreadPoint reader;
  if (!reader.setup(laszip.num_items, laszip.items, &laszip) || !reader.init(&in)) return false;
  if (begin > 0 && !reader.seek(0, static_cast<U32>(begin))) return false;
  std::vector<U8*> item(laszip.num_items);
  const bool point14 = laszip.items[0].type == LASitem::POINT14;
  alignas(8) U8 point[128];  // LASzip's in-memory point (POINT14)
  for (uint64_t i = begin; i < end; ++i) {
    U8* const record = out.data() + i * f.record_length;
    U8* rec = record;
    for (unsigned k = 0; k < laszip.num_items; ++k) {
      item[k] = rec;
      rec += laszip.items[k].size;
    }
    if (point14) item[0] = point;
    if (!reader.read(item.data())) return false;
    if (point14) point14_record(*reinterpret_cast<const LAStempWritePoint10*>(point), record);
  }
  return reader.done();
}

}  // namespace

int main(int argc, char** argv) try {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_laz_laszip IN.laz [THREADS]\n");
    return 2;
  }
  const laz_bench::File f = laz_bench::load(argv[1]);
  const int threads = laz_bench::threads_arg(argc, argv);
  if (f.chunk_size == 0xFFFFFFFFu) throw std::runtime_error("fixed-size chunks only");
  std::vector<unsigned char> out = laz_bench::touched_output(f);
  const uint64_t chunks = (f.count + f.chunk_size - 1) / f.chunk_size;
  const double c0 = laz_bench::cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<char> ok(threads, 0);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    const uint64_t begin = std::min(f.count, chunks * t / threads * f.chunk_size);
    const uint64_t end = std::min(f.count, chunks * (t + 1) / threads * f.chunk_size);
    pool.emplace_back([&, t, begin, end] { ok[t] = decode_range(f, begin, end, out); });
  }
  for (auto& t : pool) t.join();
  const double s = laz_bench::seconds_since(t0);
  const double cpu = laz_bench::cpu_seconds() - c0;
  for (char o : ok)
    if (!o) throw std::runtime_error("LASzip failed to decode");
  laz_bench::report("LASzip", f, s, cpu, out);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "bench_laz_laszip: %s\n", e.what());
  return 1;
}
