#include "formats/pcd.h"

#include <gtest/gtest.h>

#include "test_format_support.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "splatkit/error.h"

namespace splatkit {
namespace {

// PCD files are written by hand here (text header + little-endian bytes) so that the test does
// not depend on PCL's writer.
std::string header(const std::string& fields, const std::string& size, const std::string& type,
                   const std::string& count, int width, int height, const std::string& data,
                   const std::string& viewpoint = "0 0 0 1 0 0 0") {
  return "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS " + fields + "\nSIZE " +
         size + "\nTYPE " + type + "\nCOUNT " + count + "\nWIDTH " + std::to_string(width) +
         "\nHEIGHT " + std::to_string(height) + "\nVIEWPOINT " + viewpoint + "\nPOINTS " +
         std::to_string(width * height) + "\nDATA " + data + "\n";
}

template <class T>
void append(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);  // little-endian like PCD binary
}

// LZF stream of literal runs only (control byte 0-31 = copy that many + 1 bytes).
std::string lzf_literals(const std::string& raw) {
  std::string out;
  for (std::size_t i = 0; i < raw.size(); i += 32) {
    const std::size_t n = std::min<std::size_t>(32, raw.size() - i);
    out += static_cast<char>(n - 1);
    out += raw.substr(i, n);
  }
  return out;
}

float packed_rgb(uint8_t r, uint8_t g, uint8_t b) {
  uint32_t v = uint32_t{r} << 16 | uint32_t{g} << 8 | b;
  float f;
  std::memcpy(&f, &v, 4);
  return f;
}

LoadedCloud read_bytes(const std::string& s) {
  InputStream in("t.pcd", s.data(), s.size());
  return read_pcd(in);
}

void expect_error(const std::string& s, ErrorKind kind, const std::string& phrase) {
  test::expect_read_error([&] { read_bytes(s); }, kind, phrase);
}

const std::string kAsciiFields = "x y z normal_x normal_y normal_z rgb curvature";

TEST(Pcd, AsciiWithNormalsColourAndCurvature) {
  std::string s =
      header(kAsciiFields, "4 4 4 4 4 4 4 4", "F F F F F F U F", "1 1 1 1 1 1 1 1", 2, 1, "ascii") +
      "1 2 3 0 0 1 16711808 0.5\n"
      "-1.5 0.25 1e2 0 1 0 255 0\n";
  auto doc = read_bytes(s);
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions[0], (Vec3f{1, 2, 3}));
  EXPECT_EQ(c.positions[1], (Vec3f{-1.5f, 0.25f, 100}));
  EXPECT_EQ(c.normals[1], (Vec3f{0, 1, 0}));
  EXPECT_EQ(c.colors[0], (std::array<uint16_t, 3>{255, 0, 128}));
  EXPECT_EQ(c.colors[1], (std::array<uint16_t, 3>{0, 0, 255}));
  ASSERT_EQ(c.extras.size(), 1u);
  EXPECT_EQ(c.extras[0].name, "curvature");
  EXPECT_EQ(c.extras[0].values.doubles(), (std::vector<double>{0.5, 0}));
  EXPECT_FALSE(c.viewpoint.has_value());
  EXPECT_EQ(doc.header["data"], "ascii");
  EXPECT_FALSE(doc.header.contains("dropped_nan"));
  EXPECT_EQ(doc.header["fields"][6]["type"], "U");
  c.check_consistent();
}

