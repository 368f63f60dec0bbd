// encode_png: the chunk sequence with valid CRCs, an IHDR for 8-bit RGB of the right size, an
// IDAT whose zlib stream inflates to Up-filtered rows that give the pixels back, the same bytes
// for the same pixels, and files OpenImageIO (libpng) decodes to the same pixels.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "render/encode_png.h"

namespace splatkit::render {
namespace {

struct Chunk {
  std::string type;
  std::vector<uint8_t> data;
};

uint32_t be32(const uint8_t* p) {
  return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3];
}

// The chunks after the signature; fails the test on a bad signature, size or CRC.
std::vector<Chunk> chunks(const std::vector<uint8_t>& png) {
  const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  EXPECT_TRUE(png.size() >= 8 && std::equal(signature, signature + 8, png.begin()));
  std::vector<Chunk> out;
  std::size_t at = 8;
  while (at + 12 <= png.size()) {
    const uint32_t length = be32(&png[at]);
    if (at + 12 + length > png.size()) break;
    const uint8_t* type = &png[at + 4];
    EXPECT_EQ(crc32(0, type, length + 4), be32(type + 4 + length)) << std::string(type, type + 4);
    out.push_back({std::string(type, type + 4), {type + 4, type + 4 + length}});
    at += 12 + length;
  }
  EXPECT_EQ(at, png.size()) << "bytes after the last whole chunk";
  return out;
}

std::vector<uint8_t> test_image(int w, int h) {
  std::vector<uint8_t> rgb(std::size_t(w) * h * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i)  // a flat band, a gradient, then noise
    rgb[i] = i < rgb.size() / 3       ? 40
             : i < 2 * rgb.size() / 3 ? uint8_t(i / 7)
                                      : uint8_t((i * 2654435761u) >> 24);
  return rgb;
}

TEST(RenderEncodePng, ChunksRowsAndPixels) {
  const int w = 37, h = 23;
  const std::vector<uint8_t> rgb = test_image(w, h);
  const std::vector<uint8_t> png = encode_png(rgb.data(), w, h);
  const std::vector<Chunk> c = chunks(png);
  ASSERT_EQ(c.size(), 6u);
  const char* order[] = {"IHDR", "sRGB", "gAMA", "cHRM", "IDAT", "IEND"};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(c[i].type, order[i]);
  ASSERT_EQ(c[0].data.size(), 13u);
  EXPECT_EQ(be32(&c[0].data[0]), uint32_t(w));
  EXPECT_EQ(be32(&c[0].data[4]), uint32_t(h));
  EXPECT_EQ(std::vector<uint8_t>(c[0].data.begin() + 8, c[0].data.end()),
            (std::vector<uint8_t>{8, 2, 0, 0, 0}));  // 8-bit RGB, not interlaced
  EXPECT_TRUE(c[5].data.empty());

  const std::size_t row = std::size_t(w) * 3 + 1;
  std::vector<uint8_t> raw(row * h + 1);
  uLongf size = raw.size();
  ASSERT_EQ(uncompress(raw.data(), &size, c[4].data.data(), c[4].data.size()), Z_OK);
  ASSERT_EQ(size, row * h);
  std::vector<uint8_t> back(rgb.size());
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(raw[row * y], 2) << "row " << y << " is not Up-filtered";
    for (std::size_t i = 0; i + 1 < row; ++i) {
      const uint8_t above = y > 0 ? back[(row - 1) * (y - 1) + i] : 0;
      back[(row - 1) * y + i] = uint8_t(raw[row * y + 1 + i] + above);
    }
  }
  EXPECT_EQ(back, rgb);
  EXPECT_EQ(encode_png(rgb.data(), w, h), png);  // same pixels, same bytes
}

TEST(RenderEncodePng, OpenImageIODecodesThePixels) {
  for (auto [w, h] : {std::pair{1, 1}, {3, 2}, {64, 1}, {1, 50}, {201, 97}}) {
    const std::vector<uint8_t> rgb = test_image(w, h);
    const std::vector<uint8_t> png = encode_png(rgb.data(), w, h);
    const std::string path =
        ::testing::TempDir() + "render_encode_png_" + std::to_string(::getpid()) + ".png";
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in) << w << "x" << h << ": " << OIIO::geterror();
    EXPECT_EQ(in->spec().width, w);
    EXPECT_EQ(in->spec().height, h);
    ASSERT_EQ(in->spec().nchannels, 3);
    std::vector<uint8_t> back(rgb.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, back.data()));
    EXPECT_EQ(back, rgb) << w << "x" << h;
    in->close();
    std::remove(path.c_str());
  }
}

TEST(RenderEncodePng, RefusesEmptyImages) {
  const uint8_t px[3] = {1, 2, 3};
  EXPECT_THROW(encode_png(px, 0, 1), std::invalid_argument);
  EXPECT_THROW(encode_png(px, 1, 0), std::invalid_argument);
}

}  // namespace
}  // namespace splatkit::render
