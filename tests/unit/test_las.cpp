#include "formats/las.h"

#include <gtest/gtest.h>

#include "test_format_support.h"

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "formats/read_cloud.h"
#include "formats/write_cloud.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

// A tiny LAS writer with every field at its offset from the LAS 1.4 R15 tables, so that the
// reader is checked against the specification's byte layout and not against itself.
struct LasPoint {
  int32_t x = 0, y = 0, z = 0;
  uint16_t intensity = 0;
  uint8_t ret = 1, nret = 1, cls = 0;
  int angle = 0;  // int8 degrees (formats 0-3) or int16 0.006-degree steps (6-8)
  uint8_t user = 0;
  uint16_t source = 0;
  double gps = 0;
  uint16_t r = 0, g = 0, b = 0, nir = 0;
};

struct LasSpec {
  int major = 1, minor = 2;
  int format = 0;
  int format_byte = -1;       // raw point format byte when >= 0 (LAZ bits, unknown formats)
  int record_length = -1;     // -1: the format's minimum
  int header_size = -1;       // -1: the version's size
  int64_t point_offset = -1;  // -1: right after the VLRs
  int64_t legacy_count = -1, count = -1;
  double scale[3] = {0.01, 0.01, 0.01};
  double offset[3] = {0, 0, 0};
  std::vector<std::string> vlrs;  // payloads
  std::vector<std::string> evlrs;
  int vlr_length_bias = 0;  // added to the first VLR's declared length
  std::string trailing;
  std::vector<LasPoint> points;
};

void put(std::string& s, std::size_t at, const void* v, std::size_t n) {
  if (s.size() < at + n) s.resize(at + n, '\0');
  std::memcpy(s.data() + at, v, n);  // the test machine is little-endian like LAS
}
template <class T>
void put(std::string& s, std::size_t at, T v) {
  put(s, at, &v, sizeof v);
}

