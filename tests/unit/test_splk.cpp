// .splk: round trips, pinned bytes of version 1.0, carried chunks, pipes, and one test per
// malformed case (formats/splk.md). Files are built byte by byte here, independently of the
// writer, so that the tests check the spec and not the writer against itself.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "formats/read_cloud.h"
#include "formats/splk.h"
#include "splatkit/crc32c.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"
#include "splatkit/output_file.h"

namespace splatkit {
namespace {

// --- building files by hand ---

std::string le(uint64_t v, int bytes) {
  std::string s;
  for (int i = 0; i < bytes; ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
  return s;
}
std::string f32(float v) { return le(std::bit_cast<uint32_t>(v), 4); }
std::string f64(double v) { return le(std::bit_cast<uint64_t>(v), 8); }

std::string file_header(uint16_t major = 1, uint16_t minor = 0, uint32_t flags = 0) {
  return std::string("\x89SPLK\r\n\x1A", 8) + le(major, 2) + le(minor, 2) + le(flags, 4);
}

uint32_t crc_of(const std::string& s) { return crc32c(0, s.data(), s.size()); }

std::string chunk(const std::string& type, uint32_t flags, const std::string& payload) {
  return type + le(flags, 4) + le(payload.size(), 8) + le(crc_of(payload), 4) + payload;
}

std::string end_chunk() { return chunk("END ", 1, ""); }

std::string column(const std::string& name, int kind, int type, int k, const std::string& data) {
  return le(name.size(), 2) + name + le(kind, 1) + le(type, 1) + le(k, 1) + data;
}

std::string position_column(const std::vector<Vec3f>& ps) {
  std::string d;
  for (const auto& p : ps) d += f32(p.x) + f32(p.y) + f32(p.z);
  return column("position", 0, 9, 3, d);
}

std::string splt(uint64_t n, const std::vector<std::string>& columns, uint32_t flags = 0,
                 std::array<double, 3> origin = {0, 0, 0}, std::array<double, 3> view = {0, 0, 0}) {
  std::string s = le(n, 8) + f64(origin[0]) + f64(origin[1]) + f64(origin[2]) + le(flags, 4) +
                  f64(view[0]) + f64(view[1]) + f64(view[2]) + le(columns.size(), 4);
  for (const auto& c : columns) s += c;
  return s;
}

std::string splt_chunk(const std::string& payload) { return chunk("SPLT", 3, payload); }
std::string one_point_splt() { return splt_chunk(splt(1, {position_column({{1, 2, 3}})})); }
std::string meta_chunk(const std::string& json = R"({"tool":"test"})") {
  return chunk("META", 0, json);
}

// The pinned tiny file, byte by byte (splk.md, "The smallest file").
std::string tiny_file() { return file_header() + meta_chunk() + one_point_splt() + end_chunk(); }

// --- running the reader and writer ---

LoadedCloud read_bytes(const std::string& bytes) {
  InputStream in("mem.splk", bytes.data(), bytes.size());
  return read_splk(in);
}

class SplkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "splk_" + std::to_string(::getpid()) + "_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    std::string cmd = "mkdir -p '" + dir_ + "'";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
  }
  void TearDown() override {
    std::string cmd = "rm -rf '" + dir_ + "'";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
  }
  std::string encode(const LoadedCloud& doc) {
    const std::string path = dir_ + "/out.splk";
    {
      OutputFile out(path);
      write_splk(doc, out);
      out.commit();
    }
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
  }
  std::string dir_;
};

// Expects read_splk to fail with `kind` and a message containing `what`.
void expect_rejected(const std::string& bytes, ErrorKind kind, const std::string& what) {
  try {
    read_bytes(bytes);
    ADD_FAILURE() << "accepted; expected: " << what;
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), kind) << e.what();
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("mem.splk: ", 0), 0u) << e.what();
  }
}

