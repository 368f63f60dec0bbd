// Readers facing hostile or careless input: headers with 100k+ properties, elements or columns
// (refused beyond kMaxAttributes, parsed in linear time up to it: the e2e test hostile_readers.sh
// bounds the time), millions of .splk chunks, numbers beyond float range, empty input, and text on
// a pipe.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <utility>

#include "formats/off.h"
#include "formats/ply.h"
#include "formats/read_cloud.h"
#include "formats/splk.h"
#include "formats/xyz.h"
#include "splatkit/crc32c.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"
#include "test_format_support.h"

namespace splatkit {
namespace {

using test::expect_read_error;

LoadedCloud read_text(const std::string& name, const std::string& text,
                      const ReadOptions& options = {}) {
  InputStream in(name, text.data(), text.size());
  return read_cloud(in, options);
}

// --- headers of many properties, elements, columns ---

// A binary PLY whose vertex element has x y z and `extra` uchar properties, one vertex.
std::string wide_ply(std::size_t extra) {
  std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n";
  s += "property float x\nproperty float y\nproperty float z\n";
  for (std::size_t i = 0; i < extra; ++i) s += "property uchar p" + std::to_string(i) + "\n";
  s += "end_header\n";
  const float xyz[3] = {1.5f, -2.0f, 3.25f};
  s.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  for (std::size_t i = 0; i < extra; ++i) s += static_cast<char>(i % 251);
  return s;
}

TEST(FormatsHostileInput, PlyWithHundredThousandPropertiesIsRejectedClearly) {
  expect_read_error([] { read_text("wide.ply", wide_ply(100000)); }, ErrorKind::kBadInput,
                    "line 16388: more than 16384 properties in element 'vertex'");
}

TEST(FormatsHostileInput, PlyAtThePropertyLimitLoadsEveryOne) {
  constexpr std::size_t kExtra = kMaxAttributes - 3;
  const LoadedCloud doc = read_text("wide.ply", wide_ply(kExtra));
  ASSERT_EQ(doc.cloud.size(), 1u);
  EXPECT_EQ(doc.cloud.positions[0].z, 3.25f);
  ASSERT_EQ(doc.cloud.extras.size(), kExtra);
  EXPECT_EQ(doc.cloud.extras[kExtra - 1].name, "p" + std::to_string(kExtra - 1));
  EXPECT_EQ(doc.cloud.extras[kExtra - 1].values.at(0), static_cast<double>((kExtra - 1) % 251));
  EXPECT_EQ(doc.header["elements"][0]["properties"].size(), kExtra + 3);
}

TEST(FormatsHostileInput, PlyDuplicatePropertyFarApartIsStillFound) {
  std::string s = wide_ply(16000);
  s.insert(s.find("end_header"), "property uchar p123\n");
  expect_read_error([&] { read_text("dup.ply", s); }, ErrorKind::kBadInput,
                    "duplicate property 'p123' in element 'vertex'");
}

// An ASCII PLY of two vertices and `elements` further empty elements.
std::string many_element_ply(std::size_t elements) {
  std::string s =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\n";
  for (std::size_t i = 0; i < elements; ++i)
    s += "element e" + std::to_string(i) + " 0\nproperty int v\n";
  return s + "end_header\n1 2 3\n4 5 6\n";
}

TEST(FormatsHostileInput, PlyWithHundredThousandElementsIsRejectedClearly) {
  expect_read_error([] { read_text("many.ply", many_element_ply(100000)); }, ErrorKind::kBadInput,
                    "more than 16384 elements");
}

TEST(FormatsHostileInput, PlyAtTheElementLimitLoads) {
  std::string s = many_element_ply(kMaxAttributes - 1);
  const LoadedCloud doc = read_text("many.ply", s);
  EXPECT_EQ(doc.cloud.size(), 2u);
  EXPECT_EQ(doc.header["elements"].size(), kMaxAttributes);
  // The same name twice, thousands of elements apart.
  s = many_element_ply(10000);
  s.insert(s.find("end_header"), "element e0 0\n");
  expect_read_error([&] { read_text("many.ply", s); }, ErrorKind::kBadInput,
                    "duplicate element 'e0'");
}

std::string number_line(std::size_t columns) {
  std::string line;
  for (std::size_t i = 0; i < columns; ++i)
    line.append(std::to_string(i % 97)).append(i + 1 < columns ? " " : "\n");
  return line;
}

TEST(FormatsHostileInput, XyzWithHundredThousandColumnsIsRejectedClearly) {
  const std::string line = number_line(100000);
  expect_read_error([&] { read_text("wide.xyz", line + line); }, ErrorKind::kBadInput,
                    "100000 columns, more than the 16384 splatkit reads");
}

TEST(FormatsHostileInput, XyzAtTheColumnLimitKeepsThemAsExtras) {
  const std::string line = number_line(kMaxAttributes);
  const LoadedCloud doc = read_text("wide.xyz", line + line);
  ASSERT_EQ(doc.cloud.size(), 2u);
  ASSERT_EQ(doc.cloud.extras.size(), kMaxAttributes - 3);
  EXPECT_EQ(doc.cloud.extras.back().name, "column_" + std::to_string(kMaxAttributes));
  EXPECT_EQ(doc.cloud.extras.back().values[1], static_cast<double>((kMaxAttributes - 1) % 97));
}

// A CSV header of x,y,z and names a3, a4, ... (`columns` in all) and one row.
std::pair<std::string, std::string> named_csv(std::size_t columns) {
  std::string header = "x,y,z", row = "1,2,3";
  for (std::size_t i = 3; i < columns; ++i) {
    const std::string k = std::to_string(i);
    header.append(",a").append(k);
    row.append(",").append(k);
  }
  return {header, row};
}

TEST(FormatsHostileInput, CsvHeaderOfHundredThousandNamesIsRejectedClearly) {
  const auto csv = named_csv(100000);  // (no structured bindings: clang 14 cannot capture them)
  const std::string text = csv.first + "\n" + csv.second + "\n";
  expect_read_error([&] { read_text("wide.csv", text); }, ErrorKind::kBadInput,
                    "100000 columns, more than the 16384 splatkit reads");
}

TEST(FormatsHostileInput, CsvHeaderAtTheLimit) {
  const auto [header, row] = named_csv(kMaxAttributes);
  const LoadedCloud doc = read_text("wide.csv", header + "\n" + row + "\n");
  ASSERT_EQ(doc.cloud.extras.size(), kMaxAttributes - 3);
  EXPECT_EQ(doc.cloud.extras[10].name, "a13");
  EXPECT_EQ(doc.cloud.extras[10].values.at(0), 13.0);
  // A duplicate far from its twin is still a duplicate.
  const auto dup = named_csv(10000);
  const std::string dup_text = dup.first + ",a5\n" + dup.second + ",5\n";
  expect_read_error([&] { read_text("dup.csv", dup_text); }, ErrorKind::kBadInput,
                    "column 'a5' named twice");
}

// --- .splk files of very many chunks ---

void put_u32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }
void put_u64(std::string& s, uint64_t v) { s.append(reinterpret_cast<const char*>(&v), 8); }

// A valid .splk of one point followed by `empty` zero-byte private chunks "xprv".
std::string splk_with_empty_chunks(std::size_t empty) {
  LoadedCloud doc;
  doc.cloud.positions = {{1, 2, 3}};
  const std::string path = test::temp_path("hostile", "one.splk");
  {
    OutputFile out(path);
    write_splk(doc, out);
    out.commit();
  }
  std::string s = test::slurp(path);
  const std::string end = s.substr(s.size() - 20);  // the END chunk header
  s.resize(s.size() - 20);
  for (std::size_t i = 0; i < empty; ++i) {
    s += "xprv";
    put_u32(s, 0);  // flags
    put_u64(s, 0);  // size
    put_u32(s, 0);  // CRC-32C of nothing
  }
  return s + end;
}

TEST(FormatsHostileInput, SplkCarriesThousandsOfEmptyChunks) {
  const LoadedCloud doc = read_text("many.splk", splk_with_empty_chunks(5000));
  EXPECT_EQ(doc.chunks.size(), 5000u);
  EXPECT_EQ(doc.cloud.size(), 1u);
}

TEST(FormatsHostileInput, SplkOfMillionsOfChunksIsRejectedEarly) {
  expect_read_error([&] { read_text("huge.splk", splk_with_empty_chunks(1000000)); },
                    ErrorKind::kBadInput, "more than 65536 chunks");
}

// --- numbers beyond float range ---

TEST(FormatsHostileInput, XyzCoordinateBeyondFloatIsRejectedWithLineAndValue) {
  expect_read_error([] { read_text("big.xyz", "1 2 3\n1e39 0 0\n"); }, ErrorKind::kBadInput,
                    "line 2: coordinate '1e39' in column 1 (x) is beyond float range");
  expect_read_error([] { read_text("big.xyz", "1 2 3\n0 -1e300 0\n"); }, ErrorKind::kBadInput,
                    "line 2: coordinate '-1e300' in column 2 (y) is beyond float range");
  expect_read_error([] { read_text("n.xyz", "x y z nx ny nz\n0 0 0 0 0 1e39\n"); },
                    ErrorKind::kBadInput, "line 2: normal '1e39' in column 6");
  // Within range: the largest float still reads.
  EXPECT_EQ(read_text("max.xyz", "3.4028234e38 0 0\n").cloud.size(), 1u);
}

TEST(FormatsHostileInput, OffCoordinateBeyondFloatIsRejectedWithLineAndValue) {
  expect_read_error([] { read_text("big.off", "OFF\n2 0 0\n0 0 0\n1e39 1 1\n"); },
                    ErrorKind::kBadInput, "line 4: vertex 1: coordinate '1e39' is beyond float");
}

TEST(FormatsHostileInput, PlyCoordinateBeyondFloatIsRejectedWithLineAndValue) {
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n"
      "property double z\nend_header\n1 2 3\n";
  expect_read_error([&] { read_text("big.ply", head + "1e300 2 3\n"); }, ErrorKind::kBadInput,
                    "line 9: element 'vertex' row 1: coordinate 1e+300 is beyond float range");
  std::string f = head;
  for (const char* t : {"double x", "double y", "double z"}) f.replace(f.find(t), 6, "float");
  expect_read_error([&] { read_text("big.ply", f + "1e39 2 3\n"); }, ErrorKind::kBadInput,
                    "line 9: element 'vertex' row 1: value '1e39' is out of range for float");
}

TEST(FormatsHostileInput, PlyBinaryDoubleBeyondFloatNamesTheValue) {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n";
  const double v[6] = {1, 2, 3, 4, 5e300, 6};
  s.append(reinterpret_cast<const char*>(v), sizeof v);
  expect_read_error([&] { read_text("big.ply", s); }, ErrorKind::kBadInput,
                    "element 'vertex' row 1: coordinate 5e+300 is beyond float range");
}

// --- empty input and text on a pipe ---

TEST(FormatsHostileInput, EmptyInputIsBadInputWhateverItsName) {
  for (const char* name : {"-", "empty.xyz", "empty.ply", "empty.splk", "empty"})
    expect_read_error([&] { read_text(name, ""); }, ErrorKind::kBadInput, "file is empty");
}

TEST(FormatsHostileInput, WellFormedFileWithoutPointsGivesAnEmptyCloud) {
  EXPECT_EQ(read_text("h.csv", "x,y,z\n").cloud.size(), 0u);
  EXPECT_EQ(read_text("c.xyz", "# nothing here\n\n").cloud.size(), 0u);
  EXPECT_EQ(read_text("e.ply",
                      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n")
                .cloud.size(),
            0u);
}

TEST(FormatsHostileInput, TextColumnsOnStdinAreRecognisedByContent) {
  const LoadedCloud plain = read_text("-", "# scan\n1.5 2 3 0 10 20 30\n4 5 6 0 40 50 60\n");
  EXPECT_EQ(plain.format, "xyz");
  EXPECT_EQ(plain.cloud.size(), 2u);
  const LoadedCloud csv = read_text("-", "X,Y,Z,Intensity\n1,2,3,4\n");
  EXPECT_EQ(csv.format, "xyz");
  EXPECT_EQ(csv.cloud.size(), 1u);
  const LoadedCloud pts = read_text("-", "2\n1 2 3 4\n5 6 7 8\n");
  EXPECT_EQ(pts.cloud.size(), 2u);
  ReadOptions columns;
  columns.columns = "x,y,z,_,r,g,b";
  const LoadedCloud skip = read_text("-", "1 2 3 9 10 20 30\n", columns);
  EXPECT_TRUE(skip.cloud.has_colors());
  EXPECT_EQ(skip.cloud.colors[0][2], 30);
  // Binary bytes, or text that is not columns of numbers, stay unknown.
  expect_read_error([] { read_text("-", std::string("\x01\x02\x03 1 2 3\n", 10)); },
                    ErrorKind::kUnsupported, "unknown file format");
  expect_read_error([] { read_text("-", "hello world\nthis is prose\n"); }, ErrorKind::kUnsupported,
                    "unknown file format");
  // --columns says text even when the content does not look like it: the reader then explains.
  expect_read_error([&] { read_text("-", "hello world\nthis is prose\n", columns); },
                    ErrorKind::kBadInput, "expected 7 columns, found 3");
}

TEST(FormatsHostileInput, OffOnStdinIsRecognisedByContent) {
  const LoadedCloud doc = read_text("-", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(doc.format, "off");
  EXPECT_EQ(doc.cloud.face_count(), 1u);
}

TEST(FormatsHostileInput, LooksLikeTextColumnsOnlyTrustsCompleteValues) {
  EXPECT_TRUE(looks_like_text_columns("1 2 3\n", true));
  EXPECT_TRUE(looks_like_text_columns("1;2;3", true));
  EXPECT_FALSE(looks_like_text_columns("1 2\n", true));
  // A line cut by the end of the sniffed bytes: its last value may be partial.
  EXPECT_FALSE(looks_like_text_columns("1 2 3", false));
  EXPECT_TRUE(looks_like_text_columns("1 2 3 4", false));
  EXPECT_FALSE(looks_like_text_columns("x y z\nname value\n1 2 3\n", true));
}

}  // namespace
}  // namespace splatkit
