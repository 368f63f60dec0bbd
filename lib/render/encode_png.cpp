#include "render/encode_png.h"

#include <zlib.h>

#include <cstring>
#include <stdexcept>
#include <string>

namespace splatkit::render {

namespace {

constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr uint8_t kFilterUp = 2;

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  const uint8_t b[4] = {uint8_t(v >> 24), uint8_t(v >> 16), uint8_t(v >> 8), uint8_t(v)};
  out.insert(out.end(), b, b + 4);
}

// Appends the chunk header of `type`; returns where its data starts (for end_chunk).
std::size_t begin_chunk(std::vector<uint8_t>& out, const char* type) {
  put_u32(out, 0);  // length, set by end_chunk
  out.insert(out.end(), type, type + 4);
  return out.size();
}

// Sets the length of the chunk whose data started at `data` and appends its CRC (over type and
// data).
void end_chunk(std::vector<uint8_t>& out, std::size_t data) {
  const uint32_t length = static_cast<uint32_t>(out.size() - data);
  for (int i = 0; i < 4; ++i) out[data - 8 + i] = uint8_t(length >> (24 - 8 * i));
  uLong crc = crc32(0, out.data() + data - 4, static_cast<uInt>(length + 4));
  put_u32(out, static_cast<uint32_t>(crc));
}

void chunk(std::vector<uint8_t>& out, const char* type, std::initializer_list<uint32_t> words) {
  const std::size_t data = begin_chunk(out, type);
  for (uint32_t w : words) put_u32(out, w);
  end_chunk(out, data);
}

// Deflates the filtered rows into `out`, row by row (the filtered image is never held whole),
// through a small staging buffer (`out` grows by what deflate produces, not by its bound).
void deflate_rows(const uint8_t* rgb, int width, int height, std::vector<uint8_t>& out) {
  z_stream z{};
  if (deflateInit2(&z, 1, Z_DEFLATED, 15, 8, Z_RLE) != Z_OK)
    throw std::runtime_error("encode_png: zlib: deflateInit2 failed");
  const std::size_t row_bytes = std::size_t(width) * 3;
  std::vector<uint8_t> row(row_bytes + 1), stage(std::size_t{1} << 16);
  row[0] = kFilterUp;
  int status = Z_OK;
  for (int y = 0; y < height && status != Z_STREAM_ERROR; ++y) {
    const uint8_t* cur = rgb + row_bytes * y;
    if (y == 0) {
      std::memcpy(row.data() + 1, cur, row_bytes);
    } else {
      const uint8_t* up = cur - row_bytes;
      for (std::size_t i = 0; i < row_bytes; ++i) row[i + 1] = uint8_t(cur[i] - up[i]);
    }
    z.next_in = row.data();
    z.avail_in = static_cast<uInt>(row.size());
    const int flush = y + 1 < height ? Z_NO_FLUSH : Z_FINISH;
    // As zlib's own example: until a call leaves room in the staging buffer, deflate has taken
    // the whole row (and, with Z_FINISH, ended the stream). Z_BUF_ERROR there only means that
    // a call had nothing to do.
    do {
      z.next_out = stage.data();
      z.avail_out = static_cast<uInt>(stage.size());
      status = deflate(&z, flush);
      out.insert(out.end(), stage.data(), z.next_out);
    } while (status != Z_STREAM_ERROR && z.avail_out == 0);
  }
  deflateEnd(&z);
  if (status != Z_STREAM_END) throw std::runtime_error("encode_png: zlib: deflate failed");
}

}  // namespace

std::vector<uint8_t> encode_png(const uint8_t* rgb, int width, int height) {
  if (width < 1 || height < 1) throw std::invalid_argument("encode_png: empty image");
  // deflateBound takes uLong and the filtered rows must fit in one IDAT (2^31 − 1 bytes).
  if ((std::size_t(width) * 3 + 1) * std::size_t(height) > (std::size_t{1} << 30))
    throw std::invalid_argument("encode_png: image too large for one IDAT chunk");
  std::vector<uint8_t> out(kSignature, kSignature + sizeof kSignature);
  std::size_t data = begin_chunk(out, "IHDR");
  put_u32(out, static_cast<uint32_t>(width));
  put_u32(out, static_cast<uint32_t>(height));
  const uint8_t format[5] = {8, 2, 0, 0,
                             0};  // bit depth, RGB, deflate, adaptive filters, progressive
  out.insert(out.end(), format, format + 5);
  end_chunk(out, data);
  data = begin_chunk(out, "sRGB");
  out.push_back(0);  // perceptual rendering intent
  end_chunk(out, data);
  chunk(out, "gAMA", {45455});  // the values the PNG standard gives for sRGB, times 100000
  chunk(out, "cHRM", {31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000});
  data = begin_chunk(out, "IDAT");
  deflate_rows(rgb, width, height, out);
  end_chunk(out, data);
  chunk(out, "IEND", {});
  return out;
}

}  // namespace splatkit::render