// A cloud with every attribute kind and an extra of every scalar type at its edge values.
LoadedCloud full_doc() {
  LoadedCloud doc;
  SplatCloud& c = doc.cloud;
  c.origin = {500000, 4000000, 100};
  c.positions = {{0.5f, -1.25f, 3}, {1e-7f, 2e7f, -0.0f}, {-3, 4, 5}};
  c.normals = {{0, 0, 1}, {1, 0, 0}, {0, -1, 0}};
  c.radii = {0.1f, 0.2f, 0.3f};
  c.colors = {{255, 0, 7}, {1, 2, 3}, {128, 64, 32}};
  c.color_bits = 8;
  auto extra = [&](const char* name, ScalarType t, std::vector<double> v) {
    c.extras.push_back({name, t, std::move(v)});
  };
  extra("i8", ScalarType::kInt8, {-128, 0, 127});
  extra("u8", ScalarType::kUInt8, {0, 1, 255});
  extra("i16", ScalarType::kInt16, {-32768, -1, 32767});
  extra("u16", ScalarType::kUInt16, {0, 40000, 65535});
  extra("i32", ScalarType::kInt32, {-2147483648.0, 7, 2147483647.0});
  extra("u32", ScalarType::kUInt32, {0, 3000000000.0, 4294967295.0});
  extra("i64", ScalarType::kInt64, {-9223372036854775808.0, -5, 9007199254740992.0});
  extra("u64", ScalarType::kUInt64, {0, 1, 9007199254740993.0 - 1});
  extra("f32", ScalarType::kFloat32, {0.25, -0x1p100, std::numeric_limits<double>::quiet_NaN()});
  extra("f64", ScalarType::kFloat64, {0.1, -1e300, std::numeric_limits<double>::infinity()});
  extra("normal", ScalarType::kFloat32, {1, 2, 3});  // separate name space from the core column
  c.face_offsets = {0, 3, 5};
  c.face_indices = {0, 1, 2, 2, 0};
  c.viewpoint = std::array<double, 3>{500001.5, 4000002.25, 150};
  doc.metadata = {{"tool", "test"}, {"counts", {{"points", 3}}}, {"z", {1, 2.5, "x"}}};
  return doc;
}

void expect_same_values(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::isnan(a[i]))
      EXPECT_TRUE(std::isnan(b[i])) << i;
    else
      EXPECT_EQ(a[i], b[i]) << i;
  }
}

// --- round trips ---

TEST(SplkMagic, RecognisesTheMagicAndDamagedForms) {
  EXPECT_TRUE(is_splk_magic(std::string("\x89SPLK\r\n\x1A\x01\x00", 10)));
  EXPECT_TRUE(is_splk_magic(std::string("\x09SPLK\r\n\x1A", 8)));  // 7-bit: read_splk explains
  EXPECT_FALSE(is_splk_magic("ply\nformat"));
  EXPECT_FALSE(is_splk_magic(std::string("\x89SPL", 4)));
  EXPECT_FALSE(is_splk_magic(""));
}

TEST_F(SplkTest, RoundTripKeepsEveryAttributeAndExtraType) {
  const LoadedCloud doc = full_doc();
  const LoadedCloud back = read_bytes(encode(doc));
  const SplatCloud &a = doc.cloud, &b = back.cloud;
  EXPECT_EQ(back.format, "splk");
  EXPECT_EQ(b.origin, a.origin);
  EXPECT_EQ(b.positions, a.positions);
  EXPECT_EQ(b.normals, a.normals);
  EXPECT_EQ(b.radii, a.radii);
  EXPECT_EQ(b.colors, a.colors);
  EXPECT_EQ(b.color_bits, 8);
  ASSERT_EQ(b.extras.size(), a.extras.size());
  for (std::size_t i = 0; i < a.extras.size(); ++i) {
    EXPECT_EQ(b.extras[i].name, a.extras[i].name);
    EXPECT_EQ(b.extras[i].type(), a.extras[i].type()) << a.extras[i].name;
    expect_same_values(b.extras[i].values.doubles(), a.extras[i].values.doubles());
  }
  EXPECT_EQ(b.face_offsets, a.face_offsets);
  EXPECT_EQ(b.face_indices, a.face_indices);
  EXPECT_EQ(b.viewpoint, a.viewpoint);
  EXPECT_EQ(back.metadata, doc.metadata);
  EXPECT_TRUE(back.chunks.empty());
  // -0.0f survives bit for bit, not just by value.
  EXPECT_TRUE(std::signbit(b.positions[1].z));
}

TEST_F(SplkTest, EllipsesRoundTripInAnElpsChunkOfVersion1_2) {
  LoadedCloud doc = full_doc();
  SplatCloud& c = doc.cloud;
  c.axes.clear();
  for (std::size_t i = 0; i < c.size(); ++i) {
    c.axes.push_back(normalized(cross(c.normals[i], Vec3f{0.3f, 0.5f, 0.8f})));
    c.minor_radii.push_back(0.5f * c.radii[i]);
  }
  const std::string bytes = encode(doc);
  EXPECT_EQ(bytes[10], 2);  // minor version
  const LoadedCloud back = read_bytes(bytes);
  EXPECT_EQ(back.cloud.axes, c.axes);
  EXPECT_EQ(back.cloud.minor_radii, c.minor_radii);
  EXPECT_TRUE(back.chunks.empty());
  // A second ELPS chunk, or one with another count, is refused: duplicate the chunk before END.
  const std::size_t at = bytes.find("ELPS");
  ASSERT_NE(at, std::string::npos);
  const std::size_t end = bytes.size() - 20;  // the END chunk header
  const std::string chunk = bytes.substr(at, end - at);
  expect_rejected(bytes.substr(0, end) + chunk + bytes.substr(end), ErrorKind::kBadInput,
                  "a second 'ELPS' chunk");
  // Fewer splats than ellipses: the SPLT of a one-splat copy with this file's ELPS.
  LoadedCloud one = doc;
  one.cloud = SplatCloud{};
  one.cloud.positions = {c.positions[0]};
  one.cloud.normals = {c.normals[0]};
  one.cloud.radii = {c.radii[0]};
  const std::string small = encode(one);
  const std::size_t small_end = small.size() - 20;
  expect_rejected(small.substr(0, small_end) + chunk + small.substr(small_end),
                  ErrorKind::kBadInput, "ellipses for 1 splats");
}