const int kMinLength[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

std::string encode_point(const LasSpec& spec, const LasPoint& p) {
  const int f = spec.format;
  std::string r(
      static_cast<std::size_t>(spec.record_length >= 0 ? spec.record_length : kMinLength[f]),
      '\x5a');  // filler: extra bytes must be skipped
  put(r, 0, p.x);
  put(r, 4, p.y);
  put(r, 8, p.z);
  put(r, 12, p.intensity);
  if (f < 6) {
    put(r, 14, static_cast<uint8_t>(p.ret | p.nret << 3));
    put(r, 15, static_cast<uint8_t>(p.cls | 0x80));  // withheld flag set: must not leak into class
    put(r, 16, static_cast<int8_t>(p.angle));
    put(r, 17, p.user);
    put(r, 18, p.source);
    if (f == 1 || f == 3) put(r, 20, p.gps);
    const std::size_t c = f == 2 ? 20 : 28;
    if (f == 2 || f == 3) put(r, c, p.r), put(r, c + 2, p.g), put(r, c + 4, p.b);
  } else {
    put(r, 14, static_cast<uint8_t>(p.ret | p.nret << 4));
    put(r, 15, static_cast<uint8_t>(0));
    put(r, 16, p.cls);
    put(r, 17, p.user);
    put(r, 18, static_cast<int16_t>(p.angle));
    put(r, 20, p.source);
    put(r, 22, p.gps);
    if (f >= 7) put(r, 30, p.r), put(r, 32, p.g), put(r, 34, p.b);
    if (f == 8) put(r, 36, p.nir);
  }
  return r;
}

std::string make_las(const LasSpec& spec) {
  const int hs = spec.header_size >= 0 ? spec.header_size
                 : spec.minor >= 4     ? 375
                 : spec.minor == 3     ? 235
                                       : 227;
  std::string s;
  put(s, 0, "LASF", 4);
  put(s, 24, static_cast<uint8_t>(spec.major));
  put(s, 25, static_cast<uint8_t>(spec.minor));
  put(s, 26, "splatkit test", 13);
  put(s, 58, "test_las.cpp", 12);
  put(s, 90, uint16_t{200});
  put(s, 92, uint16_t{2024});
  put(s, 94, static_cast<uint16_t>(hs));
  std::size_t vlr_bytes = 0;
  for (const auto& v : spec.vlrs) vlr_bytes += 54 + v.size();
  const uint32_t offset = static_cast<uint32_t>(
      spec.point_offset >= 0 ? spec.point_offset : hs + static_cast<int64_t>(vlr_bytes));
  put(s, 96, offset);
  put(s, 100, static_cast<uint32_t>(spec.vlrs.size()));
  put(s, 104, static_cast<uint8_t>(spec.format_byte >= 0 ? spec.format_byte : spec.format));
  put(s, 105,
      static_cast<uint16_t>(spec.record_length >= 0 ? spec.record_length
                                                    : kMinLength[spec.format]));
  const uint64_t n = spec.count >= 0 ? static_cast<uint64_t>(spec.count) : spec.points.size();
  const uint32_t legacy = spec.legacy_count >= 0 ? static_cast<uint32_t>(spec.legacy_count)
                          : spec.format >= 6     ? 0
                                                 : static_cast<uint32_t>(n);
  put(s, 107, legacy);
  for (int k = 0; k < 3; ++k) {
    put(s, 131 + 8 * k, spec.scale[k]);
    put(s, 155 + 8 * k, spec.offset[k]);
    put(s, 179 + 16 * k, 100.0 + k);  // max
    put(s, 187 + 16 * k, -1.0 - k);   // min
  }
  s.resize(static_cast<std::size_t>(std::max(hs, 227)), '\0');
  std::string points;
  for (const auto& p : spec.points) points += encode_point(spec, p);
  if (spec.minor >= 4 && hs >= 375) {
    put(s, 243, static_cast<uint32_t>(spec.evlrs.size()));
    put(s, 235, static_cast<uint64_t>(spec.evlrs.empty() ? 0 : offset + points.size()));
    put(s, 247, n);
  }
  s.resize(static_cast<std::size_t>(hs));
  for (std::size_t i = 0; i < spec.vlrs.size(); ++i) {
    std::string h(54, '\0');
    put(h, 2, "LASF_Projection", 15);
    put(h, 18, uint16_t{34735});
    put(h, 20, static_cast<uint16_t>(spec.vlrs[i].size() + (i == 0 ? spec.vlr_length_bias : 0)));
    s += h + spec.vlrs[i];
  }
  if (s.size() < offset) s.resize(offset, '\0');
  s += points;
  for (const auto& e : spec.evlrs) {
    std::string h(60, '\0');
    put(h, 2, "LASF_Spec", 9);
    put(h, 20, static_cast<uint64_t>(e.size()));
    s += h + e;
  }
  return s + spec.trailing;
}

LoadedCloud read_bytes(const std::string& s) {
  InputStream in("t.las", s.data(), s.size());
  return read_las(in);
}

void expect_error(const std::string& s, ErrorKind kind, const std::string& phrase) {
  test::expect_read_error([&] { read_bytes(s); }, kind, phrase);
}

std::vector<LasPoint> two_points() {
  LasPoint a;
  a.x = 100, a.y = -200, a.z = 300;
  a.intensity = 1000, a.ret = 1, a.nret = 2, a.cls = 2, a.angle = -15, a.user = 7, a.source = 42;
  a.gps = 123456.5, a.r = 65535, a.g = 256, a.b = 0, a.nir = 999;
  LasPoint b;
  b.x = -1, b.y = 0, b.z = 1;
  b.intensity = 65535, b.ret = 2, b.nret = 2, b.cls = 6, b.angle = 30, b.user = 0, b.source = 1;
  b.gps = -0.25, b.r = 1, b.g = 2, b.b = 3, b.nir = 0;
  return {a, b};
}

double extra(const SplatCloud& c, const char* name, std::size_t i) {
  const ExtraAttribute* e = c.find_extra(name);
  if (!e) {
    ADD_FAILURE() << "no extra " << name;
    return -1e300;
  }
  return e->values.at(i);
}

void check_format(int minor, int format) {
  SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format));
  LasSpec spec;
  spec.minor = minor;
  spec.format = format;
  spec.points = two_points();
  if (format >= 6) spec.points[0].nret = 9, spec.points[0].ret = 8, spec.points[0].cls = 40;
  if (format >= 6) spec.points[0].angle = -2500;
  auto doc = read_bytes(make_las(spec));
  const auto& c = doc.cloud;
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.origin, (std::array<double, 3>{0, 0, 0}));
  EXPECT_EQ(c.positions[0], (Vec3f{1, -2, 3}));
  EXPECT_EQ(c.positions[1], (Vec3f{-0.01f, 0, 0.01f}));
  EXPECT_EQ(extra(c, "intensity", 0), 1000);
  EXPECT_EQ(extra(c, "intensity", 1), 65535);
  EXPECT_EQ(extra(c, "return_number", 0), format >= 6 ? 8 : 1);
  EXPECT_EQ(extra(c, "number_of_returns", 0), format >= 6 ? 9 : 2);
  EXPECT_EQ(extra(c, "classification", 0), format >= 6 ? 40 : 2);
  EXPECT_EQ(extra(c, "classification", 1), 6);
  EXPECT_EQ(extra(c, "scan_angle", 0), format >= 6 ? static_cast<double>(-2500 * 0.006f) : -15);
  EXPECT_EQ(c.find_extra("scan_angle")->type(),
            format >= 6 ? ScalarType::kFloat32 : ScalarType::kInt8);
  EXPECT_EQ(extra(c, "user_data", 0), 7);
  EXPECT_EQ(extra(c, "point_source_id", 0), 42);
  const bool gps = format == 1 || format == 3 || format >= 6;
  EXPECT_EQ(c.find_extra("gps_time") != nullptr, gps);
  if (gps) {
    EXPECT_EQ(extra(c, "gps_time", 0), 123456.5);
    EXPECT_EQ(extra(c, "gps_time", 1), -0.25);
  }
  const bool rgb = format == 2 || format == 3 || format == 7 || format == 8;
  EXPECT_EQ(c.has_colors(), rgb);
  if (rgb) {
    EXPECT_EQ(c.color_bits, 16);
    EXPECT_EQ(c.colors[0], (std::array<uint16_t, 3>{65535, 256, 0}));
    EXPECT_EQ(c.colors[1], (std::array<uint16_t, 3>{1, 2, 3}));
  }
  EXPECT_EQ(c.find_extra("nir") != nullptr, format == 8);
  if (format == 8) {
    EXPECT_EQ(extra(c, "nir", 0), 999);
  }
  EXPECT_EQ(doc.header["version"], "1." + std::to_string(minor));
  EXPECT_EQ(doc.header["point_format"], format);
  EXPECT_EQ(doc.header["count"], 2);
  EXPECT_EQ(doc.header["system_identifier"], "splatkit test");
  EXPECT_EQ(doc.header["generating_software"], "test_las.cpp");
  EXPECT_EQ(doc.header["creation_date"]["year"], 2024);
  EXPECT_EQ(doc.header["bounds"]["max"][2], 102.0);
  EXPECT_EQ(doc.header["bounds"]["min"][1], -2.0);
  c.check_consistent();
}

