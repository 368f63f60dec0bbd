#include "formats/las.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "formats/laz.h"
#include "splatkit/error.h"
#include "splatkit/position_builder.h"

namespace splatkit {

namespace {

// Explicit little-endian field access into a header or record buffer.
uint16_t u16(const unsigned char* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }
uint32_t u32(const unsigned char* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}
uint64_t u64(const unsigned char* p) {
  return static_cast<uint64_t>(u32(p)) | static_cast<uint64_t>(u32(p + 4)) << 32;
}
int32_t i32(const unsigned char* p) { return static_cast<int32_t>(u32(p)); }
double f64(const unsigned char* p) { return std::bit_cast<double>(u64(p)); }

// Public header block sizes by minor version and point record sizes by format (LAS 1.4 R15).
constexpr std::size_t kHeaderSize12 = 227, kHeaderSize13 = 235, kHeaderSize14 = 375;
constexpr uint16_t kMinRecordLength[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
constexpr std::size_t kVlrHeaderSize = 54, kEvlrHeaderSize = 60;
constexpr std::size_t kBlockPoints = 4096;

struct LasHeader {
  int major = 0, minor = 0;
  std::string system_identifier, generating_software;
  int creation_day = 0, creation_year = 0;
  uint16_t header_size = 0;
  uint32_t point_offset = 0;
  uint32_t vlr_count = 0;
  int format = 0;
  uint16_t record_length = 0;
  uint64_t count = 0;
  double scale[3] = {}, offset[3] = {};
  double min[3] = {}, max[3] = {};
  uint64_t evlr_start = 0;
  uint32_t evlr_count = 0;
  bool compressed = false;  // LAZ: bit 7 of the point format byte
};

// Fixed-width text field: up to the first NUL, trailing spaces dropped, bytes outside printable
// ASCII replaced so that the header JSON is always valid UTF-8.
std::string fixed_string(const unsigned char* p, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n && p[i] != 0; ++i)
    s += (p[i] >= 0x20 && p[i] < 0x7f) ? static_cast<char>(p[i]) : '?';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// Shortest text that reads back to v (for messages).
std::string number_text(double v) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::string("?");
}

std::size_t min_header_size(int minor) {
  return minor >= 4 ? kHeaderSize14 : minor == 3 ? kHeaderSize13 : kHeaderSize12;
}

void check_format(const InputStream& in, const LasHeader& h, unsigned raw_format) {
  if (raw_format & 0x40)
    throw_unsupported(in.path(), "LAS point format byte " + std::to_string(raw_format) +
                                     " has bit 6 set (an old LAStools compression mark); only "
                                     "LASzip's bit 7 is supported");
  const int f = h.format;
  if (f > 10) throw_bad_input(in.path(), "unknown LAS point data format " + std::to_string(f));
  if (f == 4 || f == 5 || f == 9 || f == 10)
    throw_unsupported(in.path(), "LAS point data format " + std::to_string(f) +
                                     " (with waveform packets) is not supported (0-3 and 6-8 are)");
  if (f >= 6 && h.minor < 4)
    throw_bad_input(in.path(), "LAS point data format " + std::to_string(f) +
                                   " needs LAS 1.4, the file says 1." + std::to_string(h.minor));
  if (h.record_length < kMinRecordLength[f])
    throw_bad_input(in.path(), "point record length " + std::to_string(h.record_length) +
                                   " is shorter than the " + std::to_string(kMinRecordLength[f]) +
                                   " bytes of point data format " + std::to_string(f));
}

void check_transform(const InputStream& in, const LasHeader& h) {
  static const char* axis[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(h.scale[k]) || h.scale[k] == 0)
      throw_bad_input(in.path(), std::string(axis[k]) + " scale factor is zero or not finite");
    if (!std::isfinite(h.offset[k]))
      throw_bad_input(in.path(), std::string(axis[k]) + " offset is not finite");
  }
}

LasHeader read_header(InputStream& in) {
  unsigned char b[kHeaderSize14] = {};
  in.read(b, kHeaderSize12, "LAS header");
  if (std::memcmp(b, "LASF", 4) != 0)
    throw_bad_input(in.path(), "not a LAS file (no LASF signature)");
  LasHeader h;
  h.major = b[24];
  h.minor = b[25];
  if (h.major != 1 || h.minor > 4)
    throw_unsupported(in.path(), "LAS version " + std::to_string(h.major) + "." +
                                     std::to_string(h.minor) + " is not supported (1.0-1.4 are)");
  h.system_identifier = fixed_string(b + 26, 32);
  h.generating_software = fixed_string(b + 58, 32);
  h.creation_day = u16(b + 90);
  h.creation_year = u16(b + 92);
  h.header_size = u16(b + 94);
  h.point_offset = u32(b + 96);
  h.vlr_count = u32(b + 100);
  const unsigned raw_format = b[104];
  h.format = static_cast<int>(raw_format & 0x3F);
  h.compressed = (raw_format & 0x80) != 0;
  h.record_length = u16(b + 105);
  const uint32_t legacy_count = u32(b + 107);
  for (int k = 0; k < 3; ++k) {
    h.scale[k] = f64(b + 131 + 8 * k);
    h.offset[k] = f64(b + 155 + 8 * k);
    h.max[k] = f64(b + 179 + 16 * k);
    h.min[k] = f64(b + 187 + 16 * k);
  }
  const std::size_t need = min_header_size(h.minor);
  if (h.header_size < need)
    throw_bad_input(in.path(), "header size " + std::to_string(h.header_size) +
                                   " is smaller than the " + std::to_string(need) +
                                   " bytes of a LAS 1." + std::to_string(h.minor) + " header");
  in.read(b + kHeaderSize12, need - kHeaderSize12, "LAS header");
  in.skip(h.header_size - need, "LAS header");
  h.count = legacy_count;
  if (h.minor >= 4) {
    h.evlr_start = u64(b + 235);
    h.evlr_count = u32(b + 243);
    h.count = u64(b + 247);
    if (legacy_count != 0 && legacy_count != h.count)
      throw_bad_input(in.path(), "legacy point count " + std::to_string(legacy_count) +
                                     " disagrees with the 64-bit point count " +
                                     std::to_string(h.count));
  }
  check_format(in, h, raw_format);
  check_transform(in, h);
  if (h.point_offset < h.header_size)
    throw_bad_input(in.path(), "offset to point data " + std::to_string(h.point_offset) +
                                   " lies inside the " + std::to_string(h.header_size) +
                                   "-byte header");
  if (auto size = in.size_hint()) {
    if (h.point_offset > *size)
      throw_bad_input(in.path(), "offset to point data " + std::to_string(h.point_offset) +
                                     " is past the end of the file (" + std::to_string(*size) +
                                     " bytes)");
  }
  if (auto size = in.size_hint(); size && !h.compressed) {
    if (h.point_offset > *size)
      throw_bad_input(in.path(), "offset to point data " + std::to_string(h.point_offset) +
                                     " is past the end of the file (" + std::to_string(*size) +
                                     " bytes)");
    const uint64_t left = *size - h.point_offset;
    if (h.count > left / h.record_length)
      throw_bad_input(in.path(), "header says " + std::to_string(h.count) + " points of " +
                                     std::to_string(h.record_length) + " bytes but only " +
                                     std::to_string(left) + " bytes follow the point data offset");
  }
  return h;
}

// VLRs sit between the header and the point data; each must end before the point data starts.
// The LASzip VLR's payload is kept in `laszip` (LAZ files).
void read_vlrs(InputStream& in, const LasHeader& h, nlohmann::json& names,
               std::vector<unsigned char>& laszip, bool& has_laszip) {
  for (uint32_t k = 0; k < h.vlr_count; ++k) {
    unsigned char v[kVlrHeaderSize];
    if (in.offset() + kVlrHeaderSize > h.point_offset)
      throw_bad_input(in.path(), "VLR " + std::to_string(k) + " of " + std::to_string(h.vlr_count) +
                                     " extends past the offset to point data");
    in.read(v, kVlrHeaderSize, "VLR header");
    const uint16_t length = u16(v + 20);
    if (in.offset() + length > h.point_offset)
      throw_bad_input(in.path(), "VLR " + std::to_string(k) + " of " + std::to_string(h.vlr_count) +
                                     " extends past the offset to point data");
    const std::string user = fixed_string(v + 2, 16);
    if (user == "laszip encoded" && u16(v + 18) == 22204 && !has_laszip) {
      laszip.resize(length);
      in.read(laszip.data(), length, "LASzip VLR");
      has_laszip = true;
    } else {
      in.skip(length, "VLR");
    }
    if (names.size() < 64)
      names.push_back(fixed_string(v + 2, 16) + "/" + std::to_string(u16(v + 18)));
  }
  in.skip(h.point_offset - in.offset(), "padding before the point data");
}

enum Extra { kIntensity, kReturn, kReturns, kClass, kAngle, kUser, kSource, kGps, kNir, kExtras };

void add_extras(SplatCloud& c, int format, std::size_t reserve, int slot[kExtras]) {
  const bool v14 = format >= 6;
  struct Spec {
    Extra e;
    const char* name;
    ScalarType type;
    bool present;
  };
  const Spec specs[] = {
      {kIntensity, "intensity", ScalarType::kUInt16, true},
      {kReturn, "return_number", ScalarType::kUInt8, true},
      {kReturns, "number_of_returns", ScalarType::kUInt8, true},
      {kClass, "classification", ScalarType::kUInt8, true},
      {kAngle, "scan_angle", v14 ? ScalarType::kFloat32 : ScalarType::kInt8, true},
      {kUser, "user_data", ScalarType::kUInt8, true},
      {kSource, "point_source_id", ScalarType::kUInt16, true},
      {kGps, "gps_time", ScalarType::kFloat64, format == 1 || format == 3 || v14},
      {kNir, "nir", ScalarType::kUInt16, format == 8},
  };
  for (const Spec& s : specs) {
    slot[s.e] = -1;
    if (!s.present) continue;
    slot[s.e] = static_cast<int>(c.extras.size());
    c.extras.push_back({s.name, s.type});
    c.extras.back().values.reserve(reserve);
  }
}

class PointDecoder {
 public:
  PointDecoder(InputStream& in, const LasHeader& h, SplatCloud& c)
      : in_(in), h_(h), c_(c), positions_(c, in.path()) {
    const std::size_t reserve =
        static_cast<std::size_t>(std::min<uint64_t>(h.count, std::size_t{1} << 22));
    c.positions.reserve(reserve);
    if (has_rgb()) {
      c.colors.reserve(reserve);
      c.color_bits = 16;
    }
    add_extras(c, h.format, reserve, slot_);
  }