TEST_F(SplkTest, RoundTripKeeps16BitColoursAndNoOptionalAttributes) {
  LoadedCloud doc;
  doc.cloud.positions = {{1, 2, 3}, {4, 5, 6}};
  doc.cloud.colors = {{65535, 0, 4096}, {1, 257, 65534}};
  doc.cloud.color_bits = 16;
  LoadedCloud back = read_bytes(encode(doc));
  EXPECT_EQ(back.cloud.color_bits, 16);
  EXPECT_EQ(back.cloud.colors, doc.cloud.colors);
  EXPECT_FALSE(back.cloud.has_normals());
  EXPECT_FALSE(back.cloud.has_radii());
  EXPECT_FALSE(back.cloud.viewpoint.has_value());
  EXPECT_EQ(back.cloud.face_count(), 0u);
  EXPECT_TRUE(back.metadata.is_object());
  EXPECT_TRUE(back.metadata.empty());
}

TEST_F(SplkTest, EmptyCloudRoundTrips) {
  LoadedCloud doc;
  LoadedCloud back = read_bytes(encode(doc));
  EXPECT_EQ(back.cloud.size(), 0u);
}

TEST_F(SplkTest, ExtrasAreRoundedAndSaturatedToTheirType) {
  LoadedCloud doc;
  doc.cloud.positions = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  doc.cloud.extras.push_back(
      {"u8", ScalarType::kUInt8, {300, -4, 2.5, std::numeric_limits<double>::quiet_NaN()}});
  doc.cloud.extras.push_back({"i64", ScalarType::kInt64, {1e30, -1e30, -2.5, 0}});
  LoadedCloud back = read_bytes(encode(doc));
  EXPECT_EQ(back.cloud.extras[0].values.doubles(), (std::vector<double>{255, 0, 3, 0}));
  EXPECT_EQ(back.cloud.extras[1].values.doubles(),
            (std::vector<double>{9223372036854775807.0, -9223372036854775808.0, -3, 0}));
}

// --- pinned bytes ---

std::string read_source_file(const std::string& rel) {
  std::ifstream f(std::string(SPLATKIT_SOURCE_DIR) + "/" + rel, std::ios::binary);
  EXPECT_TRUE(f.good()) << rel;
  return std::string(std::istreambuf_iterator<char>(f), {});
}

LoadedCloud tiny_doc() {
  LoadedCloud doc;
  doc.cloud.positions = {{1, 2, 3}};
  doc.metadata = {{"tool", "test"}};
  return doc;
}

TEST_F(SplkTest, Version10TinyFileIsPinned) {
  const std::string pinned = read_source_file("tests/data/splk/tiny-v1.0.splk");
  EXPECT_EQ(pinned.size(), 180u);
  EXPECT_EQ(pinned, tiny_file()) << "the checked-in file no longer matches splk.md";
  EXPECT_EQ(encode(tiny_doc()), pinned) << "write_splk changed the 1.0 encoding";
  LoadedCloud back = read_bytes(pinned);
  ASSERT_EQ(back.cloud.size(), 1u);
  EXPECT_EQ(back.cloud.positions[0], (Vec3f{1, 2, 3}));
  EXPECT_EQ(back.metadata, tiny_doc().metadata);
}