TEST(Las, EveryFormatAndVersion) {
  for (int minor : {0, 1, 2, 3, 4})
    for (int format : {0, 1, 2, 3}) check_format(minor, format);
  for (int format : {6, 7, 8}) check_format(4, format);
}

TEST(Las, PinnedBytesOfTheSmallestFile) {
  LasSpec spec;
  spec.points.resize(1);
  spec.points[0].x = 1;
  const std::string s = make_las(spec);
  ASSERT_EQ(s.size(), 247u);
  // The point record: X=1 Y=0 Z=0, intensity 0, returns 1/1, class 0 (+withheld), angle, user, src.
  EXPECT_EQ(s.substr(227), std::string("\x01\0\0\0\0\0\0\0\0\0\0\0\0\0\x09\x80\0\0\0\0", 20));
  EXPECT_EQ(read_bytes(s).cloud.positions[0], (Vec3f{0.01f, 0, 0}));
}

// A cloud that did not come from LAS (no return extras) is written with each point its own
// single return (return number 0 is not valid LAS), and the header counts them as first returns.
TEST(Las, WrittenWithoutReturnsEachPointIsASingleReturn) {
  for (const char* name : {"r.las", "r6.las"}) {
    LoadedCloud doc;
    doc.cloud.positions = {{0, 0, 0}, {1, 2, 3}, {4, 5, 6}};
    WriteOptions w;
    w.las_format = name[1] == '6' ? 6 : -1;
    const std::string path = test::temp_path("las", name);
    write_cloud(doc, path, w);
    const LoadedCloud back = read_cloud(path);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(back.cloud.find_extra("return_number")->values[i], 1.0) << name;
      EXPECT_EQ(back.cloud.find_extra("number_of_returns")->values[i], 1.0) << name;
    }
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> b((std::istreambuf_iterator<char>(in)), {});
    const std::size_t at = w.las_format == 6 ? 255 : 111;  // points by return, the first
    ASSERT_GT(b.size(), at + 4);
    EXPECT_EQ(b[at], 3) << name;
  }
}