  // Decodes n consecutive records (record_length bytes each), the first being point `first`.
  // Each attribute column grows by n first and takes the values in its own type.
  void add_records(const unsigned char* records, std::size_t n, uint64_t first) {
    const Columns col = grow(n);
    for (std::size_t i = 0; i < n; ++i) decode(records + i * h_.record_length, first + i, col, i);
  }
  void finish() { positions_.finish(); }

 private:
  // Where this batch's values go in each attribute column (null when the format has none).
  struct Columns {
    uint16_t *intensity, *source, *nir;
    uint8_t *ret, *rets, *cls, *user;
    int8_t* angle8;  // formats 0-5: whole degrees
    float* angle;    // formats 6-8: 0.006-degree steps, kept in degrees
    double* gps;
  };
  template <class T>
  T* column(Extra e, std::size_t n) {
    if (slot_[e] < 0) return nullptr;
    ExtraValues& v = c_.extras[static_cast<std::size_t>(slot_[e])].values;
    const std::size_t at = v.size();
    v.resize(at + n);
    return v.as<T>().data() + at;
  }
  Columns grow(std::size_t n) {
    const bool v14 = h_.format >= 6;
    return {column<uint16_t>(kIntensity, n),
            column<uint16_t>(kSource, n),
            column<uint16_t>(kNir, n),
            column<uint8_t>(kReturn, n),
            column<uint8_t>(kReturns, n),
            column<uint8_t>(kClass, n),
            column<uint8_t>(kUser, n),
            v14 ? nullptr : column<int8_t>(kAngle, n),
            v14 ? column<float>(kAngle, n) : nullptr,
            column<double>(kGps, n)};
  }