// Every attribute and extra type, pinned: two encodes in one process would share what differs
// between processes (pointer order, uninitialised padding); the checked-in bytes do not. They were
// written by write_splk and decode to full_doc() below.
TEST_F(SplkTest, EveryAttributeDocumentIsPinned) {
  const std::string pinned = read_source_file("tests/data/splk/full-v1.0.splk");
  EXPECT_EQ(pinned.size(), 626u);
  EXPECT_EQ(encode(full_doc()), pinned) << "write_splk changed the 1.0 encoding";
  const LoadedCloud back = read_bytes(pinned);
  const LoadedCloud doc = full_doc();
  EXPECT_EQ(back.header["version"], "1.0");
  EXPECT_EQ(back.cloud.origin, doc.cloud.origin);
  EXPECT_EQ(back.cloud.positions, doc.cloud.positions);
  EXPECT_EQ(back.cloud.normals, doc.cloud.normals);
  EXPECT_EQ(back.cloud.radii, doc.cloud.radii);
  EXPECT_EQ(back.cloud.colors, doc.cloud.colors);
  ASSERT_EQ(back.cloud.extras.size(), doc.cloud.extras.size());
  for (std::size_t i = 0; i < doc.cloud.extras.size(); ++i) {
    EXPECT_EQ(back.cloud.extras[i].name, doc.cloud.extras[i].name);
    expect_same_values(back.cloud.extras[i].values.doubles(), doc.cloud.extras[i].values.doubles());
  }
  EXPECT_EQ(back.cloud.face_indices, doc.cloud.face_indices);
  EXPECT_EQ(back.cloud.viewpoint, doc.cloud.viewpoint);
  EXPECT_EQ(back.metadata, doc.metadata);
}

// 1.1 registered the graph chunks; a file holding one says 1.1, the others stay 1.0 byte for byte.
TEST_F(SplkTest, Version11TinyFileWithAGraphChunkIsPinned) {
  LoadedCloud doc = tiny_doc();
  RawChunk clas;
  std::memcpy(clas.type, "CLAS", 4);
  clas.flags = kSplkChunkTiedToSplats;
  const std::string payload = le(1, 8) + std::string(1, '\x01');
  clas.payload.assign(payload.begin(), payload.end());
  doc.chunks.push_back(clas);
  const std::string pinned = read_source_file("tests/data/splk/tiny-v1.1.splk");
  EXPECT_EQ(encode(doc), pinned) << "write_splk changed the 1.1 encoding";
  const std::string v10 = tiny_file();
  ASSERT_EQ(pinned.size(), v10.size() + 20 + 9);
  EXPECT_EQ(pinned.substr(8, 4), std::string("\x01\x00\x01\x00", 4));
  EXPECT_EQ(pinned.substr(12, 148), v10.substr(12, 148)) << "flags, META and SPLT as in 1.0";
  EXPECT_EQ(pinned.substr(160, 29), chunk("CLAS", 2, payload));
  LoadedCloud back = read_bytes(pinned);
  EXPECT_EQ(back.header["version"], "1.1");
  ASSERT_EQ(back.chunks.size(), 1u);
  EXPECT_EQ(back.chunks[0].payload, clas.payload);
}

TEST_F(SplkTest, HeaderListsTheChunksInFileOrder) {
  LoadedCloud back = read_bytes(tiny_file());
  EXPECT_EQ(back.header["version"], "1.0");
  EXPECT_EQ(back.header["flags"], 0);
  const auto& chunks = back.header["chunks"];
  ASSERT_EQ(chunks.size(), 3u);
  EXPECT_EQ(chunks[0]["type"], "META");
  EXPECT_EQ(chunks[0]["offset"], 16);
  EXPECT_EQ(chunks[0]["bytes"], 15);
  EXPECT_EQ(chunks[0]["flags"], 0);
  EXPECT_EQ(chunks[0]["crc"], [] {
    char b[9];
    std::snprintf(b, sizeof b, "%08x", crc_of(R"({"tool":"test"})"));
    return std::string(b);
  }());
  EXPECT_EQ(chunks[1]["type"], "SPLT");
  EXPECT_EQ(chunks[1]["offset"], 51);
  EXPECT_EQ(chunks[1]["bytes"], 89);
  EXPECT_EQ(chunks[1]["flags"], 3);
  EXPECT_EQ(chunks[2]["type"], "END ");
  EXPECT_EQ(chunks[2]["offset"], 160);
}

TEST_F(SplkTest, ReadsANewerMinorVersion) {
  std::string f = file_header(1, 7) + one_point_splt() + end_chunk();
  LoadedCloud back = read_bytes(f);
  EXPECT_EQ(back.header["version"], "1.7");
  EXPECT_EQ(back.cloud.size(), 1u);
}