// Return numbers without their counts: each point gets the fewest returns that hold its number
// (return 3 of 3, not of 1, which LAS readers take for a broken record); counts the cloud has are
// written as they are.
TEST(Las, WrittenWithReturnNumbersOnlyCountsAtLeastThatMany) {
  for (const bool counts : {false, true})
    for (const char* name : {"k.las", "k6.las"}) {
      LoadedCloud doc;
      doc.cloud.positions = {{0, 0, 0}, {1, 2, 3}, {4, 5, 6}};
      doc.cloud.extras.emplace_back("return_number", ScalarType::kUInt8,
                                    std::vector<double>{3, 1, 0});
      // Counts the cloud has are kept as they are, even below the return number.
      if (counts)
        doc.cloud.extras.emplace_back("number_of_returns", ScalarType::kUInt8,
                                      std::vector<double>{2, 4, 1});
      WriteOptions w;
      w.las_format = name[1] == '6' ? 6 : -1;
      const std::string path = test::temp_path("las", name);
      write_cloud(doc, path, w);
      const LoadedCloud back = read_cloud(path);
      const double want_ret[] = {3, 1, 0},
                   want_rets[] = {counts ? 2.0 : 3.0, counts ? 4.0 : 1.0, 1};
      for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(back.cloud.find_extra("return_number")->values[i], want_ret[i]) << name << i;
        EXPECT_EQ(back.cloud.find_extra("number_of_returns")->values[i], want_rets[i])
            << name << i << counts;
      }
    }
}

// The creation date is never 0/0 and never today: $SOURCE_DATE_EPOCH's UTC date when set, else
// day 1 of 2000, so that two runs write the same bytes (LAS and LAZ, 1.2 and 1.4).
TEST(Las, WrittenWithADeterministicCreationDate) {
  const char* saved = std::getenv("SOURCE_DATE_EPOCH");
  const std::string keep = saved ? saved : "";
  for (const char* epoch : {"", "1700000000", "not a number"})
    for (const char* name : {"d.las", "d.laz", "d6.las"}) {
      if (*epoch)
        ::setenv("SOURCE_DATE_EPOCH", epoch, 1);
      else
        ::unsetenv("SOURCE_DATE_EPOCH");
      LoadedCloud doc;
      doc.cloud.positions = {{0, 0, 0}, {1, 2, 3}};
      WriteOptions w;
      w.las_format = name[1] == '6' ? 6 : -1;
      const std::string path = test::temp_path("las", name);
      write_cloud(doc, path, w);
      const LoadedCloud back = read_cloud(path);
      const bool set = std::string(epoch) == "1700000000";  // 2023-11-14, day 318
      EXPECT_EQ(back.header["creation_date"]["year"], set ? 2023 : 2000) << name << epoch;
      EXPECT_EQ(back.header["creation_date"]["day_of_year"], set ? 318 : 1) << name << epoch;
    }
  if (saved)
    ::setenv("SOURCE_DATE_EPOCH", keep.c_str(), 1);
  else
    ::unsetenv("SOURCE_DATE_EPOCH");
}

TEST(Las, ScaleOffsetAndOrigin) {
  LasSpec spec;
  spec.offset[0] = 500000;
  spec.offset[1] = 4100000;
  spec.scale[2] = 0.001;
  spec.points.resize(2);
  spec.points[0].x = 12345, spec.points[0].y = 50, spec.points[0].z = 1500;
  spec.points[1].x = -12345, spec.points[1].y = 0, spec.points[1].z = 0;
  auto c = read_bytes(make_las(spec)).cloud;
  EXPECT_EQ(c.origin, (std::array<double, 3>{500000, 4100000, 0}));
  EXPECT_EQ(c.positions[0], (Vec3f{123.45f, 0.5f, 1.5f}));
  EXPECT_EQ(c.positions[1], (Vec3f{-123.45f, 0, 0}));
}

