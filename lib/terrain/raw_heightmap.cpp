#include "terrain/raw_heightmap.h"

#include <sys/stat.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "splatkit/error.h"

namespace splatkit::terrain {

namespace {

// Wide enough for width × height × sample bytes of any two 64-bit sides (a GCC and Clang
// extension, so marked as one).
__extension__ typedef unsigned __int128 Uint128;

int sample_bytes(const std::string& type) {
  if (type == "int8" || type == "uint8") return 1;
  if (type == "int16" || type == "uint16") return 2;
  if (type == "int32" || type == "uint32" || type == "float32") return 4;
  if (type == "float64") return 8;
  return 0;
}

template <class T>
float load(const unsigned char* p, bool swap) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  T v;
  std::memcpy(&v, b, sizeof(T));
  return static_cast<float>(v);
}

class RawSource final : public HeightmapSource {
 public:
  RawSource(const std::string& path, const RawLayout& layout, HeightmapInfo info)
      : path_(path), layout_(layout), bytes_(sample_bytes(layout.type)) {
    info_ = std::move(info);
    info_.width = layout.width;
    info_.height = layout.height;
    info_.sample_type = layout.type;
    file_ = path == "-" ? stdin : std::fopen(path.c_str(), "rb");
    if (file_ == nullptr) throw_bad_input(display_name(path), std::strerror(errno));
    const bool little = std::endian::native == std::endian::little;
    swap_ = layout.big_endian == little;
  }
  ~RawSource() override {
    if (file_ != nullptr && file_ != stdin) std::fclose(file_);
  }

  void read_rows(int64_t rows, float* out) override {
    const std::size_t n = std::size_t(rows) * std::size_t(layout_.width);
    buf_.resize(n * std::size_t(bytes_));
    const std::size_t got = std::fread(buf_.data(), 1, buf_.size(), file_);
    if (got != buf_.size())
      throw_bad_input(display_name(path_),
                      "ends at row " + std::to_string(row_ + int64_t(got / std::size_t(bytes_) /
                                                                     std::size_t(layout_.width))) +
                          " of " + std::to_string(layout_.height) + " (" + layout_.type + ", " +
                          std::to_string(layout_.width) + " samples a row)");
    row_ += rows;
    const unsigned char* p = buf_.data();
    const std::string& t = layout_.type;
    for (std::size_t i = 0; i < n; ++i, p += bytes_) {
      float v;
      if (t == "int16") v = load<int16_t>(p, swap_);
      else if (t == "float32") v = load<float>(p, swap_);
      else if (t == "uint16") v = load<uint16_t>(p, swap_);
      else if (t == "int8") v = load<int8_t>(p, false);
      else if (t == "uint8") v = load<uint8_t>(p, false);
      else if (t == "int32") v = load<int32_t>(p, swap_);
      else if (t == "uint32") v = load<uint32_t>(p, swap_);
      else v = load<double>(p, swap_);
      out[i] = v;
    }
  }

 private:
  std::string path_;
  RawLayout layout_;
  int bytes_;
  bool swap_ = false;
  std::FILE* file_ = nullptr;
  std::vector<unsigned char> buf_;
  int64_t row_ = 0;
};

int64_t file_length(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw_bad_input(display_name(path), std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw_bad_input(display_name(path), "is not a regular file");
  return int64_t(st.st_size);
}

// "N27E086.hgt" -> the south-west corner, or null.
nlohmann::json hgt_georef(const std::string& path, int64_t side) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  int lat = 0, lon = 0;
  char ns = 0, ew = 0;
  if (name.size() < 7 || std::sscanf(name.c_str(), "%c%2d%c%3d", &ns, &lat, &ew, &lon) != 4)
    return nullptr;
  ns = char(std::toupper(ns));
  ew = char(std::toupper(ew));
  if ((ns != 'N' && ns != 'S') || (ew != 'E' && ew != 'W') || lat > 90 || lon > 180)
    return nullptr;
  const double south = ns == 'N' ? lat : -lat, west = ew == 'E' ? lon : -lon;
  const double step = 1.0 / double(side - 1);
  // Sample centres: the first row lies on the north edge, the first column on the west edge.
  return {{"crs", "EPSG:4326"},
          {"pixel_scale", {step, step}},
          {"origin", {west, south + 1.0}},
          {"origin_is_sample_centre", true},
          {"source", "SRTM file name"}};
}

}  // namespace

RawLayout parse_raw_layout(const std::string& text) {
  RawLayout l;
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = text.find(',', start);
    parts.push_back(text.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  auto bad = [&](const std::string& why) -> RawLayout {
    throw_usage("--raw " + text + ": " + why + " (expected W,H,TYPE[,little|big])");
  };
  if (parts.size() < 3 || parts.size() > 4) return bad("wrong number of fields");
  for (int i = 0; i < 2; ++i) {
    char* end = nullptr;
    const long long v = std::strtoll(parts[std::size_t(i)].c_str(), &end, 10);
    if (end == parts[std::size_t(i)].c_str() || *end != 0 || v < 1 || v > (int64_t(1) << 31))
      return bad("width and height must be integers in [1, 2^31]");
    (i == 0 ? l.width : l.height) = v;
  }
  l.type = parts[2];
  if (sample_bytes(l.type) == 0)
    return bad("TYPE must be int8, uint8, int16, uint16, int32, uint32, float32 or float64");
  if (parts.size() == 4) {
    if (parts[3] != "little" && parts[3] != "big") return bad("ENDIAN must be little or big");
    l.big_endian = parts[3] == "big";
  }
  return l;
}

std::unique_ptr<HeightmapSource> open_raw_heightmap(const std::string& path,
                                                    const RawLayout& layout) {
  if (path != "-") {
    const auto expected = static_cast<Uint128>(layout.width) * static_cast<Uint128>(layout.height) *
                          static_cast<unsigned>(sample_bytes(layout.type));
    const int64_t length = file_length(path);
    if (static_cast<Uint128>(length) != expected)
      throw_bad_input(
          display_name(path),
          std::to_string(length) + " bytes; --raw " + std::to_string(layout.width) + "," +
              std::to_string(layout.height) + "," + layout.type + " needs " +
              (expected < (static_cast<Uint128>(1) << 63) ? std::to_string(uint64_t(expected))
                                                          : std::string("more than 2^63")));
  }
  HeightmapInfo info;
  info.format = "raw";
  return std::make_unique<RawSource>(path, layout, info);
}

std::unique_ptr<HeightmapSource> open_hgt(const std::string& path) {
  const int64_t length = file_length(path);
  const auto side = int64_t(std::llround(std::sqrt(double(length) / 2.0)));
  if (length < 8 || 2 * side * side != length)
    throw_bad_input(display_name(path), std::to_string(length) +
                                            " bytes: an SRTM .hgt file holds 2·N² bytes (N = "
                                            "1201 or 3601)");
  RawLayout layout{side, side, "int16", true};
  HeightmapInfo info;
  info.format = "hgt";
  info.has_nodata = true;
  info.nodata = -32768;
  info.georef = hgt_georef(path, side);
  return std::make_unique<RawSource>(path, layout, info);
}

}  // namespace splatkit::terrain