TEST_F(SplkTest, ChunksMayComeInAnyOrder) {
  std::string face = chunk("FACE", 2, le(1, 8) + le(1, 8) + le(0, 4) + le(1, 4) + le(0, 4));
  std::string f = file_header() + face + one_point_splt() + meta_chunk() + end_chunk();
  LoadedCloud back = read_bytes(f);
  EXPECT_EQ(back.cloud.face_offsets, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(back.cloud.face_indices, (std::vector<uint32_t>{0}));
  EXPECT_EQ(back.metadata["tool"], "test");
}

// --- carried chunks ---

TEST_F(SplkTest, UnknownChunkIsCarriedThroughByteForByte) {
  const std::string payload("\x00\x01\xFFhello\r\n", 10);
  const std::string unknown = chunk("xTST", 2, payload) + chunk("ZZZ9", 0, "");
  const std::string f = file_header() + meta_chunk() + one_point_splt() + unknown + end_chunk();
  LoadedCloud doc = read_bytes(f);
  ASSERT_EQ(doc.chunks.size(), 2u);
  EXPECT_EQ(std::string(doc.chunks[0].type, 4), "xTST");
  EXPECT_EQ(doc.chunks[0].flags, 2u);
  EXPECT_EQ(std::string(doc.chunks[0].payload.begin(), doc.chunks[0].payload.end()), payload);
  EXPECT_EQ(std::string(doc.chunks[1].type, 4), "ZZZ9");
  EXPECT_EQ(encode(doc), f);
}

TEST_F(SplkTest, ChunksTiedToSplatsCanBeDropped) {
  const std::string f = file_header() + one_point_splt() + chunk("xPER", 2, "per-splat") +
                        chunk("xALL", 0, "global") + chunk("xTWO", 3 & ~1, "") + end_chunk();
  LoadedCloud doc = read_bytes(f);
  ASSERT_EQ(doc.chunks.size(), 3u);
  EXPECT_EQ(drop_chunks_tied_to_splats(doc), 2u);
  ASSERT_EQ(doc.chunks.size(), 1u);
  EXPECT_EQ(std::string(doc.chunks[0].type, 4), "xALL");
}

TEST_F(SplkTest, WriterRefusesWhatTheFormatCannotHold) {
  auto expect_output_error = [&](const LoadedCloud& doc, const std::string& what) {
    try {
      encode(doc);
      ADD_FAILURE() << "written; expected: " << what;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::kOutput);
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  LoadedCloud nan = tiny_doc();
  nan.cloud.positions[0].y = std::numeric_limits<float>::quiet_NaN();
  expect_output_error(nan, "point 0 has a non-finite position");
  LoadedCloud dup = tiny_doc();
  dup.cloud.extras = {{"a", ScalarType::kUInt8, {1}}, {"a", ScalarType::kUInt8, {2}}};
  expect_output_error(dup, "two extra attributes are named 'a'");
  LoadedCloud reserved = tiny_doc();
  reserved.chunks.push_back({{'S', 'P', 'L', 'T'}, 0, {}});
  expect_output_error(reserved, "cannot carry a chunk of type 'SPLT'");
  LoadedCloud bad_type = tiny_doc();
  bad_type.chunks.push_back({{'a', '-', 'b', 'c'}, 0, {}});
  expect_output_error(bad_type, "cannot carry a chunk of type 'a-bc'");
  LoadedCloud not_object = tiny_doc();
  not_object.metadata = nlohmann::json::array({1, 2});
  expect_output_error(not_object, "metadata must be a JSON object");
  EXPECT_FALSE(std::ifstream(dir_ + "/out.splk").good()) << "a failed write left a file";
}

// --- pipes (size unknown: no size check, allocations must follow the bytes that arrive) ---

// Feeds `bytes` through a pipe and reads it as /dev/fd/N, where the size is unknown.
LoadedCloud read_through_pipe(const std::string& bytes) {
  int fds[2];
  EXPECT_EQ(::pipe(fds), 0);
  auto old = ::signal(SIGPIPE, SIG_IGN);  // the reader may stop early: the writer gets EPIPE
  std::thread writer([&] {
    std::size_t off = 0;
    while (off < bytes.size()) {
      ssize_t k = ::write(fds[1], bytes.data() + off, bytes.size() - off);
      if (k <= 0) break;
      off += static_cast<std::size_t>(k);
    }
    ::close(fds[1]);
  });
  struct Cleanup {
    std::thread& t;
    int fd;
    void (*old)(int);
    ~Cleanup() {
      t.join();
      ::signal(SIGPIPE, old);
    }
  } cleanup{writer, fds[0], old};
  InputStream in("/dev/fd/" + std::to_string(fds[0]));
  ::close(fds[0]);  // `in` holds its own descriptor; closing ours lets the writer see EPIPE
  EXPECT_FALSE(in.size_hint().has_value());
  return read_splk(in);
}

TEST_F(SplkTest, ReadsFromAPipe) {
  const std::string bytes = encode(full_doc());
  LoadedCloud back = read_through_pipe(bytes);
  EXPECT_EQ(back.cloud.positions, full_doc().cloud.positions);
  EXPECT_EQ(back.cloud.extras.size(), full_doc().cloud.extras.size());
}

TEST_F(SplkTest, ReadsALargeCloudFromAPipe) {
  LoadedCloud doc;
  for (int i = 0; i < 300000; ++i) doc.cloud.positions.push_back({float(i), float(-i), 0.5f});
  doc.cloud.radii.assign(doc.cloud.size(), 0.25f);
  LoadedCloud back = read_through_pipe(encode(doc));
  EXPECT_EQ(back.cloud.positions, doc.cloud.positions);
  EXPECT_EQ(back.cloud.radii, doc.cloud.radii);
}

TEST_F(SplkTest, WritesToAPipeWithoutSeeking) {
  // Standard output is pointed at a pipe for the duration of the write; a thread drains it.
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  std::string piped;
  std::thread drain([&] {
    char buf[65536];
    ssize_t k;
    while ((k = ::read(fds[0], buf, sizeof buf)) > 0)
      piped.append(buf, static_cast<std::size_t>(k));
  });
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO);
  ::dup2(fds[1], STDOUT_FILENO);
  ::close(fds[1]);
  {
    OutputFile out("-");
    write_splk(full_doc(), out);
    out.commit();
  }
  ::dup2(saved, STDOUT_FILENO);  // drops the last write end: the drain sees end of file
  ::close(saved);
  drain.join();
  ::close(fds[0]);
  EXPECT_EQ(piped, encode(full_doc()));
}

TEST_F(SplkTest, PipeWithTruncatedPayloadFailsWithoutTrustingTheSize) {
  // The chunk claims 2^40 bytes: on a pipe that cannot be checked up front, and the reader must
  // fail at the end of the data instead of allocating a terabyte.
  std::string big = std::string("xBIG") + le(0, 4) + le(uint64_t{1} << 40, 8) + le(0, 4) +
                    std::string(3000000, 'a');
  std::string f = file_header() + one_point_splt() + big;
  try {
    read_through_pipe(f);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kBadInput);
    EXPECT_NE(
        std::string(e.what()).find("chunk 'xBIG' at byte 125: payload truncated: "
                                   "1099511627776 bytes declared, the file ends after 3000000"),
        std::string::npos)
        << e.what();
  }
}

