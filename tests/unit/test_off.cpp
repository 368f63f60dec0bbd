#include "formats/off.h"

#include <gtest/gtest.h>

#include "test_format_support.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "splatkit/error.h"

namespace splatkit {
namespace {

LoadedCloud read_text(const std::string& s) {
  InputStream in("t.off", s.data(), s.size());
  return read_off(in);
}

void expect_error(const std::string& s, ErrorKind kind, const std::string& phrase) {
  test::expect_read_error([&] { read_text(s); }, kind, phrase);
}

std::string temp_path(const std::string& name) { return test::temp_path("splatkit_off", name); }

using test::slurp;

const char* kTetra =
    "OFF\n"
    "# a tetrahedron\n"
    "4 4 6\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
    "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3 255 0 0\n";

TEST(Off, TetrahedronWithFaces) {
  auto doc = read_text(kTetra);
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c.positions[3], (Vec3f{0, 0, 1}));
  ASSERT_EQ(c.face_count(), 4u);
  EXPECT_EQ(c.face_offsets, (std::vector<uint32_t>{0, 3, 6, 9, 12}));
  EXPECT_EQ(c.face_indices[9], 1u);
  EXPECT_EQ(c.face_indices[11], 3u);
  EXPECT_EQ(doc.header["keyword"], "OFF");
  EXPECT_EQ(doc.header["edges"], 6);
  c.check_consistent();
}

TEST(Off, CountsOnHeaderLineAndPolygons) {
  auto c = read_text("OFF 5 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 1.5 0\n5 0 1 2 4 3\n").cloud;
  EXPECT_EQ(c.face_offsets, (std::vector<uint32_t>{0, 5}));
}

TEST(Off, ColoursIntegerAndFloat) {
  auto c = read_text("COFF\n2 0 0\n1 2 3 255 128 0 255\n4 5 6 1.0 0.5 0\n").cloud;
  ASSERT_TRUE(c.has_colors());
  EXPECT_EQ(c.colors[0], (std::array<uint16_t, 3>{255, 128, 0}));
  EXPECT_EQ(c.colors[1], (std::array<uint16_t, 3>{255, 128, 0}));
  EXPECT_FALSE(c.has_normals());
}

TEST(Off, NormalsAndColours) {
  auto n = read_text("NOFF\n1 0 0\n1 2 3 0 0 1\n").cloud;
  EXPECT_EQ(n.normals[0], (Vec3f{0, 0, 1}));
  auto cn = read_text("CNOFF\n1 0 0\n1 2 3 0 1 0 10 20 30\n").cloud;
  EXPECT_EQ(cn.normals[0], (Vec3f{0, 1, 0}));
  EXPECT_EQ(cn.colors[0], (std::array<uint16_t, 3>{10, 20, 30}));
}

TEST(Off, OriginFromFirstVertex) {
  auto c = read_text("OFF\n1 0 0\n600000.5 20 -30000.25\n").cloud;
  EXPECT_EQ(c.origin, (std::array<double, 3>{600000, 0, -30000}));
  EXPECT_EQ(c.positions[0], (Vec3f{0.5f, 20, -0.25f}));
}

TEST(Off, Errors) {
  expect_error("", ErrorKind::kBadInput, "empty file (no OFF header)");
  expect_error("PLY\n", ErrorKind::kBadInput, "line 1: not an OFF file");
  expect_error("STOFF\n1 0 0\n", ErrorKind::kUnsupported, "OFF variant 'STOFF' is not supported");
  expect_error("4OFF\n1 0 0\n", ErrorKind::kUnsupported, "OFF variant '4OFF'");
  expect_error("OFF BINARY\n", ErrorKind::kUnsupported, "binary OFF is not supported");
  expect_error("OFF\n", ErrorKind::kBadInput, "no vertex/face/edge count line");
  expect_error("OFF\n1 0\n", ErrorKind::kBadInput, "line 2: expected 3 counts");
  expect_error("OFF\n-1 0 0\n", ErrorKind::kBadInput, "count '-1' is not a non-negative integer");
  expect_error("OFF\n1000000000000 0 0\n0 0 0\n", ErrorKind::kBadInput,
               "header claims 1000000000000 vertices and 0 faces, more than the");
  expect_error("OFF\n3 0 0\n0.000 0.000 0.000\n1.000 1.000 1.000\n", ErrorKind::kBadInput,
               "unexpected end of file after 2 of 3 vertices");
  expect_error("OFF\n1 2 0\n0.000 0.000 0.000\n3   0   0   0\n", ErrorKind::kBadInput,
               "unexpected end of file after 1 of 2 faces");
  expect_error("OFF\n1 0 0\n0     0\n", ErrorKind::kBadInput,
               "line 3: vertex 0: expected 3 values, found 2");
  expect_error("OFF\n1 0 0\n0 x 0\n", ErrorKind::kBadInput, "vertex 0: not a number: 'x'");
  expect_error("OFF\n1 0 0\n0 nan 0\n", ErrorKind::kBadInput,
               "vertex 0: NaN or infinite coordinate");
  expect_error("NOFF\n1 0 0\n0 0 0 0 inf 0\n", ErrorKind::kBadInput, "NaN or infinite normal");
  expect_error("COFF\n1 0 0\n0 0 0 256 0 0\n", ErrorKind::kBadInput,
               "colour value '256' out of range 0-255");
  expect_error("COFF\n1 0 0\n0 0 0 1.5 0 0\n", ErrorKind::kBadInput, "out of range 0-1");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", ErrorKind::kBadInput,
               "face 0: vertex index 3 out of range (3 vertices)");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1    \n", ErrorKind::kBadInput,
               "face 0 has 2 vertices (at least 3 needed)");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1  \n", ErrorKind::kBadInput,
               "face 0: expected 3 vertex indices");
  expect_error("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n7 7 7\n", ErrorKind::kBadInput,
               "line 7: trailing data after the last face");
}

