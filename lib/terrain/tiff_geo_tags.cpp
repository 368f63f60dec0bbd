#include "terrain/tiff_geo_tags.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <vector>

#include "splatkit/error.h"

namespace splatkit::terrain {

namespace {

constexpr uint16_t kNoData = 42113, kPixelScale = 33550, kTiepoint = 33922,
                   kTransformation = 34264, kGeoKeys = 34735;
constexpr uint64_t kMaxValues = 1 << 16;  // far above any real GeoTIFF tag

class Parser {
 public:
  Parser(const ReadAt& read, const std::string& name) : read_(read), name_(name) {}

  TiffGeoTags parse() {
    unsigned char head[16];
    if (!read_(0, 8, head)) fail("shorter than a TIFF header");
    if (head[0] == 'I' && head[1] == 'I') little_ = true;
    else if (head[0] == 'M' && head[1] == 'M') little_ = false;
    else fail("not a TIFF file (no II/MM byte order mark)");
    const uint16_t magic = u16(head + 2);
    uint64_t ifd = 0;
    if (magic == 42) {
      ifd = u32(head + 4);
    } else if (magic == 43) {
      big_ = true;
      if (!read_(0, 16, head)) fail("shorter than a BigTIFF header");
      if (u16(head + 4) != 8) fail("BigTIFF offset size is not 8");
      ifd = u64(head + 8);
    } else {
      fail("bad TIFF magic number " + std::to_string(magic));
    }
    unsigned char cnt[8];
    if (!read_(ifd, big_ ? 8 : 2, cnt)) fail("first directory offset " + std::to_string(ifd) + " is past the end");
    const uint64_t entries = big_ ? u64(cnt) : u16(cnt);
    if (entries > 65535) fail("first directory has " + std::to_string(entries) + " entries");
    const std::size_t entry_size = big_ ? 20 : 12;
    std::vector<unsigned char> dir(std::size_t(entries) * entry_size);
    if (!dir.empty() && !read_(ifd + (big_ ? 8 : 2), dir.size(), dir.data()))
      fail("first directory (" + std::to_string(entries) + " entries) runs past the end");
    TiffGeoTags out;
    nlohmann::json geo = nlohmann::json::object();
    for (uint64_t i = 0; i < entries; ++i) {
      const unsigned char* e = dir.data() + i * entry_size;
      const uint16_t tag = u16(e), type = u16(e + 2);
      const bool layout_tag = tag == 256 || tag == 257 || tag == 258 || tag == 259 ||
                              tag == 273 || tag == 277 || tag == 278 || tag == 279 ||
                              tag == 284 || tag == 322 || tag == 323 || tag == 324 ||
                              tag == 325 || tag == 339;
      if (tag != kNoData && tag != kPixelScale && tag != kTiepoint && tag != kTransformation &&
          tag != kGeoKeys && !layout_tag)
        continue;
      const uint64_t count = big_ ? u64(e + 4) : u32(e + 4);
      if (layout_tag) {
        read_layout(tag, type, count, e + (big_ ? 12 : 8), out.layout);
        continue;
      }
      const unsigned char* inline_value = e + (big_ ? 12 : 8);
      const std::size_t slot = big_ ? 8 : 4;
      const std::string where = "tag " + std::to_string(tag);
      if (count > kMaxValues) fail(where + " has " + std::to_string(count) + " values");
      const std::size_t size = type_size(type);
      if (size == 0) fail(where + " has unknown type " + std::to_string(type));
      std::vector<unsigned char> v(std::size_t(count) * size);
      if (v.size() <= slot) {
        if (!v.empty()) std::memcpy(v.data(), inline_value, v.size());
      } else {
        const uint64_t off = big_ ? u64(inline_value) : u32(inline_value);
        if (!read_(off, v.size(), v.data())) fail(where + " values run past the end");
      }
      if (tag == kNoData) {
        if (type != 2) fail(where + " (GDAL_NODATA) is not ASCII");
        std::string s(v.begin(), v.end());
        s = s.substr(0, s.find('\0'));
        char* end = nullptr;
        const double d = std::strtod(s.c_str(), &end);
        if (end == s.c_str()) fail("GDAL_NODATA '" + s + "' is not a number");
        if (!std::isnan(d)) out.nodata = d;  // NaN voids are found anyway
        continue;
      }
      nlohmann::json values = nlohmann::json::array();
      for (uint64_t k = 0; k < count; ++k) {
        const unsigned char* p = v.data() + k * size;
        if (type == 12) values.push_back(f64(p));
        else if (type == 3) values.push_back(u16(p));
        else if (type == 4) values.push_back(u32(p));
        else if (type == 16) values.push_back(u64(p));
        else fail(where + " has type " + std::to_string(type) + " (numbers expected)");
      }
      if (tag == kPixelScale) geo["pixel_scale"] = values;
      else if (tag == kTiepoint) geo["tiepoint"] = values;
      else if (tag == kTransformation) geo["transformation"] = values;
      else {
        geo["geokeys"] = values;
        // Key entries of four shorts after a header of four: 2048 GeographicType, 3072
        // ProjectedCSType (EPSG codes), 1025 RasterType (1 area, 2 point).
        for (std::size_t k = 4; k + 3 < values.size(); k += 4) {
          // Entries are SHORTs; a directory of other numbers (a hostile file) names no CRS.
          if (!values[k].is_number_unsigned() || !values[k + 1].is_number_unsigned() ||
              !values[k + 3].is_number_unsigned())
            continue;
          const auto key = values[k].get<uint64_t>(), loc = values[k + 1].get<uint64_t>();
          const auto val = values[k + 3].get<uint64_t>();
          if (loc != 0) continue;
          if ((key == 2048 || key == 3072) && val != 32767) geo["crs"] = "EPSG:" + std::to_string(val);
          if (key == 1025) geo["raster_type"] = val == 2 ? "point" : "area";
        }
      }
    }
    if (!geo.empty()) out.georef = std::move(geo);
    out.layout.little_endian = little_;
    return out;
  }