TEST_F(SplkTest, PipeWithHugePointCountFailsAtTheEndOfTheData) {
  std::string payload =
      splt(uint64_t{1} << 36, {column("position", 0, 9, 3, "")}) + std::string(2000000, '\0');
  std::string f = file_header() + std::string("SPLT") + le(3, 4) + le(uint64_t{1} << 40, 8) +
                  le(0, 4) + payload;
  try {
    read_through_pipe(f);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("payload truncated"), std::string::npos) << e.what();
  }
}

// --- malformed files: one test per case, each with its own message ---

TEST(SplkReject, BadMagic) {
  expect_rejected("ply\nformat ascii 1.0\nend_header\n", ErrorKind::kBadInput,
                  "not a .splk file (bad magic)");
}

TEST(SplkReject, MagicDamagedByLineEndingConversion) {
  std::string f = tiny_file();
  f.erase(5, 1);  // \r\n -> \n
  expect_rejected(f, ErrorKind::kBadInput, "damaged .splk magic: \\r\\n became \\n");
  f = tiny_file();
  f = f.substr(0, 6) + "\r" + f.substr(6);  // \n -> \r\n
  expect_rejected(f, ErrorKind::kBadInput, "damaged .splk magic: \\n became \\r\\n");
}

TEST(SplkReject, MagicDamagedBy7BitTransfer) {
  std::string f = tiny_file();
  f[0] = 0x09;
  expect_rejected(f, ErrorKind::kBadInput, "high bit of byte 0 was cleared");
}

TEST(SplkReject, UnknownMajorVersionIsUnsupported) {
  expect_rejected(file_header(2, 0) + one_point_splt() + end_chunk(), ErrorKind::kUnsupported,
                  ".splk version 2.0 is not supported");
}

TEST(SplkReject, UnknownFileFlagBitsAreUnsupported) {
  expect_rejected(file_header(1, 0, 4) + one_point_splt() + end_chunk(), ErrorKind::kUnsupported,
                  "file flags 0x00000004 have bits this reader does not know");
}

TEST(SplkReject, TruncatedHeader) {
  expect_rejected(tiny_file().substr(0, 10), ErrorKind::kBadInput, "truncated header: 10 of 16");
  expect_rejected(tiny_file().substr(0, 3), ErrorKind::kBadInput, "truncated header: 3 of 16");
  expect_rejected("", ErrorKind::kBadInput, "truncated header: 0 of 16");
}

TEST(SplkReject, TruncatedChunkHeader) {
  expect_rejected(tiny_file().substr(0, 16 + 11), ErrorKind::kBadInput,
                  "byte 16: truncated chunk header: 11 of 20 bytes");
}