TEST(Off, TrailingCommentsAndBlankLinesAreFine) {
  auto c = read_text(std::string(kTetra) + "\n# end\n\n").cloud;
  EXPECT_EQ(c.face_count(), 4u);
}

TEST(Off, WriterExactBytesAndRoundTrip) {
  SplatCloud c;
  c.positions = {{0, 0, 0}, {1.5f, 0, 0}, {0, 0.1f, 0}};
  c.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, -1}};
  c.colors = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  c.face_offsets = {0, 3};
  c.face_indices = {0, 1, 2};
  const std::string path = temp_path("w.off");
  {
    OutputFile out(path);
    write_off(c, out);
    out.commit();
  }
  EXPECT_EQ(slurp(path),
            "CNOFF\n3 1 0\n"
            "0 0 0 0 0 1 255 0 0 255\n"
            "1.5 0 0 0 0 1 0 255 0 255\n"
            "0 0.1 0 0 0 -1 0 0 255 255\n"
            "3 0 1 2\n");
  InputStream in(path);
  auto back = read_off(in).cloud;
  EXPECT_EQ(back.positions, c.positions);
  EXPECT_EQ(back.normals, c.normals);
  EXPECT_EQ(back.colors, c.colors);
  EXPECT_EQ(back.face_offsets, c.face_offsets);
  EXPECT_EQ(back.face_indices, c.face_indices);
}

TEST(Off, WriterPlainOffWithOrigin) {
  SplatCloud c;
  c.origin = {600000, 0, 0};
  c.positions = {{0.5f, 1, 2}};
  const std::string path = temp_path("p.off");
  {
    OutputFile out(path);
    write_off(c, out);
    out.commit();
  }
  EXPECT_EQ(slurp(path), "OFF\n1 0 0\n600000.5 1 2\n");
}

}  // namespace
}  // namespace splatkit
