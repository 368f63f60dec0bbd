#include "formats/las_writer.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <limits>
#include <string>
#include <vector>

#include "formats/laz_chunk.h"
#include "formats/little_endian.h"
#include "splatkit/error.h"

namespace splatkit {

namespace {

using le::put16;
using le::put32;
using le::put64;

constexpr std::size_t kHeaderSize12 = 227, kHeaderSize14 = 375, kVlrHeaderSize = 54;
constexpr uint16_t kFormatSize[9] = {20, 28, 26, 34, 0, 0, 30, 36, 38};

void putf64(unsigned char* p, double v) { put64(p, std::bit_cast<uint64_t>(v)); }
int32_t get_i32(const unsigned char* p) {
  return static_cast<int32_t>(static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
                              static_cast<uint32_t>(p[2]) << 16 |
                              static_cast<uint32_t>(p[3]) << 24);
}
void put_text(unsigned char* p, std::size_t n, const std::string& s) {
  std::memcpy(p, s.data(), std::min(n, s.size()));
}

}  // namespace

std::pair<uint16_t, uint16_t> las_creation_date() {
  const char* env = std::getenv("SOURCE_DATE_EPOCH");
  long long seconds = 0;
  if (env && *env) {
    const char* end = env + std::strlen(env);
    const auto [at, ec] = std::from_chars(env, end, seconds);
    std::tm tm{};
    const std::time_t t = static_cast<std::time_t>(seconds);
    if (ec == std::errc() && at == end && seconds >= 0 && ::gmtime_r(&t, &tm) &&
        tm.tm_year + 1900 <= 65535)
      return {static_cast<uint16_t>(tm.tm_yday + 1), static_cast<uint16_t>(tm.tm_year + 1900)};
  }
  return {1, 2000};
}

void write_las_records(OutputFile& out, const LasRecordsLayout& layout,
                       const unsigned char* records, uint64_t count, bool compressed,
                       uint32_t chunk_size, bool variable_chunks) {
  const bool v14 = layout.format >= 6;
  if (!v14 && count > 0xFFFFFFFFu)
    throw_unsupported(out.path(), "LAS 1.2 holds at most 4294967295 points, the cloud has " +
                                      std::to_string(count) +
                                      " (point data formats 6-8 write LAS 1.4)");
  const std::size_t rl = layout.record_length;
  const std::size_t header_size = v14 ? kHeaderSize14 : kHeaderSize12;
  std::vector<unsigned char> vlr;
  if (compressed) {
    laz::LaszipVlr v;
    v.chunk_size = variable_chunks ? laz::kVariableChunkSize : chunk_size;
    v.items = laz::items_for_format(layout.format, layout.record_length);
    if (v14) {  // what LASzip 3.4 writes for LAS 1.4 point types
      v.compressor = laz::kLayeredChunked;
      v.version_major = 3;
      v.version_minor = 4;
      v.revision = 3;
    }
    const std::vector<unsigned char> payload = laz::laszip_vlr_payload(v);
    vlr.assign(kVlrHeaderSize, 0);
    put_text(&vlr[2], 16, laz::kLaszipUserId);
    put16(&vlr[18], laz::kLaszipRecordId);
    put16(&vlr[20], static_cast<uint32_t>(payload.size()));
    put_text(&vlr[22], 32, "by splatkit");
    vlr.insert(vlr.end(), payload.begin(), payload.end());
  }
  unsigned char h[kHeaderSize14] = {};
  std::memcpy(h, "LASF", 4);
  if (v14) put16(h + 6, 16);  // global encoding: coordinate system as WKT (required for 6-10)
  h[24] = 1;
  h[25] = v14 ? 4 : 2;
  put_text(h + 26, 32, "splatkit");
  put_text(h + 58, 32, layout.generating_software);
  const auto [day, year] = layout.creation_year
                               ? std::pair(layout.creation_day, layout.creation_year)
                               : las_creation_date();
  put16(h + 90, day);
  put16(h + 92, year);
  put16(h + 94, static_cast<uint32_t>(header_size));
  put32(h + 96, static_cast<uint32_t>(header_size + vlr.size()));
  put32(h + 100, compressed ? 1 : 0);
  h[104] = static_cast<unsigned char>(layout.format | (compressed ? 0x80 : 0));
  put16(h + 105, layout.record_length);
  put32(h + 107, v14 ? 0 : static_cast<uint32_t>(count));  // LAS 1.4: legacy count 0 for 6-10
  uint64_t by_return[15] = {};
  int32_t lo[3] = {INT32_MAX, INT32_MAX, INT32_MAX}, hi[3] = {INT32_MIN, INT32_MIN, INT32_MIN};
  for (uint64_t i = 0; i < count; ++i) {
    const unsigned char* r = records + i * rl;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], get_i32(r + 4 * k));
      hi[k] = std::max(hi[k], get_i32(r + 4 * k));
    }
    const int ret = r[14] & (v14 ? 15 : 7);
    if (ret >= 1 && ret <= (v14 ? 15 : 5)) ++by_return[ret - 1];
  }
  if (v14) {
    put64(h + 247, count);
    for (int k = 0; k < 15; ++k) put64(h + 255 + 8 * k, by_return[k]);
  } else {
    for (int k = 0; k < 5; ++k) put32(h + 111 + 4 * k, static_cast<uint32_t>(by_return[k]));
  }
  for (int k = 0; k < 3; ++k) {
    putf64(h + 131 + 8 * k, layout.scale[k]);
    putf64(h + 155 + 8 * k, layout.offset[k]);
    putf64(h + 179 + 16 * k, count ? hi[k] * layout.scale[k] + layout.offset[k] : 0);
    putf64(h + 187 + 16 * k, count ? lo[k] * layout.scale[k] + layout.offset[k] : 0);
  }
  out.write(h, header_size);
  out.write(vlr.data(), vlr.size());
  if (!compressed) {
    out.write(records, count * rl);
    return;
  }
  // Chunks are compressed in memory first: the chunk table's offset comes before them.
  std::vector<unsigned char> data(8);
  std::vector<laz::ChunkEntry> table;
  for (uint64_t first = 0, n = 0; first < count; first += n) {
    n = std::min<uint64_t>(chunk_size + (variable_chunks ? table.size() : 0), count - first);
    const std::size_t before = data.size();
    laz::encode_chunk(records + first * rl, n,
                      laz::items_for_format(layout.format, layout.record_length), data);
    table.push_back({n, data.size() - before});
  }
  put64(data.data(), header_size + vlr.size() + data.size());
  laz::encode_chunk_table(table, variable_chunks, data);
  out.write(data.data(), data.size());
}

