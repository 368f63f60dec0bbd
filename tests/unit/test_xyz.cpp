#include "formats/xyz.h"

#include <gtest/gtest.h>

#include "test_format_support.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "formats/read_cloud.h"
#include "formats/write_cloud.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

LoadedCloud read_text(const std::string& s, const std::string& columns = "") {
  InputStream in("t.xyz", s.data(), s.size());
  ReadOptions o;
  o.columns = columns;
  return read_xyz(in, o);
}

void expect_error(const std::string& s, ErrorKind kind, const std::string& phrase,
                  const std::string& columns = "") {
  test::expect_read_error([&] { read_text(s, columns); }, kind, phrase);
}

std::string temp_path(const std::string& name) { return test::temp_path("splatkit_xyz", name); }

using test::slurp;

TEST(Xyz, ThreeColumnsWhitespace) {
  auto doc = read_text("1 2 3\n\t-4.5  5e1 0.25\r\n");
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.positions[0], (Vec3f{1, 2, 3}));
  EXPECT_EQ(c.positions[1], (Vec3f{-4.5f, 50, 0.25f}));
  EXPECT_FALSE(c.has_normals());
  EXPECT_FALSE(c.has_colors());
  EXPECT_EQ(doc.header["header"], "none");
  EXPECT_EQ(doc.header["separator"], "whitespace");
}

TEST(Xyz, NamedHeaderCsv) {
  auto doc = read_text("x,y,z,nx,ny,nz,r,g,b\n1, 2, 3, 0, 1, 0, 255, 128, 0\n");
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c.normals[0], (Vec3f{0, 1, 0}));
  EXPECT_EQ(c.colors[0], (std::array<uint16_t, 3>{255, 128, 0}));
  EXPECT_EQ(c.color_bits, 8);
  EXPECT_EQ(doc.header["separator"], ",");
}

TEST(Xyz, CloudCompareHeaderWithScalarField) {
  auto doc = read_text("//X,Y,Z,R,G,B,Scalar field\n1,2,3,4,5,6,0.5\n");
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c.colors[0], (std::array<uint16_t, 3>{4, 5, 6}));
  const ExtraAttribute* sf = c.find_extra("Scalar field");
  ASSERT_NE(sf, nullptr);
  EXPECT_EQ(sf->type(), ScalarType::kFloat64);
  EXPECT_EQ(sf->values.doubles(), std::vector<double>{0.5});
}

TEST(Xyz, PtsCountAndSevenColumns) {
  auto doc = read_text("2\n1 2 3 -120 10 20 30\n4 5 6 7 40 50 60\n");
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(doc.header["pts_count"], 2);
  EXPECT_EQ(c.find_extra("intensity")->values.doubles(), (std::vector<double>{-120, 7}));
  EXPECT_EQ(c.colors[1], (std::array<uint16_t, 3>{40, 50, 60}));
}

TEST(Xyz, SixColumnsNormalOrColour) {
  auto normals = read_text("1 2 3 0 0 1\n").cloud;
  EXPECT_TRUE(normals.has_normals());
  EXPECT_FALSE(normals.has_colors());
  auto floats = read_text("1 2 3 0.5 0.5 0.0\n").cloud;
  EXPECT_TRUE(floats.has_normals());
  auto colours = read_text("1 2 3 10 20 30\n").cloud;
  EXPECT_TRUE(colours.has_colors());
  EXPECT_EQ(colours.colors[0], (std::array<uint16_t, 3>{10, 20, 30}));
}

TEST(Xyz, FourAndNineAndOddColumnCounts) {
  EXPECT_EQ(read_text("1 2 3 9\n").cloud.find_extra("intensity")->values[0], 9);
  auto nine = read_text("1 2 3 0 0 1 1 2 3\n").cloud;
  EXPECT_TRUE(nine.has_normals());
  EXPECT_EQ(nine.colors[0], (std::array<uint16_t, 3>{1, 2, 3}));
  auto five = read_text("1 2 3 4 5\n").cloud;
  EXPECT_EQ(five.find_extra("column_4")->values[0], 4);
  EXPECT_EQ(five.find_extra("column_5")->values[0], 5);
}

