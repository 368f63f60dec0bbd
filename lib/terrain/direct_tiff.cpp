#include "terrain/direct_tiff.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <vector>

#include "splatkit/error.h"

namespace splatkit::terrain {

namespace {

class DirectTiff final : public HeightmapSource {
 public:
  DirectTiff(std::string path, int fd, TiffLayout layout, uint64_t bytes, HeightmapInfo info)
      : path_(std::move(path)), fd_(fd), l_(std::move(layout)), bytes_(bytes) {
    info_ = std::move(info);
    swap_ = l_.little_endian != (std::endian::native == std::endian::little);
  }
  ~DirectTiff() override { ::close(fd_); }

  void read_rows(int64_t rows, float* out) override {
    const uint64_t w = l_.width, row_bytes = w * bytes_;
    buf_.resize(std::size_t(row_bytes * uint64_t(rows)));
    if (l_.tile_width == 0) {
      for (int64_t r = 0; r < rows;) {  // rows of one strip at a time
        const uint64_t y = uint64_t(next_ + r), strip = y / l_.rows_per_strip;
        const uint64_t in_strip = y % l_.rows_per_strip;
        const uint64_t n = std::min<uint64_t>(l_.rows_per_strip - in_strip, uint64_t(rows - r));
        read_at(l_.offsets[strip] + in_strip * row_bytes, n * row_bytes,
                buf_.data() + uint64_t(r) * row_bytes);
        r += int64_t(n);
      }
    } else {
      const uint64_t tw = l_.tile_width, th = l_.tile_height, across = (w + tw - 1) / tw;
      tile_buf_.resize(std::size_t(tw * bytes_ * th));
      for (int64_t r = 0; r < rows;) {  // rows of one row of tiles at a time
        const uint64_t y = uint64_t(next_ + r), ty = y / th, in_tile = y % th;
        const uint64_t n = std::min<uint64_t>(th - in_tile, uint64_t(rows - r));
        for (uint64_t tx = 0; tx < across; ++tx) {
          const uint64_t tile_row_bytes = tw * bytes_;
          read_at(l_.offsets[ty * across + tx] + in_tile * tile_row_bytes, n * tile_row_bytes,
                  tile_buf_.data());
          const uint64_t x0 = tx * tw, cols = std::min(tw, w - x0);
          for (uint64_t k = 0; k < n; ++k)
            std::memcpy(buf_.data() + (uint64_t(r) + k) * row_bytes + x0 * bytes_,
                        tile_buf_.data() + k * tile_row_bytes, cols * bytes_);
        }
        r += int64_t(n);
      }
    }
    next_ += rows;
    convert(std::size_t(w) * std::size_t(rows), out);
  }

 private:
  void read_at(uint64_t offset, uint64_t n, unsigned char* dst) {
    uint64_t done = 0;
    while (done < n) {
      const ssize_t got = ::pread(fd_, dst + done, n - done, off_t(offset + done));
      if (got <= 0)
        throw_bad_input(display_name(path_), "cannot read " + std::to_string(n) + " bytes at " +
                                                 std::to_string(offset) + ": " +
                                                 (got == 0 ? "end of file" : std::strerror(errno)));
      done += uint64_t(got);
    }
  }
  template <class T>
  void convert_as(std::size_t n, float* out) {
    const unsigned char* p = buf_.data();
    for (std::size_t i = 0; i < n; ++i, p += sizeof(T)) {
      unsigned char b[sizeof(T)];
      std::memcpy(b, p, sizeof(T));
      if (swap_)
        for (std::size_t k = 0; k < sizeof(T) / 2; ++k) std::swap(b[k], b[sizeof(T) - 1 - k]);
      T v;
      std::memcpy(&v, b, sizeof(T));
      out[i] = static_cast<float>(v);
    }
  }
  void convert(std::size_t n, float* out) {
    const uint64_t f = l_.sample_format, bits = l_.bits;
    if (f == 3 && bits == 32 && !swap_) std::memcpy(out, buf_.data(), n * 4);
    else if (f == 3 && bits == 32) convert_as<float>(n, out);
    else if (f == 3) convert_as<double>(n, out);
    else if (f == 2 && bits == 8) convert_as<int8_t>(n, out);
    else if (f == 2 && bits == 16) convert_as<int16_t>(n, out);
    else if (f == 2 && bits == 32) convert_as<int32_t>(n, out);
    else if (f == 2) convert_as<int64_t>(n, out);
    else if (bits == 8) convert_as<uint8_t>(n, out);
    else if (bits == 16) convert_as<uint16_t>(n, out);
    else if (bits == 32) convert_as<uint32_t>(n, out);
    else convert_as<uint64_t>(n, out);
  }

