// PLY reader and writer: round trips for every type and encoding, header aliases, faces, extras,
// pinned bytes, and one rejection per malformed case.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>
#include "test_format_support.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>

#include "formats/ply.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

std::string unique_temp_path(const std::string& name) {
  static int counter = 0;
  return testing::TempDir() + "splatkit_ply_" + std::to_string(::getpid()) + "_" +
         std::to_string(counter++) + "_" + name;
}

using test::slurp;

LoadedCloud read_bytes(const std::string& bytes) {
  InputStream in("test.ply", bytes.data(), bytes.size());
  return read_ply(in);
}

std::string write_bytes(const SplatCloud& cloud, PlyEncoding enc,
                        const std::vector<std::string>& comments = {}) {
  const std::string path = unique_temp_path("out.ply");
  {
    OutputFile out(path);
    write_ply(cloud, out, enc, comments);
    out.commit();
  }
  std::string bytes = slurp(path);
  std::remove(path.c_str());
  return bytes;
}

// Binary PLY bodies, little- or big-endian.
class Bytes {
 public:
  explicit Bytes(std::string header, bool big = false) : s_(std::move(header)), big_(big) {}
  template <class T>
  Bytes& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof v);
    if (big_ == (std::endian::native == std::endian::little))
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    s_.append(b, sizeof b);
    return *this;
  }
  Bytes& f(float v) { return put(v); }
  const std::string& str() const { return s_; }

 private:
  std::string s_;
  bool big_;
};

void expect_bad(const std::string& bytes, const std::string& phrase) {
  test::expect_read_error([&] { read_bytes(bytes); }, ErrorKind::kBadInput, phrase);
}

const std::vector<ScalarType> kAllTypes = {
    ScalarType::kInt8,    ScalarType::kUInt8,  ScalarType::kInt16, ScalarType::kUInt16,
    ScalarType::kInt32,   ScalarType::kUInt32, ScalarType::kInt64, ScalarType::kUInt64,
    ScalarType::kFloat32, ScalarType::kFloat64};

// Values at the ends of each type's range (and an inexact float for the float types).
std::vector<double> extreme_values(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8:
      return {-128, 127, 0};
    case ScalarType::kUInt8:
      return {0, 255, 7};
    case ScalarType::kInt16:
      return {-32768, 32767, -1};
    case ScalarType::kUInt16:
      return {0, 65535, 300};
    case ScalarType::kInt32:
      return {-2147483648.0, 2147483647.0, 5};
    case ScalarType::kUInt32:
      return {0, 4294967295.0, 9};
    case ScalarType::kInt64:
      return {-9007199254740992.0, 9007199254740992.0, -3};
    case ScalarType::kUInt64:
      return {0, 9007199254740992.0, 11};
    case ScalarType::kFloat32:
      return {static_cast<double>(0.1f), -3.4e38f, 1.4e-45f};
    case ScalarType::kFloat64:
      return {0.1, -1.7976931348623157e308, 4.9e-324};
  }
  return {};
}

SplatCloud full_cloud() {
  SplatCloud c;
  c.positions = {{1, 2, 3}, {-1.5f, 0.1f, 1e-7f}, {1e30f, -2e-30f, 0}};
  c.normals = {{0, 0, 1}, {0.6f, 0.8f, 0}, {-1, 0, 0}};
  c.radii = {0.5f, 0.25f, 1.0f / 3};
  c.colors = {{{255, 0, 128}}, {{1, 2, 3}}, {{0, 0, 0}}};
  c.extras.push_back({"intensity", ScalarType::kFloat32, {0.5, 1.25, -2}});
  c.extras.push_back({"alpha", ScalarType::kUInt8, {255, 0, 17}});
  c.face_offsets = {0, 3, 7};
  c.face_indices = {0, 1, 2, 2, 1, 0, 1};
  return c;
}