TEST(SplkReject, TruncatedPayload) {
  expect_rejected(tiny_file().substr(0, 51 + 20 + 40), ErrorKind::kBadInput,
                  "chunk 'SPLT': payload truncated: 89 bytes declared, only 40 left in the file");
}

TEST(SplkReject, ChunkSizeLargerThanTheFile) {
  std::string f = tiny_file();
  f.replace(51 + 8, 8, le(1000000, 8));
  expect_rejected(f, ErrorKind::kBadInput,
                  "byte 51: chunk 'SPLT' claims 1000000 payload bytes, more than the whole file "
                  "(180 bytes)");
}

TEST(SplkReject, BadChecksumNamesTheChunkAndOffset) {
  std::string f = tiny_file();
  f[51 + 20 + 64 + 13] ^= 0x01;  // a bit of the first position
  expect_rejected(f, ErrorKind::kBadInput, "chunk 'SPLT' at byte 51: checksum mismatch");
}

TEST(SplkReject, MissingEnd) {
  expect_rejected(file_header() + meta_chunk() + one_point_splt(), ErrorKind::kBadInput,
                  "byte 160: missing END chunk: the file ends after chunk 'SPLT'");
  expect_rejected(file_header(), ErrorKind::kBadInput,
                  "missing END chunk: the file ends after the header");
}

TEST(SplkReject, TrailingGarbageAfterEnd) {
  expect_rejected(tiny_file() + "xyz", ErrorKind::kBadInput,
                  "byte 180: 3 bytes of trailing data after the END chunk");
}

TEST(SplkReject, EndWithPayload) {
  expect_rejected(file_header() + one_point_splt() + chunk("END ", 1, "x"), ErrorKind::kBadInput,
                  "the END chunk has a payload of 1 bytes");
}

TEST(SplkReject, MissingSplt) {
  expect_rejected(file_header() + meta_chunk() + end_chunk(), ErrorKind::kBadInput,
                  "no SPLT chunk (the splats) before END");
}

TEST(SplkReject, DuplicateSplt) {
  expect_rejected(file_header() + one_point_splt() + one_point_splt() + end_chunk(),
                  ErrorKind::kBadInput, "a second 'SPLT' chunk (only one is allowed)");
}

TEST(SplkReject, DuplicateMeta) {
  expect_rejected(file_header() + meta_chunk() + one_point_splt() + meta_chunk() + end_chunk(),
                  ErrorKind::kBadInput, "a second 'META' chunk (only one is allowed)");
}

TEST(SplkReject, ColumnShorterThanTheCount) {
  // Two points declared, one position stored.
  std::string p = splt(2, {position_column({{1, 2, 3}})});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "column 'position': 2 values of 12 bytes do not fit in the 12 bytes left");
}

TEST(SplkReject, UnusedBytesAfterTheLastColumn) {
  std::string p = splt(1, {position_column({{1, 2, 3}})}) + "??";
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "2 unused bytes at the end of the payload");
}

TEST(SplkReject, PointCountLargerThanTheFile) {
  std::string p = splt(1000000000000, {position_column({{1, 2, 3}})});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "point count 1000000000000 needs 12000000000000 bytes of positions alone");
}

TEST(SplkReject, NanCoordinates) {
  std::string p = splt(2, {position_column({{1, 2, 3}, {4, std::nanf(""), 6}})});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "point 1 has a non-finite position");
}

TEST(SplkReject, InfiniteOrigin) {
  std::string p =
      splt(1, {position_column({{1, 2, 3}})}, 0, {0, std::numeric_limits<double>::infinity(), 0});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "the origin is not finite");
}

TEST(SplkReject, UnknownCriticalChunkIsUnsupported) {
  expect_rejected(file_header() + one_point_splt() + chunk("xCRT", 1, "abc") + end_chunk(),
                  ErrorKind::kUnsupported, "chunk 'xCRT' at byte 125 is critical and unknown");
}

TEST(SplkReject, UnknownChunkFlagBitsAreUnsupported) {
  expect_rejected(file_header() + one_point_splt() + chunk("xFLG", 8, "") + end_chunk(),
                  ErrorKind::kUnsupported,
                  "chunk 'xFLG' has flag bits 0x00000008 this reader does not know");
}

TEST(SplkReject, InvalidChunkType) {
  expect_rejected(file_header() + one_point_splt() + chunk("a\x01 b", 0, "") + end_chunk(),
                  ErrorKind::kBadInput, "type 61 01 20 62 is not four letters or digits");
}

TEST(SplkReject, InvalidJsonInMeta) {
  expect_rejected(file_header() + meta_chunk("{\"tool\": ") + one_point_splt() + end_chunk(),
                  ErrorKind::kBadInput, "chunk 'META' at byte 16: invalid JSON: ");
}