TEST(Pcd, BinaryOrganisedWithViewpoint) {
  std::string s = header("x y z rgb intensity", "4 4 4 4 2", "F F F F U", "1 1 1 1 1", 2, 2,
                         "binary", "10 20 30 1 0 0 0");
  const float pts[4][3] = {{1, 2, 3}, {0, 0, 0}, {4, 5, 6}, {7, 8, 9}};
  for (int i = 0; i < 4; ++i) {
    for (float v : pts[i]) append(s, v);
    append(s, packed_rgb(static_cast<uint8_t>(i), 2, 3));
    append(s, static_cast<uint16_t>(100 + i));
  }
  auto doc = read_bytes(s);
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c.positions[2], (Vec3f{4, 5, 6}));
  EXPECT_EQ(c.colors[3], (std::array<uint16_t, 3>{3, 2, 3}));
  EXPECT_EQ(c.find_extra("intensity")->type(), ScalarType::kUInt16);
  EXPECT_EQ(c.find_extra("intensity")->values.doubles(), (std::vector<double>{100, 101, 102, 103}));
  ASSERT_TRUE(c.viewpoint.has_value());
  EXPECT_EQ(*c.viewpoint, (std::array<double, 3>{10, 20, 30}));
}

// As every reader: a NaN or infinite coordinate is refused naming the point, never dropped.
TEST(Pcd, NanOrInfiniteCoordinateIsRefused) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const float bad : {nan, inf}) {
    std::string s = header("x y z", "4 4 4", "F F F", "1 1 1", 3, 1, "binary");
    const float pts[3][3] = {{1, 2, 3}, {4, bad, 6}, {7, 8, 9}};
    for (const auto& p : pts)
      for (float v : p) append(s, v);
    expect_error(s, ErrorKind::kBadInput, "point 1: NaN or infinite coordinate (y = ");
  }
}

TEST(Pcd, BinaryCompressedFieldMajor) {
  std::string s = header("x y z label", "4 4 4 4", "F F F I", "1 1 1 1", 3, 1, "binary_compressed");
  // binary_compressed stores each field for all points, then the next field.
  std::string raw;
  for (float v : {1.f, 2.f, 3.f}) append(raw, v);
  for (float v : {10.f, 20.f, 30.f}) append(raw, v);
  for (float v : {-1.f, -2.f, -3.f}) append(raw, v);
  for (int32_t v : {7, -8, 9}) append(raw, v);
  const std::string packed = lzf_literals(raw);
  append(s, static_cast<uint32_t>(packed.size()));
  append(s, static_cast<uint32_t>(raw.size()));
  s += packed;
  auto c = read_bytes(s).cloud;
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.positions[2], (Vec3f{3, 30, -3}));
  EXPECT_EQ(c.find_extra("label")->values.doubles(), (std::vector<double>{7, -8, 9}));
  EXPECT_EQ(c.find_extra("label")->type(), ScalarType::kInt32);
}

TEST(Pcd, DoubleCoordinatesMultiCountFieldsAndOrigin) {
  std::string s = header("x y z _ fpfh", "8 8 8 1 4", "F F F U F", "1 1 1 2 3", 1, 1, "ascii") +
                  "500123.25 4100000.5 10 0 0 0.5 1.5 2.5\n";
  auto c = read_bytes(s).cloud;
  EXPECT_EQ(c.origin, (std::array<double, 3>{500000, 4100000, 0}));
  EXPECT_EQ(c.positions[0], (Vec3f{123.25f, 0.5f, 10}));
  ASSERT_EQ(c.extras.size(), 3u);  // the "_" padding is not kept
  EXPECT_EQ(c.extras[1].name, "fpfh_1");
  EXPECT_EQ(c.extras[1].values[0], 1.5);
}

TEST(Pcd, ZeroPoints) {
  auto doc = read_bytes(header("x y z", "4 4 4", "F F F", "1 1 1", 0, 1, "ascii"));
  EXPECT_EQ(doc.cloud.size(), 0u);
}

// Points TMPDIR (where a PCD that is not a regular file is spilled for PCL) somewhere else for
// the lifetime of the object.
class ScopedTmpdir {
 public:
  explicit ScopedTmpdir(const std::string& dir) {
    if (const char* old = std::getenv("TMPDIR")) old_ = old;
    ::setenv("TMPDIR", dir.c_str(), 1);
  }
  ~ScopedTmpdir() {
    if (old_)
      ::setenv("TMPDIR", old_->c_str(), 1);
    else
      ::unsetenv("TMPDIR");
  }
  ScopedTmpdir(const ScopedTmpdir&) = delete;
  ScopedTmpdir& operator=(const ScopedTmpdir&) = delete;