TEST(Las, ExtraBytesVlrsAndEvlrs) {
  LasSpec spec;
  spec.minor = 4;
  spec.format = 6;
  spec.record_length = 30 + 5;
  spec.vlrs = {std::string(10, 'v'), ""};
  spec.evlrs = {"12345"};
  spec.points = two_points();
  auto doc = read_bytes(make_las(spec));
  EXPECT_EQ(doc.cloud.positions[1], (Vec3f{-0.01f, 0, 0.01f}));
  EXPECT_EQ(doc.header["vlr_count"], 2);
  EXPECT_EQ(doc.header["vlrs"][0], "LASF_Projection/34735");
  EXPECT_EQ(doc.header["evlr_count"], 1);
  EXPECT_EQ(doc.header["record_length"], 35);
}

TEST(Las, PaddingBeforePointData) {
  LasSpec spec;
  spec.point_offset = 227 + 16;
  spec.points = two_points();
  EXPECT_EQ(read_bytes(make_las(spec)).cloud.size(), 2u);
}

TEST(Las, ZeroPoints) {
  LasSpec spec;
  EXPECT_EQ(read_bytes(make_las(spec)).cloud.size(), 0u);
}

TEST(Las, StreamsFromAFileInBlocks) {
  LasSpec spec;
  spec.format = 3;
  for (int i = 0; i < 10000; ++i) {
    LasPoint p;
    p.x = i, p.y = -i, p.z = i % 7, p.r = static_cast<uint16_t>(i);
    spec.points.push_back(p);
  }
  auto dir =
      std::filesystem::path(testing::TempDir()) / ("splatkit_las_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "big.las").string();
  std::ofstream(path, std::ios::binary) << make_las(spec);
  InputStream in(path, 4096);
  auto c = read_las(in).cloud;
  ASSERT_EQ(c.size(), 10000u);
  EXPECT_EQ(c.positions[9999], (Vec3f{99.99f, -99.99f, 0.03f}));
  EXPECT_EQ(c.colors[4097][0], 4097);
}

// A cloud that did not come from LAS gets a scale per axis fine enough for its extent: degrees of
// longitude and latitude beside heights in metres keep centimetres, not 0.001 degrees (100 m).
TEST(Las, WrittenScaleFollowsEachAxisExtent) {
  LoadedCloud doc;
  for (int i = 0; i < 1000; ++i)
    doc.cloud.positions.push_back({-122.0f + 0.01f * static_cast<float>(i) / 1000,
                                   47.0f + 0.01f * static_cast<float>(i % 37) / 37,
                                   100.0f + static_cast<float>(i % 101)});
  const std::string path = test::temp_path("las", "lonlat.las");
  write_cloud(doc, path);
  const LoadedCloud back = read_cloud(path);
  EXPECT_EQ(back.header["scale"][0].get<double>(), 1e-7);
  EXPECT_EQ(back.header["scale"][1].get<double>(), 1e-7);
  EXPECT_EQ(back.header["scale"][2].get<double>(), 1e-3);  // 100 m of heights: millimetres
  ASSERT_EQ(back.cloud.size(), doc.cloud.size());
  double worst = 0;
  for (std::size_t i = 0; i < doc.cloud.size(); ++i)
    for (int k = 0; k < 2; ++k)
      worst = std::max(worst,
                       std::abs(double{back.cloud.positions[i][k] + float(back.cloud.origin[k])} -
                                double{doc.cloud.positions[i][k]}));
  EXPECT_LT(worst, 2e-5);  // float32 at 122 degrees: 7.6e-6
}

TEST(Las, Errors) {
  LasSpec ok;
  ok.points = two_points();
  const std::string good = make_las(ok);
  auto with = [&](auto edit) {
    LasSpec s = ok;
    edit(s);
    return make_las(s);
  };
  const auto bad = ErrorKind::kBadInput, unsupported = ErrorKind::kUnsupported;
  expect_error(good.substr(0, 100), bad, "unexpected end of file while reading LAS header");
  expect_error("LASX" + good.substr(4), bad, "not a LAS file (no LASF signature)");
  expect_error(with([](LasSpec& s) { s.major = 2, s.minor = 0; }), unsupported,
               "LAS version 2.0 is not supported (1.0-1.4 are)");
  expect_error(with([](LasSpec& s) { s.minor = 5; }), unsupported,
               "LAS version 1.5 is not supported");
  expect_error(with([](LasSpec& s) { s.header_size = 200; }), bad,
               "header size 200 is smaller than the 227 bytes of a LAS 1.2 header");
  expect_error(with([](LasSpec& s) { s.minor = 4, s.header_size = 235; }), bad,
               "header size 235 is smaller than the 375 bytes of a LAS 1.4 header");
  // The LAZ bit without a LASzip VLR (LAZ itself: tests/e2e/laz.sh); bit 6, an old mark.
  expect_error(with([](LasSpec& s) { s.format_byte = 0x80; }), bad,
               "compressed LAS (LAZ) without the LASzip VLR");
  expect_error(with([](LasSpec& s) { s.format_byte = 0x40; }), unsupported, "has bit 6 set");
  for (int f : {4, 5, 9, 10})
    expect_error(with([f](LasSpec& s) { s.minor = 4, s.format_byte = f, s.record_length = 80; }),
                 unsupported, "LAS point data format " + std::to_string(f) + " (with waveform");
  expect_error(with([](LasSpec& s) { s.format_byte = 11; }), bad,
               "unknown LAS point data format 11");
  expect_error(with([](LasSpec& s) { s.format = 6; }), bad,
               "point data format 6 needs LAS 1.4, the file says 1.2");
  expect_error(with([](LasSpec& s) {
                 s.record_length = 19;
                 s.points.clear();
               }),
               bad, "point record length 19 is shorter than the 20 bytes of point data format 0");
  expect_error(with([](LasSpec& s) { s.point_offset = 100; }), bad,
               "offset to point data 100 lies inside the 227-byte header");
  {
    std::string s = good;
    put(s, 96, uint32_t{100000});
    expect_error(s, bad, "offset to point data 100000 is past the end of the file (267 bytes)");
  }
  expect_error(with([](LasSpec& s) { s.count = 3; }), bad,
               "header says 3 points of 20 bytes but only 40 bytes follow the point data offset");
  expect_error(with([](LasSpec& s) { s.count = 4000000000; }), bad,
               "header says 4000000000 points");
  expect_error(with([](LasSpec& s) { s.minor = 4, s.legacy_count = 1; }), bad,
               "legacy point count 1 disagrees with the 64-bit point count 2");
  expect_error(with([](LasSpec& s) { s.scale[0] = 0; }), bad,
               "x scale factor is zero or not finite");
  expect_error(with([](LasSpec& s) { s.offset[2] = std::numeric_limits<double>::infinity(); }), bad,
               "z offset is not finite");
  expect_error(with([](LasSpec& s) { s.vlrs = {"abc"}, s.vlr_length_bias = 50; }), bad,
               "VLR 0 of 1 extends past the offset to point data");
  expect_error(with([](LasSpec& s) { s.vlrs = {"abc"}, s.point_offset = 227 + 20; }), bad,
               "VLR 0 of 1 extends past the offset to point data");
  expect_error(with([](LasSpec& s) { s.trailing = "junk"; }), bad,
               "byte 267: 4 bytes of trailing data after the last point record");
  expect_error(with([](LasSpec& s) { s.minor = 4, s.evlrs = {"x"}, s.trailing = "!"; }), bad,
               "1 bytes of trailing data after the last EVLR");
  {
    std::string s = with([](LasSpec& sp) { sp.minor = 4, sp.evlrs = {"abc"}; });
    s.resize(s.size() - 1);
    expect_error(s, bad, "EVLR 0 of 1 claims 3 bytes, past the end of the file");
  }
  expect_error(with([](LasSpec& s) { s.scale[1] = 1e308, s.points[0].y = 2000000000; }), bad,
               "point record 0: coordinate overflows after scale and offset");
}

}  // namespace
}  // namespace splatkit