TEST(Xyz, ColumnsOptionWithSkip) {
  auto c = read_text("1 2 3 99 10 20 30\n", "x,y,z,_,r,g,b").cloud;
  EXPECT_EQ(c.positions[0], (Vec3f{1, 2, 3}));
  EXPECT_EQ(c.colors[0], (std::array<uint16_t, 3>{10, 20, 30}));
  EXPECT_TRUE(c.extras.empty());
  // The option overrides the header line, which is still skipped.
  auto d = read_text("a b c\n1 2 3\n", "z y x").cloud;
  EXPECT_EQ(d.positions[0], (Vec3f{3, 2, 1}));
}

TEST(Xyz, CommentsBlankLinesAndCommentHeader) {
  auto c =
      read_text("# scan of a thing\n\n# x y z radius\n1 2 3 0.5\n# mid comment\n\n4 5 6 1\n").cloud;
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.radii, (std::vector<float>{0.5f, 1}));
  EXPECT_TRUE(c.extras.empty());
}

TEST(Xyz, CommentWithOtherColumnCountIsNoHeader) {
  auto doc = read_text("# x y z\n1 2 3 0 0 1\n");
  EXPECT_EQ(doc.header["header"], "none");
  EXPECT_TRUE(doc.cloud.has_normals());
}

TEST(Xyz, OriginFromFirstPoint) {
  auto c = read_text("500123.25 4100000.5 10\n500124.25 4100001.5 11\n").cloud;
  EXPECT_EQ(c.origin, (std::array<double, 3>{500000, 4100000, 0}));
  EXPECT_EQ(c.positions[0], (Vec3f{123.25f, 0.5f, 10}));
  EXPECT_EQ(c.positions[1], (Vec3f{124.25f, 1.5f, 11}));
}

TEST(Xyz, ColumnNamesAreValidUtf8) {
  auto c = read_text("x y z temp\xe9 \xc3\xa9t\xc3\xa9\n1 2 3 4 5\n").cloud;
  ASSERT_EQ(c.extras.size(), 2u);
  EXPECT_EQ(c.extras[0].name, "temp?");              // Latin-1 byte: not UTF-8
  EXPECT_EQ(c.extras[1].name, "\xc3\xa9t\xc3\xa9");  // UTF-8 kept
  EXPECT_NO_THROW((void)read_text("x y z \xed\xa0\x80\n1 2 3 4\n").header.dump());  // surrogate
}

TEST(Xyz, EmptyAndHeaderOnly) {
  EXPECT_EQ(read_text("").cloud.size(), 0u);
  EXPECT_EQ(read_text("x y z\n").cloud.size(), 0u);
}

TEST(Xyz, Errors) {
  expect_error("1 2 3\n4 5\n", ErrorKind::kBadInput, "line 2: expected 3 columns, found 2");
  expect_error("1 2 3\n4 five 6\n", ErrorKind::kBadInput,
               "line 2: column 2 (y): not a number: 'five'");
  expect_error("1 2 3\nnan 5 6\n", ErrorKind::kBadInput, "line 2: NaN or infinite coordinate");
  expect_error("1 2 3\n4 inf 6\n", ErrorKind::kBadInput, "NaN or infinite coordinate");
  expect_error("x y z nx ny nz\n1 2 3 nan 0 1\n", ErrorKind::kBadInput, "NaN or infinite normal");
  expect_error("x y z r g b\n1 2 3 256 0 0\n", ErrorKind::kBadInput,
               "out of range (integers 0-255)");
  expect_error("x y z r g b\n1 2 3 1.5 0 0\n", ErrorKind::kBadInput, "out of range");
  expect_error("3\n1 2 3\n", ErrorKind::kBadInput,
               "PTS header line says 3 points but the file has 1");
  expect_error("1 2\n", ErrorKind::kBadInput, "line 1: expected at least 3 columns");
  expect_error("a b c\n1 2 3\n", ErrorKind::kBadInput,
               "no x, y and z columns in the header (line 1)");
  expect_error("x y z nx\n1 2 3 4\n", ErrorKind::kBadInput,
               "incomplete normal (need nx, ny and nz) in the header (line 1)");
  expect_error("x y z r g\n1 2 3 4 5\n", ErrorKind::kBadInput, "incomplete colour");
  expect_error("x y z x\n1 2 3 4\n", ErrorKind::kBadInput, "column 'x' named twice");
  expect_error("1 2 3\n", ErrorKind::kUsage, "no x, y and z columns in the --columns option",
               "x,y");
  expect_error("x y z radius\n1 2 3 -1\n", ErrorKind::kBadInput, "radius must be finite and >= 0");
}