void expect_same(const SplatCloud& a, const SplatCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a.positions[i], b.positions[i]) << "point " << i;
  }
  EXPECT_EQ(a.origin, b.origin);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.radii, b.radii);
  EXPECT_EQ(a.colors, b.colors);
  EXPECT_EQ(a.color_bits, b.color_bits);
  ASSERT_EQ(a.extras.size(), b.extras.size());
  for (std::size_t k = 0; k < a.extras.size(); ++k) {
    EXPECT_EQ(a.extras[k].name, b.extras[k].name);
    EXPECT_EQ(a.extras[k].type(), b.extras[k].type()) << a.extras[k].name;
    EXPECT_EQ(a.extras[k].values, b.extras[k].values) << a.extras[k].name;
  }
  EXPECT_EQ(a.face_offsets, b.face_offsets);
  EXPECT_EQ(a.face_indices, b.face_indices);
}

class PlyEncodings : public testing::TestWithParam<PlyEncoding> {};

TEST_P(PlyEncodings, RoundTripKeepsEveryAttribute) {
  const SplatCloud c = full_cloud();
  const std::string bytes = write_bytes(c, GetParam(), {"made by a test"});
  const LoadedCloud doc = read_bytes(bytes);
  expect_same(c, doc.cloud);
  EXPECT_EQ(doc.format, "ply");
  EXPECT_EQ(doc.header["comments"], nlohmann::json::array({"made by a test"}));
  EXPECT_EQ(write_bytes(doc.cloud, GetParam(), {"made by a test"}), bytes) << "deterministic";
}

TEST_P(PlyEncodings, RoundTripEveryScalarType) {
  SplatCloud c;
  c.positions = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  for (ScalarType t : kAllTypes)
    c.extras.push_back({"v_" + std::string(scalar_name(t)), t, extreme_values(t)});
  const LoadedCloud doc = read_bytes(write_bytes(c, GetParam()));
  expect_same(c, doc.cloud);
}

TEST_P(PlyEncodings, RoundTripSixteenBitColoursAndOrigin) {
  SplatCloud c;
  c.origin = {512000, 4123000, 100000};
  c.positions = {{123.25f, 456.5f, 7.75f}, {-0.125f, 999.0f, 0.5f}};
  c.colors = {{{65535, 0, 257}}, {{1, 2, 3}}};
  c.color_bits = 16;
  const std::string bytes = write_bytes(c, GetParam());
  EXPECT_NE(bytes.find("property double x\n"), std::string::npos);
  EXPECT_NE(bytes.find("property ushort red\n"), std::string::npos);
  expect_same(c, read_bytes(bytes).cloud);
}

INSTANTIATE_TEST_SUITE_P(All, PlyEncodings,
                         testing::Values(PlyEncoding::kBinaryLittleEndian,
                                         PlyEncoding::kBinaryBigEndian, PlyEncoding::kAscii));

TEST(Ply, PinnedBinaryLittleEndianBytes) {
  SplatCloud c;
  c.positions = {{1, 2, 3}, {-1, 0.5f, 0}};
  c.normals = {{0, 0, 1}, {0, 0, 1}};
  c.colors = {{{255, 0, 128}}, {{1, 2, 3}}};
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment t\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  const unsigned char body[] = {
      0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0x40, 0x00, 0x00, 0x40, 0x40,  // 1 2 3
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f,  // 0 0 1
      0xff, 0x00, 0x80,                                                        // colour
      0x00, 0x00, 0x80, 0xbf, 0x00, 0x00, 0x00, 0x3f, 0x00, 0x00, 0x00, 0x00,  // -1 .5 0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f,  // 0 0 1
      0x01, 0x02, 0x03};
  const std::string expected =
      header + std::string(reinterpret_cast<const char*>(body), sizeof body);
  EXPECT_EQ(write_bytes(c, PlyEncoding::kBinaryLittleEndian, {"t"}), expected);
}