TEST(SplkReject, MetaNestedTooDeep) {
  const std::string deep = "{\"a\":" + std::string(100000, '[') + std::string(100000, ']') + "}";
  expect_rejected(file_header() + meta_chunk(deep) + one_point_splt() + end_chunk(),
                  ErrorKind::kBadInput, "the metadata JSON nests deeper than 64 levels");
  const std::string ok = "{\"a\":" + std::string(63, '[') + std::string(63, ']') + "}";
  EXPECT_EQ(read_bytes(file_header() + meta_chunk(ok) + one_point_splt() + end_chunk())
                .metadata.dump()
                .size(),
            ok.size());
}

TEST(SplkReject, MetaThatIsNotAnObject) {
  expect_rejected(file_header() + meta_chunk("[1,2]") + one_point_splt() + end_chunk(),
                  ErrorKind::kBadInput, "the metadata is JSON but not an object");
}

TEST(SplkReject, UnknownCoreColumn) {
  std::string p =
      splt(1, {position_column({{1, 2, 3}}), column("tangent", 0, 9, 3, f32(0) + f32(0) + f32(1))});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "unknown core column 'tangent'");
}

TEST(SplkReject, UnknownScalarType) {
  std::string p = splt(1, {position_column({{1, 2, 3}}), column("w", 1, 11, 1, "")});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "column 'w' has unknown scalar type code 11");
}

TEST(SplkReject, UnknownColumnKind) {
  std::string p = splt(1, {position_column({{1, 2, 3}}), column("w", 2, 2, 1, "x")});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "column 'w' has unknown kind 2");
}

TEST(SplkReject, CoreColumnWithTheWrongLayout) {
  std::string p = splt(1, {position_column({{1, 2, 3}}), column("radius", 0, 10, 1, f64(1))});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "core column 'radius' must be float32 x1, found float64 x1");
}

TEST(SplkReject, ExtraWithSeveralComponents) {
  std::string p = splt(1, {position_column({{1, 2, 3}}), column("uv", 1, 9, 2, f32(0) + f32(1))});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "extra column 'uv' has 2 components");
}

TEST(SplkReject, DuplicateColumnNames) {
  std::string p =
      splt(1, {position_column({{1, 2, 3}}), column("w", 1, 2, 1, "a"), column("w", 1, 2, 1, "b")});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "two extra columns named 'w'");
}

TEST(SplkReject, MissingPositionColumn) {
  std::string p = splt(1, {column("w", 1, 10, 1, f64(0.5))});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "no 'position' column");
}

TEST(SplkReject, ColumnNameThatIsNotUtf8) {
  std::string p = splt(1, {position_column({{1, 2, 3}}), column("\xC0\xAF", 1, 2, 1, "a")});
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "column 1 name is not UTF-8");
}

TEST(SplkReject, UnknownSpltFlags) {
  std::string p = splt(1, {position_column({{1, 2, 3}})}, 2);
  expect_rejected(file_header() + splt_chunk(p) + end_chunk(), ErrorKind::kBadInput,
                  "unknown SPLT flag bits 0x00000002");
}

TEST(SplkReject, FaceSizesThatDoNotMatch) {
  std::string face = chunk("FACE", 2, le(5, 8) + le(1, 8) + le(0, 4) + le(1, 4) + le(0, 4));
  expect_rejected(file_header() + one_point_splt() + face + end_chunk(), ErrorKind::kBadInput,
                  "5 faces and 1 indices do not match the 12 bytes");
}

TEST(SplkReject, FaceIndexOutOfRange) {
  std::string face = chunk("FACE", 2, le(1, 8) + le(1, 8) + le(0, 4) + le(1, 4) + le(7, 4));
  expect_rejected(file_header() + one_point_splt() + face + end_chunk(), ErrorKind::kBadInput,
                  "FACE: index 0 is 7, but there are only 1 splats");
}

TEST(SplkReject, FaceOffsetsThatDecrease) {
  std::string face =
      chunk("FACE", 2, le(2, 8) + le(1, 8) + le(0, 4) + le(2, 4) + le(1, 4) + le(0, 4));
  expect_rejected(file_header() + one_point_splt() + face + end_chunk(), ErrorKind::kBadInput,
                  "face offsets decrease at face 1");
}

TEST(SplkRead, ThroughReadCloudByContent) {
  const std::string f = tiny_file();
  InputStream in("no-extension", f.data(), f.size());
  LoadedCloud doc = read_cloud(in);
  EXPECT_EQ(doc.format, "splk");
  EXPECT_EQ(doc.cloud.size(), 1u);
}

}  // namespace
}  // namespace splatkit