  bool has_rgb() const {
    return h_.format == 2 || h_.format == 3 || h_.format == 7 || h_.format == 8;
  }

  void decode(const unsigned char* r, uint64_t index, const Columns& col, std::size_t i) {
    std::array<double, 3> p;
    for (int k = 0; k < 3; ++k) {
      const int32_t raw = i32(r + 4 * k);
      p[k] = raw * h_.scale[k] + h_.offset[k];
      // Positions are stored as float32: a scaled value beyond its range is an error.
      if (!fits_float(p[k]))
        throw_bad_input(in_.path(),
                        "point record " + std::to_string(index) +
                            ": coordinate overflows after scale and offset: " + "xyz"[k] + " = " +
                            std::to_string(raw) + " * " + number_text(h_.scale[k]) + " + " +
                            number_text(h_.offset[k]) + " is beyond float range");
    }
    positions_.add(p);
    col.intensity[i] = u16(r + 12);
    const int f = h_.format;
    if (f < 6) {
      col.ret[i] = r[14] & 7;
      col.rets[i] = (r[14] >> 3) & 7;
      col.cls[i] = r[15] & 31;
      col.angle8[i] = static_cast<int8_t>(r[16]);
      col.user[i] = r[17];
      col.source[i] = u16(r + 18);
      if (f == 1 || f == 3) col.gps[i] = f64(r + 20);
      if (f == 2) c_.colors.push_back({u16(r + 20), u16(r + 22), u16(r + 24)});
      if (f == 3) c_.colors.push_back({u16(r + 28), u16(r + 30), u16(r + 32)});
      return;
    }
    col.ret[i] = r[14] & 15;
    col.rets[i] = r[14] >> 4;
    col.cls[i] = r[16];
    col.user[i] = r[17];
    col.angle[i] = static_cast<float>(static_cast<int16_t>(u16(r + 18)) * 0.006);
    col.source[i] = u16(r + 20);
    col.gps[i] = f64(r + 22);
    if (f >= 7) c_.colors.push_back({u16(r + 30), u16(r + 32), u16(r + 34)});
    if (f == 8) col.nir[i] = u16(r + 36);
  }