TEST(Ply, PinnedBinaryBigEndianBytes) {
  SplatCloud c;
  c.positions = {{1, -2, 0.5f}};
  c.extras.push_back({"i", ScalarType::kInt16, {-2}});
  const std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nproperty short i\nend_header\n";
  const unsigned char body[] = {0x3f, 0x80, 0x00, 0x00, 0xc0, 0x00, 0x00,
                                0x00, 0x3f, 0x00, 0x00, 0x00, 0xff, 0xfe};
  EXPECT_EQ(write_bytes(c, PlyEncoding::kBinaryBigEndian),
            header + std::string(reinterpret_cast<const char*>(body), sizeof body));
}

TEST(Ply, WindowsLineEndingsInHeaderAndAsciiData) {
  const SplatCloud c = read_bytes(
                           "ply\r\nformat ascii 1.0\r\nelement vertex 1\r\nproperty float x\r\n"
                           "property float y\r\nproperty float z\r\nend_header\r\n1 2 3\r\n")
                           .cloud;
  EXPECT_EQ(c.positions, (std::vector<Vec3f>{{1, 2, 3}}));
}

TEST(Ply, PinnedAsciiText) {
  SplatCloud c;
  c.positions = {{0.1f, 2, -3.5f}};
  c.face_offsets = {0, 3};
  c.face_indices = {0, 0, 0};
  EXPECT_EQ(write_bytes(c, PlyEncoding::kAscii),
            "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0.1 2 -3.5\n3 0 0 0\n");
}

TEST(Ply, HeaderAliasesAndTypesAreDecoded) {
  // Every PLY alias and sized name, big-endian, in one vertex row.
  const char* names[] = {"char",  "uchar",  "short",   "ushort", "int",   "uint",
                         "float", "double", "int8",    "uint8",  "int16", "uint16",
                         "int32", "uint32", "float32", "float64"};
  std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 1\n"
      "property float x\nproperty float y\nproperty float z\n";
  for (const char* n : names) header += std::string("property ") + n + " p_" + n + "\n";
  header += "end_header\n";
  Bytes b(header, true);
  b.f(1).f(2).f(3);
  b.put<int8_t>(-5).put<uint8_t>(250).put<int16_t>(-300).put<uint16_t>(60000);
  b.put<int32_t>(-70000).put<uint32_t>(4000000000u).put<float>(0.25f).put<double>(0.1);
  b.put<int8_t>(-6).put<uint8_t>(251).put<int16_t>(-301).put<uint16_t>(60001);
  b.put<int32_t>(-70001).put<uint32_t>(4000000001u).put<float>(0.5f).put<double>(0.2);
  const LoadedCloud doc = read_bytes(b.str());
  const SplatCloud& c = doc.cloud;
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c.positions[0], (Vec3f{1, 2, 3}));
  const std::vector<std::pair<ScalarType, double>> want = {
      {ScalarType::kInt8, -5},      {ScalarType::kUInt8, 250},
      {ScalarType::kInt16, -300},   {ScalarType::kUInt16, 60000},
      {ScalarType::kInt32, -70000}, {ScalarType::kUInt32, 4000000000.0},
      {ScalarType::kFloat32, 0.25}, {ScalarType::kFloat64, 0.1},
      {ScalarType::kInt8, -6},      {ScalarType::kUInt8, 251},
      {ScalarType::kInt16, -301},   {ScalarType::kUInt16, 60001},
      {ScalarType::kInt32, -70001}, {ScalarType::kUInt32, 4000000001.0},
      {ScalarType::kFloat32, 0.5},  {ScalarType::kFloat64, 0.2}};
  ASSERT_EQ(c.extras.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(c.extras[i].name, std::string("p_") + names[i]);
    EXPECT_EQ(c.extras[i].type(), want[i].first) << names[i];
    EXPECT_EQ(c.extras[i].values.doubles(), std::vector<double>{want[i].second}) << names[i];
  }
  EXPECT_EQ(doc.header["encoding"], "binary_big_endian");
  EXPECT_EQ(doc.header["elements"][0]["properties"][3]["type"], "int8");
  EXPECT_EQ(doc.header["elements"][0]["properties"][18]["type"], "float64");
}