int las_output_format(const LoadedCloud& doc, int las_format) {
  const SplatCloud& c = doc.cloud;
  if (las_format >= 0) return las_format;
  if ((doc.format == "las" || doc.format == "laz") && doc.header.contains("point_format") &&
      doc.header["point_format"].is_number_integer() && doc.header["point_format"].get<int>() >= 6)
    return !c.has_colors() ? 6 : c.find_extra("nir") ? 8 : 7;
  return (c.has_colors() ? 2 : 0) + (c.find_extra("gps_time") ? 1 : 0);
}

std::vector<std::string> las_kept_attributes(int format) {
  std::vector<std::string> kept = {"intensity",      "return_number", "number_of_returns",
                                   "classification", "scan_angle",    "user_data",
                                   "point_source_id"};
  if (format == 1 || format == 3 || format >= 6) kept.push_back("gps_time");
  if (format == 8) kept.push_back("nir");
  return kept;
}

void write_las(const LoadedCloud& doc, OutputFile& out, bool compressed, int las_format) {
  const SplatCloud& c = doc.cloud;
  auto extra = [&](const char* name) { return c.find_extra(name); };
  const ExtraAttribute* gps = extra("gps_time");
  LasRecordsLayout layout;
  layout.format = las_output_format(doc, las_format);
  layout.record_length = kFormatSize[layout.format];
  const bool v14 = layout.format >= 6;
  // Scale and offset: the source's when it was LAS, so that LAS -> LAZ keeps every integer.
  bool from_las = false;
  if (doc.header.contains("scale") && doc.header.contains("offset") &&
      doc.header["scale"].is_array() && doc.header["scale"].size() == 3 &&
      doc.header["offset"].is_array() && doc.header["offset"].size() == 3 &&
      (doc.format == "las" || doc.format == "laz")) {
    from_las = true;
    for (int k = 0; k < 3; ++k) {
      layout.scale[k] = doc.header["scale"][k].get<double>();
      layout.offset[k] = doc.header["offset"][k].get<double>();
    }
  }
  if (!from_las) {
    // Per axis: 0.001 (a millimetre for metres), finer while fewer than 10^5 steps span the
    // points (degrees of longitude beside heights in metres, unit-size models), coarser until
    // the farthest coordinate from the offset fits 32 bits.
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0}, reach[3] = {0, 0, 0};
    for (std::size_t i = 0; i < c.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const double v = c.positions[i][k];
        lo[k] = i == 0 ? v : std::min(lo[k], v);
        hi[k] = i == 0 ? v : std::max(hi[k], v);
        reach[k] = std::max(reach[k], std::abs(v));
      }
    for (int k = 0; k < 3; ++k) {
      int e = -3;  // scale 10^e
      while ((hi[k] - lo[k]) / std::pow(10.0, e) < 1.0e5 && e > -12) --e;
      while (reach[k] / std::pow(10.0, e) > 2.0e9) ++e;
      const double scale = std::pow(10.0, e);
      layout.scale[k] = scale;
      layout.offset[k] = c.origin[k];
    }
  }
  const std::size_t rl = layout.record_length;
  std::vector<unsigned char> records(c.size() * rl, 0);
  // A field the cloud has no attribute for gets `absent`.
  auto value = [&](const ExtraAttribute* e, std::size_t i, double lo, double hi,
                   double absent = 0.0) {
    if (!e) return absent;
    const double v = e->values[i];
    return std::isfinite(v) ? std::clamp(std::round(v), lo, hi) : 0.0;
  };
  const ExtraAttribute *intensity = extra("intensity"), *ret = extra("return_number"),
                       *rets = extra("number_of_returns"), *cls = extra("classification"),
                       *angle = extra("scan_angle"), *user = extra("user_data"),
                       *source = extra("point_source_id");
  // Return k of n: a cloud with return numbers but no counts gets n = k, the fewest returns that
  // hold k; one with neither is each point its own single return (return 0 is not valid). Counts
  // the cloud has are written as they are, even below the number (a round trip keeps the data).
  auto returns = [&](std::size_t i, double top) {
    return static_cast<int>(value(ret, i, 0, top, 1));
  };
  auto returns_total = [&](std::size_t i, double top) {
    return rets ? static_cast<int>(value(rets, i, 0, top)) : std::max(returns(i, top), 1);
  };
  for (std::size_t i = 0; i < c.size(); ++i) {
    unsigned char* r = records.data() + i * rl;
    const Vec3f& p = c.positions[i];
    const double xyz[3] = {c.origin[0] + p.x, c.origin[1] + p.y, c.origin[2] + p.z};
    for (int k = 0; k < 3; ++k) {
      const double q = std::round((xyz[k] - layout.offset[k]) / layout.scale[k]);
      if (!(q >= INT32_MIN && q <= INT32_MAX))
        throw_unsupported(out.path(), "point " + std::to_string(i) +
                                          " does not fit LAS's 32-bit "
                                          "coordinates with scale " +
                                          std::to_string(layout.scale[k]));
      put32(r + 4 * k, static_cast<uint32_t>(static_cast<int32_t>(q)));
    }
    put16(r + 12, static_cast<uint32_t>(value(intensity, i, 0, 65535)));
    std::size_t at;
    if (v14) {
      r[14] = static_cast<unsigned char>(returns(i, 15) | returns_total(i, 15) << 4);
      r[16] = static_cast<unsigned char>(value(cls, i, 0, 255));
      r[17] = static_cast<unsigned char>(value(user, i, 0, 255));
      // Degrees to LAS 1.4's 0.006 degree steps (the int16 range: files beyond +-30000 read back).
      const double steps = angle && std::isfinite(angle->values[i])
                               ? std::clamp(std::round(angle->values[i] / 0.006), -32768.0, 32767.0)
                               : 0.0;
      put16(r + 18, static_cast<uint16_t>(static_cast<int16_t>(steps)));
      put16(r + 20, static_cast<uint32_t>(value(source, i, 0, 65535)));
      putf64(r + 22, gps ? gps->values[i] : 0.0);
      at = 30;
    } else {
      r[14] = static_cast<unsigned char>(returns(i, 7) | returns_total(i, 7) << 3);
      r[15] = static_cast<unsigned char>(value(cls, i, 0, 31));
      r[16] = static_cast<unsigned char>(static_cast<int8_t>(value(angle, i, -128, 127)));
      r[17] = static_cast<unsigned char>(value(user, i, 0, 255));
      put16(r + 18, static_cast<uint32_t>(value(source, i, 0, 65535)));
      at = 20;
      if (layout.format == 1 || layout.format == 3) {
        putf64(r + at, gps ? gps->values[i] : 0.0);
        at += 8;
      }
    }
    const bool rgb = v14 ? layout.format >= 7 : layout.format >= 2;
    if (rgb && c.has_colors()) {
      const int mul = c.color_bits == 8 ? 257 : 1;
      for (int k = 0; k < 3; ++k)
        put16(r + at + 2 * k, static_cast<uint32_t>(c.colors[i][k] * mul));
    }
    if (layout.format == 8) put16(r + 36, static_cast<uint32_t>(value(extra("nir"), i, 0, 65535)));
  }
  write_las_records(out, layout, records.data(), c.size(), compressed);
}

}  // namespace splatkit