TEST(Xyz, WriterExactBytes) {
  SplatCloud c;
  c.positions = {{0.1f, 2, -3}, {1e-3f, 0, 1}};
  c.normals = {{0, 0, 1}, {0.6f, 0.8f, 0}};
  c.colors = {{255, 0, 7}, {1, 2, 3}};
  c.extras.push_back({"my field", ScalarType::kFloat64, {0.25, -1}});
  const std::string path = temp_path("w.xyz");
  {
    OutputFile out(path);
    write_xyz(c, out);
    out.commit();
  }
  EXPECT_EQ(slurp(path),
            "# x y z nx ny nz r g b my_field\n"
            "0.1 2 -3 0 0 1 255 0 7 0.25\n"
            "0.001 0 1 0.6 0.8 0 1 2 3 -1\n");
}

// A .csv name through write_cloud: commas under a header line of names (spreadsheets split the
// columns), read back to the same cloud.
TEST(Xyz, CsvWriterUsesCommasAndReadsBack) {
  LoadedCloud doc;
  doc.cloud.positions = {{0.1f, 2, -3}, {1e-3f, 0, 1}};
  doc.cloud.normals = {{0, 0, 1}, {0.6f, 0.8f, 0}};
  doc.cloud.radii = {0.5f, 0.25f};
  doc.cloud.extras.push_back({"my field", ScalarType::kFloat64, {0.25, -1}});
  const std::string path = temp_path("w.csv");
  write_cloud(doc, path);
  EXPECT_EQ(slurp(path),
            "x,y,z,nx,ny,nz,radius,my_field\n"
            "0.1,2,-3,0,0,1,0.5,0.25\n"
            "0.001,0,1,0.6,0.8,0,0.25,-1\n");
  const LoadedCloud back = read_cloud(path);
  EXPECT_EQ(back.cloud.positions, doc.cloud.positions);
  EXPECT_EQ(back.cloud.normals, doc.cloud.normals);
  EXPECT_EQ(back.cloud.radii, doc.cloud.radii);
  ASSERT_NE(back.cloud.find_extra("my_field"), nullptr);
  EXPECT_EQ(back.cloud.find_extra("my_field")->values[1], -1.0);
}

TEST(Xyz, RoundTripWithOrigin) {
  SplatCloud c;
  c.origin = {500000, 4100000, 0};
  c.positions = {{123.123f, 0.5f, 10.1f}, {-7.77f, 999.999f, 0.001f}};
  c.radii = {0.5f, 0.25f};
  c.colors = {{65535, 0, 32768}, {257, 0, 0}};
  c.color_bits = 16;
  const std::string path = temp_path("rt.xyz");
  {
    OutputFile out(path);
    write_xyz(c, out);
    out.commit();
  }
  InputStream in(path);
  auto back = read_xyz(in).cloud;
  EXPECT_EQ(back.origin, c.origin);
  EXPECT_EQ(back.positions, c.positions);
  EXPECT_EQ(back.radii, c.radii);
  EXPECT_EQ(back.color_bits, 8);
  EXPECT_EQ(back.colors[0], (std::array<uint16_t, 3>{255, 0, 128}));
  EXPECT_EQ(back.colors[1], (std::array<uint16_t, 3>{1, 0, 0}));
  // Shortest decimals: no float noise in the file.
  EXPECT_NE(slurp(path).find("500123.123 4100000.5 10.1"), std::string::npos) << slurp(path);
}

}  // namespace
}  // namespace splatkit