TEST(Ply, DiffuseColoursAlphaAndOtherPropertiesAsExtras) {
  const std::string text =
      "ply\nformat ascii 1.0\ncomment scanned\nobj_info scanner X\nelement vertex 2\n"
      "property float x\nproperty float y\nproperty float z\nproperty uchar diffuse_red\n"
      "property uchar diffuse_green\nproperty uchar diffuse_blue\nproperty uchar alpha\n"
      "property float confidence\nend_header\n"
      "0 0 0 10 20 30 255 0.5\n1 1 1 40 50 60 128 0.25\n";
  const LoadedCloud doc = read_bytes(text);
  const SplatCloud& c = doc.cloud;
  EXPECT_EQ(c.color_bits, 8);
  EXPECT_EQ(c.colors, (std::vector<std::array<uint16_t, 3>>{{{10, 20, 30}}, {{40, 50, 60}}}));
  ASSERT_NE(c.find_extra("alpha"), nullptr);
  EXPECT_EQ(c.find_extra("alpha")->type(), ScalarType::kUInt8);
  EXPECT_EQ(c.find_extra("alpha")->values.doubles(), (std::vector<double>{255, 128}));
  ASSERT_NE(c.find_extra("confidence"), nullptr);
  EXPECT_EQ(c.find_extra("confidence")->values.doubles(), (std::vector<double>{0.5, 0.25}));
  EXPECT_EQ(doc.header["comments"], nlohmann::json::array({"scanned"}));
  EXPECT_EQ(doc.header["obj_info"], nlohmann::json::array({"scanner X"}));
  EXPECT_EQ(doc.header["elements"][0]["count"], 2);
}

TEST(Ply, FloatColoursMapToEightBitsAndUShortToSixteen) {
  const std::string f =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nproperty float red\nproperty float green\nproperty float blue\n"
      "end_header\n0 0 0 1 0.5 0\n0 0 0 2 -1 0.002\n";
  const SplatCloud a = read_bytes(f).cloud;
  EXPECT_EQ(a.color_bits, 8);
  EXPECT_EQ(a.colors, (std::vector<std::array<uint16_t, 3>>{{{255, 128, 0}}, {{255, 0, 1}}}));
  Bytes b(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nproperty ushort red\nproperty ushort green\n"
      "property ushort blue\nend_header\n");
  b.f(0).f(0).f(0).put<uint16_t>(65535).put<uint16_t>(1000).put<uint16_t>(0);
  const SplatCloud c = read_bytes(b.str()).cloud;
  EXPECT_EQ(c.color_bits, 16);
  EXPECT_EQ(c.colors, (std::vector<std::array<uint16_t, 3>>{{{65535, 1000, 0}}}));
}

TEST(Ply, FacesWithAnyListTypesAndOtherElementsSkipped) {
  Bytes b(
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nelement face 2\nproperty uchar flags\n"
      "property list ushort uint vertex_index\nproperty list uchar float texcoord\n"
      "element edge 2\nproperty list int int v\nelement material 1\nproperty float k\n"
      "end_header\n");
  for (int i = 0; i < 4; ++i) b.f(static_cast<float>(i)).f(0).f(0);
  b.put<uint8_t>(9).put<uint16_t>(3).put<uint32_t>(0).put<uint32_t>(1).put<uint32_t>(2);
  b.put<uint8_t>(2).f(0.5f).f(0.5f);
  b.put<uint8_t>(9).put<uint16_t>(4).put<uint32_t>(3).put<uint32_t>(2).put<uint32_t>(1);
  b.put<uint32_t>(0).put<uint8_t>(0);
  b.put<int32_t>(2).put<int32_t>(0).put<int32_t>(1).put<int32_t>(0);
  b.f(7);
  const LoadedCloud doc = read_bytes(b.str());
  EXPECT_EQ(doc.cloud.face_offsets, (std::vector<uint32_t>{0, 3, 7}));
  EXPECT_EQ(doc.cloud.face_indices, (std::vector<uint32_t>{0, 1, 2, 3, 2, 1, 0}));
  EXPECT_TRUE(doc.cloud.extras.empty());
  ASSERT_EQ(doc.header["elements"].size(), 4u);
  EXPECT_EQ(doc.header["elements"][1]["properties"][1]["count_type"], "uint16");
  EXPECT_EQ(doc.header["elements"][2]["name"], "edge");
}