  InputStream& in_;
  const LasHeader& h_;
  SplatCloud& c_;
  PositionBuilder positions_;
  int slot_[kExtras];
};

// After the points: LAS 1.4 extended VLRs (each header checked), otherwise nothing.
void read_tail(InputStream& in, const LasHeader& h) {
  if (h.evlr_count > 0) {
    if (h.evlr_start < in.offset())
      throw_bad_input(in.path(), "first EVLR at byte " + std::to_string(h.evlr_start) +
                                     " overlaps the point records (which end at byte " +
                                     std::to_string(in.offset()) + ")");
    in.skip(h.evlr_start - in.offset(), "data before the first EVLR");
    for (uint32_t k = 0; k < h.evlr_count; ++k) {
      unsigned char v[kEvlrHeaderSize];
      in.read(v, kEvlrHeaderSize, "EVLR header");
      const uint64_t length = u64(v + 20);
      if (auto left = in.remaining(); left && length > *left)
        throw_bad_input(in.path(), "EVLR " + std::to_string(k) + " of " +
                                       std::to_string(h.evlr_count) + " claims " +
                                       std::to_string(length) + " bytes, past the end of the file");
      in.skip(length, "EVLR");
    }
  }
  if (!in.at_eof()) {
    const auto left = in.remaining();
    in.fail((left ? std::to_string(*left) + " bytes of " : std::string()) +
            "trailing data after the last " + (h.evlr_count ? "EVLR" : "point record"));
  }
}

nlohmann::json header_json(const LasHeader& h, nlohmann::json vlr_names) {
  auto triple = [](const double* v) { return nlohmann::json::array({v[0], v[1], v[2]}); };
  return {
      {"version", std::to_string(h.major) + "." + std::to_string(h.minor)},
      {"point_format", h.format},
      {"record_length", h.record_length},
      {"count", h.count},
      {"scale", triple(h.scale)},
      {"offset", triple(h.offset)},
      {"bounds", {{"min", triple(h.min)}, {"max", triple(h.max)}}},
      {"system_identifier", h.system_identifier},
      {"generating_software", h.generating_software},
      {"creation_date", {{"year", h.creation_year}, {"day_of_year", h.creation_day}}},
      {"vlr_count", h.vlr_count},
      {"vlrs", std::move(vlr_names)},
      {"evlr_count", h.evlr_count},
  };
}

}  // namespace