  std::string path_;
  int fd_;
  TiffLayout l_;
  uint64_t bytes_;
  bool swap_ = false;
  int64_t next_ = 0;
  std::vector<unsigned char> buf_, tile_buf_;
};

const char* type_name(uint64_t format, uint64_t bits) {
  static const char* const names[3][4] = {{"uint8", "uint16", "uint32", "uint64"},
                                          {"int8", "int16", "int32", "int64"},
                                          {"", "", "float32", "float64"}};
  const int b = bits == 8 ? 0 : bits == 16 ? 1 : bits == 32 ? 2 : 3;
  return names[format - 1][b];
}

}  // namespace

std::unique_ptr<HeightmapSource> open_direct_tiff(const std::string& path, const TiffGeoTags& t) {
  TiffLayout l = t.layout;
  const bool bits_ok = l.bits == 8 || l.bits == 16 || l.bits == 32 || l.bits == 64;
  const bool format_ok = l.sample_format == 1 || l.sample_format == 2 ||
                         (l.sample_format == 3 && (l.bits == 32 || l.bits == 64));
  if (l.compression != 1 || l.samples != 1 || !bits_ok || !format_ok || l.width == 0 ||
      l.height == 0 || l.width > (uint64_t(1) << 31) || l.height > (uint64_t(1) << 31))
    return nullptr;
  const uint64_t bytes = l.bits / 8;
  auto bad = [&](const std::string& what) -> std::unique_ptr<HeightmapSource> {
    throw_bad_input(display_name(path), "TIFF: " + what);
  };
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw_bad_input(display_name(path), std::strerror(errno));
  struct stat st {};
  ::fstat(fd, &st);
  const auto file = uint64_t(st.st_size);
  struct Guard {
    int fd;
    bool keep = false;
    ~Guard() {
      if (!keep) ::close(fd);
    }
  } guard{fd};
  // Every strip (rows_per_strip rows) or tile must lie inside the file.
  uint64_t chunks = 0, chunk_bytes = 0;
  if (l.tile_width > 0 || l.tile_height > 0) {
    if (l.tile_width == 0 || l.tile_height == 0 || l.tile_width > (1u << 20) ||
        l.tile_height > (1u << 20))
      return bad("bad tile size " + std::to_string(l.tile_width) + " x " + std::to_string(l.tile_height));
    chunks = ((l.width + l.tile_width - 1) / l.tile_width) * ((l.height + l.tile_height - 1) / l.tile_height);
    chunk_bytes = l.tile_width * l.tile_height * bytes;
  } else {
    const uint64_t rps = l.rows_per_strip == 0 || l.rows_per_strip > l.height ? l.height : l.rows_per_strip;
    l.rows_per_strip = rps;
    chunks = (l.height + rps - 1) / rps;
    chunk_bytes = rps * l.width * bytes;
  }
  if (l.offsets.size() < chunks)
    return bad(std::to_string(l.offsets.size()) + " strip or tile offsets for " +
               std::to_string(chunks) + " strips or tiles");
  for (uint64_t i = 0; i < chunks; ++i) {
    // The last strip may be short: only its rows must be there.
    uint64_t need = chunk_bytes;
    if (l.tile_width == 0 && i + 1 == chunks)
      need = (l.height - i * l.rows_per_strip) * l.width * bytes;
    if (l.offsets[i] > file || need > file - l.offsets[i])
      return bad("strip or tile " + std::to_string(i) + " (" + std::to_string(need) +
                 " bytes at " + std::to_string(l.offsets[i]) + ") runs past the end of the file (" +
                 std::to_string(file) + " bytes)");
  }
  HeightmapInfo info;
  info.width = int64_t(l.width);
  info.height = int64_t(l.height);
  info.format = "tiff";
  info.sample_type = type_name(l.sample_format, l.bits);
  info.has_nodata = t.nodata.has_value();
  info.nodata = t.nodata.value_or(0.0);
  info.georef = t.georef;
  info.band_rows = 64;
  auto source = std::make_unique<DirectTiff>(path, fd, std::move(l), bytes, std::move(info));
  guard.keep = true;
  return source;
}

}  // namespace splatkit::terrain