 private:
  std::optional<std::string> old_;
};

std::filesystem::path private_dir(const std::string& name) {
  auto dir = std::filesystem::path(testing::TempDir()) /
             ("splatkit_pcd_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// TMPDIR names a directory that does not exist: a spill would fail, so a read that succeeds did
// not spill. The in-memory read shows that the trap works.
TEST(Pcd, ReadsARegularFileInPlace) {
  const auto dir = private_dir("in_place");
  const std::string path = (dir / "in place.pcd").string();
  const std::string bytes = header("x y z", "4 4 4", "F F F", "1 1 1", 1, 1, "ascii") + "7 8 9\n";
  std::ofstream(path, std::ios::binary) << bytes;
  {
    ScopedTmpdir no_spill((dir / "no such dir").string());
    InputStream in(path);
    EXPECT_EQ(read_pcd(in).cloud.positions[0], (Vec3f{7, 8, 9}));
    test::expect_read_error([&] { read_bytes(bytes); }, ErrorKind::kOutput,
                            "cannot create temporary file");
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  std::filesystem::remove_all(dir);
}

// Input that is not a regular file is spilled into TMPDIR; the spill file is gone after the read,
// whether it succeeded or failed.
TEST(Pcd, SpillFileIsRemovedAfterReadingAndAfterAnError) {
  const auto dir = private_dir("spill");
  {
    ScopedTmpdir spill(dir.string());
    EXPECT_EQ(read_bytes(header("x y z", "4 4 4", "F F F", "1 1 1", 1, 1, "ascii") + "7 8 9\n")
                  .cloud.positions[0],
              (Vec3f{7, 8, 9}));
    EXPECT_TRUE(std::filesystem::is_empty(dir));
    expect_error(header("x y z", "4 4 4", "F F F", "1 1 1", 2, 1, "ascii") + "7 8 9\n1 2 zz\n",
                 ErrorKind::kBadInput, "zz");
    EXPECT_TRUE(std::filesystem::is_empty(dir));
  }
  std::filesystem::remove_all(dir);
}

// Written by PCL 1.13's own writer (pcl_convert_pcd_ascii_binary, see tests/data/pcd/README.md):
// real LZF back references and PCL's zero padding to the page size after the data.
TEST(Pcd, FileWrittenByPcl) {
  InputStream in(std::string(SPLATKIT_SOURCE_DIR) + "/tests/data/pcd/pcl_written_compressed.pcd");
  auto doc = read_pcd(in);
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 200u);
  for (std::size_t i = 0; i < c.size(); ++i) {
    ASSERT_EQ(c.positions[i], (Vec3f{i * 0.5f, (i % 10) * 0.25f, 1})) << i;
    ASSERT_EQ(c.normals[i], (Vec3f{0, 0, 1})) << i;
    ASSERT_EQ(c.colors[i], (std::array<uint16_t, 3>{static_cast<uint16_t>(i % 256),
                                                    static_cast<uint16_t>(2 * i % 256),
                                                    static_cast<uint16_t>(3 * i % 256)}))
        << i;
    ASSERT_EQ(c.extras[0].values[i], static_cast<double>(static_cast<float>(i / 1000.0))) << i;
  }
  EXPECT_EQ(*c.viewpoint, (std::array<double, 3>{1.5, 2.5, 3.5}));
  EXPECT_EQ(doc.header["data"], "binary_compressed");
}

TEST(Pcd, HeaderErrors) {
  const auto bad = ErrorKind::kBadInput;
  const std::string xyz = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
  expect_error("VERSION 0.7\n" + xyz + "WIDTH 1\n", bad,
               "unexpected end of file in the PCD header (no DATA line)");
  expect_error("VERSION 0.8\n", ErrorKind::kUnsupported, "PCD version '0.8' is not supported");
  expect_error(xyz + "WIDTH 1\nPOINTS 1\nCOLOR 3\nDATA ascii\n", bad,
               "line 6: unknown header keyword 'COLOR'");
  expect_error("FIELDS x y z\nSIZE 4 4\n", bad, "line 2: SIZE has 2 values for 3 fields");
  expect_error("FIELDS x y z\nSIZE 4 4 3\n", bad, "SIZE 3 is not 1, 2, 4 or 8");
  expect_error("FIELDS x y z\nSIZE 4 4 4\nTYPE F F D\n", bad, "TYPE 'D' is not F, I or U");
  expect_error("FIELDS x y z\nSIZE 4 4 2\nTYPE F F F\n", bad, "field 'z': float of size 2");
  expect_error("FIELDS x y z\nTYPE F F F\nSIZE 4 4 4\n", bad, "line 2: TYPE before SIZE");
  expect_error("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nSIZE 4 4 4\n", bad,
               "line 4: SIZE repeated or out of order");
  expect_error("FIELDS x y z\nSIZE 4 4 4\n#TYPE F F F\nCOUNT 1 1 1\n", bad,
               "line 4: COUNT before TYPE");
  expect_error("FIELDS x y z\nSIZE 4 4 4\nWIDTH 1\n", bad, "line 3: WIDTH before TYPE");
  expect_error(xyz + "COUNT 1 0 1\n", bad, "COUNT 0 out of range");
  expect_error(xyz + "WIDTH 2\nHEIGHT 2\nPOINTS 3\nDATA ascii\n", bad,
               "WIDTH x HEIGHT = 2 x 2 differs from POINTS 3");
  expect_error(xyz + "WIDTH 1\nPOINTS 1\nDATA ascii\n", bad,
               "POINTS 1 cannot fit in the 0 bytes left");
  expect_error(xyz + "POINTS 1\nDATA ascii\n", bad, "the header has no WIDTH line");
  expect_error(xyz + "WIDTH 1\nDATA ascii\n", bad, "the header has no POINTS line");
  expect_error(xyz + "WIDTH 1\nVIEWPOINT 0 0 0 1 0 0\nPOINTS 1\nDATA ascii\n", bad,
               "VIEWPOINT needs 7 values");
  expect_error(xyz + "WIDTH 1\nVIEWPOINT 0 nan 0 1 0 0 0\nPOINTS 1\nDATA ascii\n", bad,
               "VIEWPOINT value 'nan'");
  expect_error(xyz + "WIDTH 1\nPOINTS 1\nDATA xml\n", bad, "unknown DATA encoding 'xml'");
  expect_error(xyz + "WIDTH 1\n  \nPOINTS 1\nDATA ascii\n", bad,
               "line 5: line of only spaces in the header");
  expect_error("FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2\n", bad,
               "no x, y and z fields");
  expect_error(
      "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 2 1\nWIDTH 1\nPOINTS 1\nDATA ascii\n1 2 3 4\n",
      bad, "field 'y' must be one value of 4 or 8 bytes");
  expect_error("FIELDS x y z x\nSIZE 4 4 4 4\n", bad, "field 'x' named twice");
  expect_error("FIELDS x y z\fw\n", bad, "line 1: control character in a header line");
  expect_error(xyz + "WIDTH 4294967296\n", bad, "WIDTH exceeds 2^32 - 1");
  expect_error(xyz + "WIDTH 200000000\nPOINTS 200000000\nDATA binary\n", bad,
               "exceed the 2 GiB that PCL can read");
}

TEST(Pcd, BodyErrors) {
  const auto bad = ErrorKind::kBadInput;
  const std::string h2 = header("x y z", "4 4 4", "F F F", "1 1 1", 2, 1, "ascii");
  expect_error(h2 + "1.000 2.000 3.000\n", bad, "unexpected end of file after 1 of 2 points");
  expect_error(h2 + "1 2 3\n4     5\n", bad, "line 13: expected 3 values, found 2");
  expect_error(h2 + "1 2 3\n4 five 6\n", bad, "line 13: not a number: 'five'");
  expect_error(h2 + "1 2 3\n4 5 6\n7 8 9\n", bad,
               "line 14: trailing data after the last of 2 points");
  expect_error(h2 + "1 2 3\n   \n4 5 6\n", bad, "line of only spaces among the points");
  expect_error(h2 + "1 2 3\n4 inf 6\n", bad, "point 1: NaN or infinite coordinate (y = inf)");
  expect_error(header("x y z", "4 4 4", "F F F", "1 1 1", 100000, 1, "ascii") + "1 2 3\n", bad,
               "POINTS 100000 cannot fit in the");

  const std::string hb = header("x y z", "4 4 4", "F F F", "1 1 1", 2, 1, "binary");
  std::string body;
  for (float v : {1.f, 2.f, 3.f, 4.f, 5.f, 6.f}) append(body, v);
  expect_error(hb + body.substr(0, 20), bad, "binary data truncated: 24 bytes expected, 20 left");
  expect_error(hb + body + std::string(5, '\0') + "x", bad,
               "byte 193: trailing data after the binary points");
  EXPECT_EQ(read_bytes(hb + body + std::string(3000, '\0')).cloud.size(),
            2u);  // PCL's page padding
  expect_error(hb + "POINTS 9\n" + body.substr(9), bad,
               "binary data starts with a line that PCL would read as a header line ('POINTS')");
  expect_error(hb + "#\n\nDATA a\n" + body.substr(11), bad, "as a header line ('DATA')");

  const std::string hc = header("x y z", "4 4 4", "F F F", "1 1 1", 2, 1, "binary_compressed");
  const std::string packed = lzf_literals(body);
  auto sizes = [](uint32_t c, uint32_t u) {
    std::string s;
    append(s, c);
    append(s, u);
    return s;
  };
  expect_error(hc + sizes(static_cast<uint32_t>(packed.size()), 25) + packed, bad,
               "uncompressed size 25 differs from POINTS x point size = 24");
  expect_error(hc + sizes(0, 24), bad, "compressed size is zero");
  expect_error(hc + sizes(static_cast<uint32_t>(packed.size()) + 1, 24) + packed, bad,
               "binary data truncated");
  expect_error(hc + sizes(static_cast<uint32_t>(packed.size()), 24) + packed + "z", bad,
               "trailing data after the binary points");
  auto lzf = [&](const std::string& stream) {
    return hc + sizes(static_cast<uint32_t>(stream.size()), 24) + stream;
  };
  std::string corrupt = packed;
  corrupt[0] = 31;  // a literal run longer than the output
  expect_error(lzf(corrupt), bad,
               "binary_compressed: the LZF stream decompresses to more than 24 bytes");
  expect_error(lzf(std::string("\x00\x41\x20\x05", 4) + std::string(64, '\0')), bad,
               "an LZF back reference points before the start");
  expect_error(lzf(packed.substr(0, 20)), bad, "the LZF stream ends inside a literal run");
  expect_error(lzf(packed + "\xe0"), bad, "the LZF stream ends inside a back reference");
  expect_error(lzf("\x03" + body.substr(0, 4)), bad,
               "the LZF stream decompresses to 4 bytes, not 24");
  // A back reference (length 2 + 2, distance 4) repeating the third float: valid LZF. The data is
  // field-major, so x = (1, 2), y = (3, 3), z = (5, 6).
  std::string rep;
  rep += '\x0b';
  rep += body.substr(0, 12);
  rep += std::string("\x40\x03", 2);
  rep += '\x07';
  rep += body.substr(16, 8);
  auto c = read_bytes(lzf(rep)).cloud;
  EXPECT_EQ(c.positions[1], (Vec3f{2, 3, 6}));
  const std::string big =
      header("x y z", "4 4 4", "F F F", "1 1 1", 1000000, 1, "binary_compressed");
  expect_error(big + sizes(10, 12000000) + std::string(10, '\0'), bad,
               "is too small for 12000000 bytes");
}

}  // namespace
}  // namespace splatkit
