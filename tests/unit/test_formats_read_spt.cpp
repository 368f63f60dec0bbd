// The .spt quantisers and reader (formats/spt_codes.h, formats/read_spt.h): error bounds of each
// code, a round trip through the writer, and one test per malformed case, each rejected with its
// own message.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "formats/read_spt.h"
#include "formats/spt_codes.h"
#include "splatkit/crc32c.h"
#include "splatkit/error.h"
#include "splatkit/synthetic_shapes.h"
#include "spt/build_spt_tree.h"
#include "spt/encode_spt.h"

namespace splatkit::spt {
namespace {

using Bytes = std::vector<unsigned char>;

TEST(SptCodes, NormalErrorIsBounded) {
  std::mt19937 rng(1);
  std::normal_distribution<float> g;
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const Vec3f n = normalized(Vec3f{g(rng), g(rng), g(rng)});
    const Vec3f d = decode_normal(encode_normal(n));
    worst = std::max(worst, std::acos(std::min(1.0, double(dot(n, d)))));
  }
  EXPECT_LE(worst, kNormalMaxError);
  EXPECT_GT(worst, kNormalMaxError / 2);  // the bound is not loose
}

TEST(SptCodes, RCodesAreMonotoneAndCloseDiametersNeverShrink) {
  const float lo = 0.01f, hi = 1e4f;
  const LogScale rs = r_scale(lo, hi), ds = d_scale(lo, hi);
  uint16_t last = 0;
  double worst = 0;
  for (float r = lo; r <= hi; r *= 1.001f) {
    const uint16_t c = encode_r(r, rs);
    EXPECT_GE(c, last);
    last = c;
    worst = std::max(worst, std::fabs(double(decode_r(c, rs)) / r - 1));
    const uint16_t d = encode_diameter(r, ds);
    EXPECT_GE(decode_diameter(d, ds), r);
    EXPECT_LE(decode_diameter(d, ds), r * 1.0005f);
  }
  EXPECT_LE(worst, std::pow(hi / lo, 1.0 / 65533) - 1);  // half a step, rounded to nearest
  EXPECT_EQ(encode_r(0, rs), 0);
  EXPECT_EQ(encode_r(INFINITY, rs), kRInfinity);
  EXPECT_TRUE(std::isinf(decode_r(kRInfinity, rs)));
}

TEST(SptCodes, DiameterCoderGivesEncodeDiametersCodes) {
  const float lo = 0.003f, hi = 7.5f;
  const LogScale ds = d_scale(lo, hi);
  const DiameterCoder coder(ds);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> diameters = {0.0f, -1.0f, NAN, lo / 2, lo, hi, 2 * hi, INFINITY};
  for (int code = 0; code < 65536; code += 97) {  // decoded values and their neighbours
    const float d = decode_diameter(static_cast<uint16_t>(code), ds);
    diameters.insert(diameters.end(), {d, std::nextafter(d, 0.0f), std::nextafter(d, INFINITY)});
  }
  for (int i = 0; i < 100000; ++i) diameters.push_back(lo * std::pow(hi / lo, u(rng)));
  for (float d : diameters) ASSERT_EQ(coder.encode(d), encode_diameter(d, ds)) << d;
}

SplatCloud small_cloud() {
  ShapeOptions s;
  s.kind = ShapeKind::kTwoSpheres;
  s.points = 2000;
  return make_shape(s);
}

Bytes encode(const SplatCloud& c, bool full) {
  EncodeSptOptions o;
  o.full = full;
  return build_spt_bytes(c, 1.0f, o).bytes;
}

TEST(ReadSpt, RoundTripStaysWithinTheStatedErrors) {
  const SplatCloud c = small_cloud();
  for (bool full : {false, true}) {
    EncodeSptOptions o;
    o.full = full;
    const SptBytes built = build_spt_bytes(c, 1.0f, o, true);
    const EncodedSpt& f = built.info;
    const SptModel m = parse_spt(built.bytes, "t.spt");
    EXPECT_EQ(m.header.full(), full);
    EXPECT_TRUE(m.header.has_color());
    EXPECT_EQ(m.header.input_points, c.size());
    const Vec3f s = m.header.step;
    for (std::size_t i = 0; i < c.size(); ++i) {
      const uint32_t e = f.entry_of_node[i];
      ASSERT_NE(e, kNoParent);
      const Vec3f d = m.positions[e] - c.positions[i];
      EXPECT_LE(std::fabs(d.x), s.x * 0.5001f + 1e-6f);
      EXPECT_LE(std::fabs(d.z), s.z * 0.5001f + 1e-6f);
      EXPECT_GE(m.diameters[e], 2 * c.radii[i] * (1 - 1e-6f));
      EXPECT_LE(std::acos(std::min(1.0f, dot(m.normals[e], c.normals[i]))),
                full ? 1e-3 : kNormalMaxError);
      EXPECT_EQ(m.r_min[e], 0.0f);
      EXPECT_NEAR(m.colors[e][0], c.colors[i][0], full ? 0 : 4);
      EXPECT_NEAR(m.colors[e][1], c.colors[i][1], full ? 0 : 2);
    }
  }
}

// A file with its checksum made right again after an edit.
Bytes resealed(Bytes b) {
  uint32_t crc = crc32c(0, b.data(), 124);
  crc = crc32c(crc, b.data() + kSptHeaderBytes, b.size() - kSptHeaderBytes);
  put_u32(b.data() + 124, crc);
  return b;
}

std::string error_of(const Bytes& b, ErrorKind* kind = nullptr) {
  try {
    parse_spt(b, "t.spt");
  } catch (const Error& e) {
    if (kind) *kind = e.kind();
    return e.what();
  }
  return "";
}

void expect_error(const Bytes& b, const std::string& what, ErrorKind kind = ErrorKind::kBadInput) {
  ErrorKind got = ErrorKind::kInternal;
  const std::string message = error_of(b, &got);
  EXPECT_NE(message.find(what), std::string::npos) << "got: " << message;
  EXPECT_EQ(got, kind) << message;
}

TEST(ReadSpt, RejectsEachMalformedCaseWithItsOwnMessage) {
  const Bytes good = encode(small_cloud(), false);
  ASSERT_EQ(error_of(good), "");
  Bytes b = good;
  b[0] = 'X';
  expect_error(b, "bad magic");
  expect_error(Bytes(good.begin(), good.begin() + 100), "truncated header");
  expect_error(Bytes(good.begin(), good.end() - 3), "truncated file");
  b = good;
  b.push_back(0);
  expect_error(b, "bytes after the last entry");
  b = good;
  b[200] ^= 1;
  expect_error(b, "checksum mismatch");
  b = good;
  put_u32(b.data() + 8, 2);
  expect_error(resealed(b), "newer than this reader", ErrorKind::kUnsupported);
  b = good;
  put_u32(b.data() + 8, 0);
  expect_error(resealed(b), "version 0");
  b = good;
  put_u32(b.data() + 12, 8);
  expect_error(resealed(b), "unknown flag bits", ErrorKind::kUnsupported);
  b = good;
  put_u32(b.data() + 16, 40);
  expect_error(resealed(b), "entry size 40");
  b = good;
  b[115] = 1;
  expect_error(resealed(b), "reserved header byte");
  b = good;
  put_u32(b.data() + 24, 0xFFFFFFFFu);
  put_u32(b.data() + 28, 0xFFFFFFFFu);  // an entry count whose size overflows
  expect_error(resealed(b), "truncated file");
  b = good;
  put_f32(b.data() + 76, -1);
  expect_error(resealed(b), "quantisation step");
  b = good;
  put_f32(b.data() + 88, 0);
  expect_error(resealed(b), "r scale");
  b = good;
  put_f32(b.data() + 100, NAN);
  expect_error(resealed(b), "diameter scale");
  b = good;
  put_f32(b.data() + 104, 0);
  expect_error(resealed(b), "epsilon");
  b = good;
  put_f32(b.data() + 108, -1);
  expect_error(resealed(b), "colour weight");
  // Entries: r_max below r_min, an infinite r_min, the list out of order.
  const std::size_t last = good.size() - kSptCompactEntryBytes;
  b = good;
  put_u16(b.data() + last + 10, 100);
  put_u16(b.data() + last + 12, 50);
  expect_error(resealed(b), "r_max is below r_min");
  b = good;
  put_u16(b.data() + last + 10, kRInfinity);
  put_u16(b.data() + last + 12, kRInfinity);
  expect_error(resealed(b), "r_min is infinite");
  b = good;
  put_u16(b.data() + last + 12, 65000);
  expect_error(resealed(b), "not sorted by r_max");
}

TEST(ReadSpt, RejectsMalformedFullEntries) {
  const Bytes good = encode(small_cloud(), true);
  ASSERT_EQ(error_of(good), "");
  const std::size_t e = good.size() - kSptFullEntryBytes;
  Bytes b = good;
  put_f32(b.data() + e, INFINITY);
  expect_error(resealed(b), "position is not finite");
  b = good;
  put_f32(b.data() + e + 12, 3);
  expect_error(resealed(b), "normal is not unit");
  b = good;
  put_f32(b.data() + e + 24, -1);
  expect_error(resealed(b), "diameter is negative");
  b = good;
  put_f32(b.data() + e + 28, NAN);
  expect_error(resealed(b), "r_min is negative");
}

}  // namespace
}  // namespace splatkit::spt