 private:
  // A layout tag's values (SHORT, LONG or LONG8): one value, or the strips' or tiles' offsets
  // and byte counts (at most 2^24 of them; the bytes must be in the file).
  void read_layout(uint16_t tag, uint16_t type, uint64_t count, const unsigned char* inline_value,
                   TiffLayout& l) {
    const std::string where = "tag " + std::to_string(tag);
    const std::size_t size = type == 3 ? 2 : type == 4 ? 4 : type == 16 ? 8 : 0;
    if (size == 0) fail(where + " has type " + std::to_string(type) + " (an integer expected)");
    if (count > (uint64_t(1) << 24)) fail(where + " has " + std::to_string(count) + " values");
    const bool many = tag == 273 || tag == 279 || tag == 324 || tag == 325;
    if (!many && count != 1 && tag != 258 && tag != 339) fail(where + " has " + std::to_string(count) + " values");
    if (count == 0) fail(where + " has no value");
    std::vector<unsigned char> v(std::size_t(count) * size);
    if (v.size() <= std::size_t(big_ ? 8 : 4)) {
      std::memcpy(v.data(), inline_value, v.size());
    } else {
      const uint64_t off = big_ ? u64(inline_value) : u32(inline_value);
      if (!read_(off, v.size(), v.data())) fail(where + " values run past the end");
    }
    std::vector<uint64_t> values(static_cast<std::size_t>(count));
    for (std::size_t k = 0; k < values.size(); ++k)
      values[k] = size == 2 ? u16(v.data() + 2 * k) : size == 4 ? u32(v.data() + 4 * k) : u64(v.data() + 8 * k);
    switch (tag) {
      case 256: l.width = values[0]; break;
      case 257: l.height = values[0]; break;
      case 258: l.bits = values[0]; break;  // one per sample; the first is the one read
      case 259: l.compression = values[0]; break;
      case 277: l.samples = values[0]; break;
      case 278: l.rows_per_strip = values[0]; break;
      case 284: l.planar = values[0]; break;
      case 322: l.tile_width = values[0]; break;
      case 323: l.tile_height = values[0]; break;
      case 339: l.sample_format = values[0]; break;
      case 273: case 324: l.offsets = std::move(values); break;
      default: l.byte_counts = std::move(values); break;
    }
  }

  static std::size_t type_size(uint16_t type) {
    switch (type) {
      case 1: case 2: case 6: case 7: return 1;
      case 3: case 8: return 2;
      case 4: case 9: case 11: case 13: return 4;
      case 5: case 10: case 12: case 16: case 17: case 18: return 8;
      default: return 0;
    }
  }
  uint64_t get(const unsigned char* p, int n) const {
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= uint64_t(p[little_ ? i : n - 1 - i]) << (8 * i);
    return v;
  }
  uint16_t u16(const unsigned char* p) const { return uint16_t(get(p, 2)); }
  uint32_t u32(const unsigned char* p) const { return uint32_t(get(p, 4)); }
  uint64_t u64(const unsigned char* p) const { return get(p, 8); }
  double f64(const unsigned char* p) const {
    const uint64_t b = get(p, 8);
    double d;
    std::memcpy(&d, &b, 8);
    return std::isfinite(d) ? d : 0.0;  // JSON has no NaN
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw_bad_input(display_name(name_), "TIFF: " + what);
  }

  const ReadAt& read_;
  std::string name_;
  bool little_ = true, big_ = false;
};

}  // namespace

TiffGeoTags read_tiff_geo_tags(const ReadAt& read, const std::string& name) {
  return Parser(read, name).parse();
}

TiffGeoTags read_tiff_geo_tags_file(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw_bad_input(display_name(path), std::strerror(errno));
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  const ReadAt read = [fd](uint64_t offset, std::size_t n, void* out) {
    if (offset > uint64_t(INT64_MAX) - n) return false;
    std::size_t done = 0;
    while (done < n) {
      const ssize_t r = ::pread(fd, static_cast<char*>(out) + done, n - done, off_t(offset + done));
      if (r <= 0) return false;
      done += std::size_t(r);
    }
    return true;
  };
  return read_tiff_geo_tags(read, path);
}

TiffGeoTags read_tiff_geo_tags_memory(const uint8_t* data, std::size_t size,
                                      const std::string& name) {
  const ReadAt read = [data, size](uint64_t offset, std::size_t n, void* out) {
    if (offset > size || n > size - offset) return false;
    if (n > 0) std::memcpy(out, data + offset, n);
    return true;
  };
  return read_tiff_geo_tags(read, name);
}

}  // namespace splatkit::terrain