namespace {

// Reads the header and VLRs, then passes every point record (decompressed for LAZ) to `sink` in
// file order; `on_header` runs first.
void read_records(InputStream& in, const std::function<void(const LasHeader&)>& on_header,
                  const std::function<void(const unsigned char*, std::size_t)>& sink,
                  nlohmann::json& vlr_names, LasHeader& h) {
  h = read_header(in);
  std::vector<unsigned char> laszip;
  bool has_laszip = false;
  read_vlrs(in, h, vlr_names, laszip, has_laszip);
  LazPointsInfo info;
  if (h.compressed) {
    info.format = h.format;
    info.record_length = h.record_length;
    info.count = h.count;
    info.point_offset = h.point_offset;
    info.laszip_vlr = laszip;
    info.has_laszip_vlr = has_laszip;
    info.evlr_start = h.evlr_start;
    info.evlr_count = h.evlr_count;
    check_laz_vlr(in.path(), info);
  }
  on_header(h);
  if (h.compressed) {
    read_laz_points(in, info, sink);
    return;
  }
  std::vector<unsigned char> block;
  for (uint64_t done = 0; done < h.count;) {
    const std::size_t n =
        static_cast<std::size_t>(std::min<uint64_t>(kBlockPoints, h.count - done));
    block.resize(n * h.record_length);
    const std::size_t got = in.read_some(block.data(), block.size());
    if (got != block.size())
      in.fail("unexpected end of file in point record " +
              std::to_string(done + got / h.record_length) + " of " + std::to_string(h.count));
    sink(block.data(), n);
    done += n;
  }
  read_tail(in, h);
}

}  // namespace

LoadedCloud read_las(InputStream& in, const ReadOptions& options) {
  (void)options;
  LoadedCloud doc;
  LasHeader h;
  nlohmann::json vlr_names = nlohmann::json::array();
  std::unique_ptr<PointDecoder> decoder;
  uint64_t done = 0;
  read_records(
      in,
      [&](const LasHeader& header) {
        decoder = std::make_unique<PointDecoder>(in, header, doc.cloud);
      },
      [&](const unsigned char* records, std::size_t n) {
        decoder->add_records(records, n, done);
        done += n;
      },
      vlr_names, h);
  decoder->finish();
  doc.header = header_json(h, std::move(vlr_names));
  if (h.compressed) doc.header["compressed"] = "laszip";
  return doc;
}

LasRecordsInfo read_las_records(InputStream& in,
                                const std::function<void(const unsigned char*, std::size_t)>& sink,
                                const std::function<void(const LasRecordsInfo&)>& on_info) {
  LasHeader h;
  nlohmann::json vlr_names = nlohmann::json::array();
  auto info = [](const LasHeader& x) {
    return LasRecordsInfo{x.format, x.record_length, x.count, x.compressed};
  };
  read_records(
      in,
      [&](const LasHeader& x) {
        if (on_info) on_info(info(x));
      },
      sink, vlr_names, h);
  return info(h);
}

}  // namespace splatkit