TEST(Ply, AsciiFacesAndSkippedElements) {
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
      "element other 2\nproperty list uchar float w\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 1.5 2.5\n0\n\n";
  const SplatCloud c = read_bytes(text).cloud;
  EXPECT_EQ(c.size(), 3u);
  EXPECT_EQ(c.face_offsets, (std::vector<uint32_t>{0, 3}));
  EXPECT_EQ(c.face_indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_EQ(c.origin, (std::array<double, 3>{0, 0, 0}));
}

TEST(Ply, DoubleCoordinatesGetAnOrigin) {
  Bytes b(
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n");
  b.put(512345.25).put(4123456.5).put(10.0).put(512346.0).put(4123457.0).put(11.0);
  const SplatCloud c = read_bytes(b.str()).cloud;
  EXPECT_EQ(c.origin, (std::array<double, 3>{512000, 4123000, 0}));
  EXPECT_EQ(c.positions[0], (Vec3f{345.25f, 456.5f, 10}));
  EXPECT_EQ(c.positions[1], (Vec3f{346, 457, 11}));
}

TEST(Ply, VertexRowsWithListsDecodeLikeFixedRows) {
  // The row-at-a-time path (a list in the vertex) and the block path agree.
  const std::string head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property short s\n";
  Bytes fixed(head + "end_header\n");
  Bytes listed(head + "property list uchar int ids\nend_header\n");
  for (int i = 0; i < 3; ++i) {
    for (Bytes* b : {&fixed, &listed}) {
      b->f(i * 0.5f).f(-i * 1.0f).f(3.0f).put<uint8_t>(i).put<uint8_t>(2 * i).put<uint8_t>(255);
      b->put<int16_t>(static_cast<int16_t>(-i));
    }
    listed.put<uint8_t>(1).put<int32_t>(i);
  }
  expect_same(read_bytes(fixed.str()).cloud, read_bytes(listed.str()).cloud);
  EXPECT_EQ(read_bytes(fixed.str()).cloud.positions[2], (Vec3f{1, -2, 3}));
}

TEST(Ply, ManyBlocksFromAFileAndFromAPipe) {
  // 100k points span many decode blocks; a FIFO has no size, so vectors grow as data arrives.
  SplatCloud c;
  for (int i = 0; i < 100000; ++i) {
    c.positions.push_back({i * 0.25f, -i * 1.0f, 1.0f / (i + 1)});
    c.normals.push_back({0, 1, 0});
    c.radii.push_back(i * 0.001f);
    c.colors.push_back({{static_cast<uint16_t>(i % 256), 7, 9}});
  }
  const std::string path = unique_temp_path("many.ply");
  {
    OutputFile out(path);
    write_ply(c, out);
    out.commit();
  }
  InputStream file(path, 4096);
  expect_same(c, read_ply(file).cloud);

  const std::string fifo = unique_temp_path("fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string bytes = slurp(path);
  std::thread writer([&] {
    std::ofstream f(fifo, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
  {
    InputStream pipe(fifo);
    EXPECT_FALSE(pipe.size_hint().has_value());
    expect_same(c, read_ply(pipe).cloud);
  }
  writer.join();
  // Cut short in a pipe (whose size is unknown up front): the row where the data ends.
  std::thread cut([&] {
    std::ofstream f(fifo, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  });
  test::expect_read_error(
      [&] {
        InputStream pipe(fifo);
        read_ply(pipe);
      },
      ErrorKind::kBadInput, "element 'vertex': truncated data: end of file after ");
  cut.join();
  std::remove(fifo.c_str());
  std::remove(path.c_str());
}

TEST(Ply, WriterMakesNamesHeaderSafeAndUnique) {
  SplatCloud c;
  c.positions = {{0, 0, 0}};
  c.extras.push_back({"my value", ScalarType::kUInt8, {1}});
  c.extras.push_back({"x", ScalarType::kUInt8, {2}});
  const std::string bytes = write_bytes(c, PlyEncoding::kAscii);
  EXPECT_NE(bytes.find("property uchar my_value\n"), std::string::npos);
  EXPECT_NE(bytes.find("property uchar x_2\n"), std::string::npos);
  EXPECT_EQ(read_bytes(bytes).cloud.find_extra("x_2")->values.doubles(), std::vector<double>{2});
}

// --- malformed input: one test per case -------------------------------------------------------

const std::string kAsciiHead =
    "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
    "property float z\nend_header\n";
const std::string kBinaryHead =
    "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\n"
    "property float y\nproperty float z\n";

TEST(PlyBad, MissingMagic) { expect_bad("PLY\nformat ascii 1.0\n", "missing 'ply' magic"); }
TEST(PlyBad, MagicLineWithMore) { expect_bad("plyx\nformat ascii 1.0\n", "missing 'ply' magic"); }
TEST(PlyBad, BadFormatLine) {
  expect_bad("ply\nformat binary 1.0\nelement vertex 0\nend_header\n", "bad format line");
}
TEST(PlyBad, ElementBeforeFormat) {
  expect_bad("ply\nelement vertex 0\nend_header\n", "bad format line");
}
TEST(PlyBad, UnknownVersion) {
  expect_bad("ply\nformat ascii 2.0\nend_header\n", "unknown PLY version '2.0'");
}
TEST(PlyBad, UnknownType) {
  expect_bad("ply\nformat ascii 1.0\nelement vertex 0\nproperty float16 x\nend_header\n",
             "line 4: unknown type 'float16'");
}
TEST(PlyBad, PropertyBeforeElement) {
  expect_bad("ply\nformat ascii 1.0\nproperty float x\nend_header\n",
             "property before any element");
}
TEST(PlyBad, TruncatedHeader) {
  expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", "truncated header");
}
TEST(PlyBad, MissingEndHeader) {
  expect_bad("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n1\n",
             "missing end_header");
}
TEST(PlyBad, NegativeCount) {
  expect_bad("ply\nformat ascii 1.0\nelement vertex -3\nend_header\n", "is negative (bad count)");
}
TEST(PlyBad, NonNumericCount) {
  expect_bad("ply\nformat ascii 1.0\nelement vertex 12x\nend_header\n",
             "is not a number (bad count)");
}
TEST(PlyBad, OverflowingCount) {
  expect_bad("ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\nend_header\n",
             "overflows 64 bits (bad count)");
}
TEST(PlyBad, CountsLargerThanTheFile) {
  Bytes b(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n");
  b.f(0).f(0).f(0);
  expect_bad(b.str(), "counts larger than the file");
}
TEST(PlyBad, CountsOverflowingSize) {
  expect_bad(
      "ply\nformat binary_little_endian 1.0\nelement vertex 9000000000000000000\n"
      "property double x\nproperty double y\nproperty double z\nend_header\n",
      "counts larger than the file");
}
TEST(PlyBad, TruncatedAsciiData) {
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n1.000 2.000 3.000\n4.000 5.000 6.000\n",
      "truncated data: end of file after 2 of 3 rows");
}
TEST(PlyBad, TruncatedBinaryData) {
  Bytes b(kBinaryHead + "element face 2\nproperty list int int vertex_indices\nend_header\n");
  b.f(0).f(0).f(0).f(1).f(1).f(1);
  b.put<int32_t>(2).put<int32_t>(0).put<int32_t>(1);
  const std::string cut = b.str() + std::string("\x02\x00", 2);
  expect_bad(cut, "truncated data");
}
TEST(PlyBad, ListCountNegative) {
  Bytes b(kBinaryHead + "element face 1\nproperty list char int vertex_indices\nend_header\n");
  b.f(0).f(0).f(0).f(1).f(1).f(1).put<int8_t>(-1);
  expect_bad(b.str(), "list count -1 is negative");
}
TEST(PlyBad, ListCountTooBig) {
  Bytes b(kBinaryHead + "element face 1\nproperty list uint int vertex_indices\nend_header\n");
  b.f(0).f(0).f(0).f(1).f(1).f(1).put<uint32_t>(4000000000u).put<int32_t>(0);
  expect_bad(b.str(), "list count too big");
}
TEST(PlyBad, FaceIndexOutOfRange) {
  Bytes b(kBinaryHead + "element face 1\nproperty list uchar int vertex_indices\nend_header\n");
  b.f(0).f(0).f(0).f(1).f(1).f(1).put<uint8_t>(3).put<int32_t>(0).put<int32_t>(1).put<int32_t>(2);
  expect_bad(b.str(), "element 'face' row 0: vertex index 2 out of range (2 vertices)");
}
TEST(PlyBad, NegativeFaceIndex) {
  expect_bad(kAsciiHead.substr(0, kAsciiHead.size() - 11) +
                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0\n1 1 1\n3 0 1 -1\n",
             "vertex index -1 out of range");
}
TEST(PlyBad, NaNCoordinateBinary) {
  Bytes b(kBinaryHead + "end_header\n");
  b.f(0).f(0).f(0).f(1).f(std::numeric_limits<float>::quiet_NaN()).f(1);
  expect_bad(b.str(), "element 'vertex' row 1: NaN or infinite coordinate");
}
TEST(PlyBad, InfiniteCoordinateAscii) {
  expect_bad(kAsciiHead + "0 0 0\n1 inf 1\n", "line 9: element 'vertex' row 1: NaN or infinite");
}
TEST(PlyBad, AsciiTokenNotANumber) {
  expect_bad(kAsciiHead + "0 0 0\n1 abc 1\n", "value 'abc' is not a number of type float32");
}
TEST(PlyBad, AsciiTooFewTokens) {
  expect_bad(kAsciiHead + "0 0 0\n1 1\n", "line 9: element 'vertex' row 1: too few values");
}
TEST(PlyBad, AsciiTooManyTokens) {
  expect_bad(kAsciiHead + "0 0 0 0\n1 1 1\n", "too many values on the line");
}
TEST(PlyBad, AsciiValueOutOfRange) {
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nend_header\n0 0 0 256\n",
      "value '256' is out of range for uint8");
}
TEST(PlyBad, TrailingGarbageBinary) {
  Bytes b(kBinaryHead + "end_header\n");
  b.f(0).f(0).f(0).f(1).f(1).f(1).put<uint8_t>(0);
  expect_bad(b.str(), "trailing garbage after the last element (1 bytes)");
}
TEST(PlyBad, TrailingGarbageAscii) {
  expect_bad(kAsciiHead + "0 0 0\n1 1 1\n \nextra\n", "line 11: trailing garbage");
}
TEST(PlyBad, DuplicatePropertyName) {
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty double x\n"
      "end_header\n",
      "duplicate property 'x'");
}
TEST(PlyBad, MissingXyz) {
  expect_bad(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
      "end_header\n0 0\n",
      "missing property 'z'");
}
TEST(PlyBad, NoVertexElement) {
  expect_bad("ply\nformat ascii 1.0\nelement face 0\nend_header\n", "no 'vertex' element");
}

TEST(PlyBad, AsciiTrailingWhitespaceIsFine) {
  const SplatCloud c = read_bytes(kAsciiHead + "0 0 0  \n\n1 1 1\r\n\n  \n").cloud;
  EXPECT_EQ(c.positions[1], (Vec3f{1, 1, 1}));
}

// Faces of 8-bit counts and 32-bit indices are read a block at a time: rows that straddle the
// blocks, both byte orders, a file read through a small buffer and one in memory all give the
// faces written; a bad row past the first block is named as in any other file.
TEST(Ply, FacesAcrossReadBlocks) {
  constexpr uint32_t kFaces = 200000;  // 2.4 MB of rows: several blocks
  const auto corners = [](uint32_t f, uint32_t k) { return (f * 7 + k * 13) % 1000; };
  for (const bool big : {false, true}) {
    for (const ScalarType count : {ScalarType::kUInt8, ScalarType::kInt8}) {
      Bytes b(std::string("ply\nformat binary_") + (big ? "big" : "little") +
                  "_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
                  "property float z\nelement face " + std::to_string(kFaces) +
                  "\nproperty list " + (count == ScalarType::kUInt8 ? "uchar" : "char") +
                  " uint vertex_indices\nend_header\n",
              big);
      for (int i = 0; i < 1000; ++i) b.f(static_cast<float>(i)).f(0).f(0);
      std::vector<uint32_t> offsets{0}, indices;
      for (uint32_t f = 0; f < kFaces; ++f) {
        const uint32_t n = 3 + f % 2;  // triangles and quads: rows of 13 and 17 bytes
        b.put<uint8_t>(static_cast<uint8_t>(n));
        for (uint32_t k = 0; k < n; ++k) {
          b.put<uint32_t>(corners(f, k));
          indices.push_back(corners(f, k));
        }
        offsets.push_back(static_cast<uint32_t>(indices.size()));
      }
      const SplatCloud memory = read_bytes(b.str()).cloud;
      EXPECT_EQ(memory.face_offsets, offsets);
      EXPECT_EQ(memory.face_indices, indices);
      const std::string path = unique_temp_path("faces.ply");
      std::ofstream(path, std::ios::binary) << b.str();
      InputStream file(path, 4096);
      const SplatCloud read = read_ply(file).cloud;
      EXPECT_EQ(read.face_offsets, offsets);
      EXPECT_EQ(read.face_indices, indices);
      std::remove(path.c_str());
    }
  }
  const auto file_with_bad_row = [&](uint32_t bad) {
    Bytes b(kBinaryHead + "element face " + std::to_string(kFaces) +
            "\nproperty list uchar int vertex_indices\nend_header\n");
    b.f(0).f(0).f(0).f(1).f(1).f(1);
    for (uint32_t f = 0; f < kFaces; ++f)
      b.put<uint8_t>(3).put<int32_t>(0).put<int32_t>(f == bad ? 2 : 1).put<int32_t>(0);
    return b.str();
  };
  expect_bad(file_with_bad_row(150000),
             "element 'face' row 150000: vertex index 2 out of range (2 vertices)");
  const std::string good = file_with_bad_row(kFaces);
  EXPECT_EQ(read_bytes(good).cloud.face_indices.size(), 3 * kFaces);
  expect_bad(good.substr(0, good.size() - 6), "row 199999: list count too big");
}

// Blocks of triangles only are parsed in parallel chunks: a block that holds another row (a
// quad, in either byte order) falls back to the row by row reading, and the faces come out the
// same.
TEST(Ply, TriangleBlocksWithAnotherRow) {
  constexpr uint32_t kFaces = 300000;  // 3.9 MB: blocks of triangles only, and one with the quad
  for (const bool big : {false, true}) {
    Bytes b(std::string("ply\nformat binary_") + (big ? "big" : "little") +
                "_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
                "property float z\nelement face " + std::to_string(kFaces) +
                "\nproperty list uchar uint vertex_indices\nend_header\n",
            big);
    for (int i = 0; i < 1000; ++i) b.f(static_cast<float>(i)).f(0).f(0);
    std::vector<uint32_t> offsets{0}, indices;
    for (uint32_t f = 0; f < kFaces; ++f) {
      const uint32_t n = f == 170001 ? 4 : 3;
      b.put<uint8_t>(static_cast<uint8_t>(n));
      for (uint32_t k = 0; k < n; ++k) {
        b.put<uint32_t>((f * 7 + k * 13) % 1000);
        indices.push_back((f * 7 + k * 13) % 1000);
      }
      offsets.push_back(static_cast<uint32_t>(indices.size()));
    }
    const SplatCloud c = read_bytes(b.str()).cloud;
    EXPECT_EQ(c.face_offsets, offsets);
    EXPECT_EQ(c.face_indices, indices);
  }
}

}  // namespace
}  // namespace splatkit
