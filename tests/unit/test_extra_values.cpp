// ExtraValues: extra attributes held at the width of their type, read and written as doubles.
#include "splatkit/extra_values.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "splatkit/splat_cloud.h"

namespace splatkit {
namespace {

TEST(ExtraValues, TakeTheWidthOfTheirType) {
  const std::pair<ScalarType, std::size_t> widths[] = {
      {ScalarType::kInt8, 1},    {ScalarType::kUInt8, 1},   {ScalarType::kInt16, 2},
      {ScalarType::kUInt16, 2},  {ScalarType::kInt32, 4},   {ScalarType::kUInt32, 4},
      {ScalarType::kInt64, 8},   {ScalarType::kUInt64, 8},  {ScalarType::kFloat32, 4},
      {ScalarType::kFloat64, 8}};
  for (const auto& entry : widths) {
    const ScalarType type = entry.first;  // not a structured binding: clang 14 cannot capture one
    const std::size_t width = entry.second;
    ExtraValues v(type);
    for (int i = 0; i < 100; ++i) v.push_back(i);
    EXPECT_EQ(v.size(), 100u);
    EXPECT_EQ(v[99], 99.0) << scalar_name(type);
    visit_scalar_type(type, [&](auto zero) {
      EXPECT_EQ(sizeof zero, width);
      EXPECT_EQ(v.as<decltype(zero)>().size_bytes(), 100 * width) << scalar_name(type);
    });
  }
}

TEST(ExtraValues, ConvertAsTheWritersDo) {
  ExtraValues u8(ScalarType::kUInt8);
  for (double x : {-3.0, 2.5, 2.4, 254.6, 300.0, std::nan(""), 7.0}) u8.push_back(x);
  EXPECT_EQ(u8.doubles(), (std::vector<double>{0, 3, 2, 255, 255, 0, 7}));  // round half away
  ExtraValues i16(ScalarType::kInt16);
  for (double x : {-40000.0, -2.5, 40000.0, -0.0}) i16.push_back(x);
  EXPECT_EQ(i16.doubles(), (std::vector<double>{-32768, -3, 32767, 0}));
  ExtraValues f32(ScalarType::kFloat32);
  f32.push_back(0.1);
  EXPECT_EQ(f32[0], static_cast<double>(0.1f));
  ExtraValues f64(ScalarType::kFloat64);
  f64.push_back(0.1);
  EXPECT_EQ(f64[0], 0.1);
  ExtraValues u64(ScalarType::kUInt64);
  u64.push_back(std::ldexp(1.0, 64));  // saturates instead of overflowing
  EXPECT_EQ(u64.as<uint64_t>()[0], std::numeric_limits<uint64_t>::max());
  u64.push_back(9007199254740992.0);  // 2^53: exact
  EXPECT_EQ(u64.as<uint64_t>()[1], 9007199254740992ull);
}

TEST(ExtraValues, CopySetResizeAndCompare) {
  ExtraValues a(ScalarType::kInt32);
  for (int i = 0; i < 5; ++i) a.push_back(i * 10);
  a.copy_value(0, 4);
  a.set(1, -7);
  a.resize(3);
  EXPECT_EQ(a.doubles(), (std::vector<double>{40, -7, 20}));
  a.resize(4);
  EXPECT_EQ(a[3], 0.0);
  EXPECT_THROW(a.at(4), std::out_of_range);
  ExtraValues b(ScalarType::kInt32);
  for (double x : {40.0, -7.0, 20.0, 0.0}) b.push_back(x);
  EXPECT_EQ(a, b);
  ExtraValues c(ScalarType::kUInt32);  // the same numbers in another type are another column
  for (double x : {40.0, 7.0, 20.0, 0.0}) c.push_back(x);
  EXPECT_FALSE(b == c);
}

TEST(ExtraValues, AreReachedInTheirOwnTypeOnly) {
  ExtraValues v(ScalarType::kUInt16);
  v.resize(2);
  v.as<uint16_t>()[1] = 65535;
  EXPECT_EQ(v[1], 65535.0);
  EXPECT_THROW(v.as<int16_t>(), std::logic_error);
  EXPECT_THROW(v.as<uint32_t>(), std::logic_error);
  const ExtraAttribute e("intensity", ScalarType::kUInt16, {1, 2, 3});
  EXPECT_EQ(e.type(), ScalarType::kUInt16);
  EXPECT_EQ(e.values.as<uint16_t>()[2], 3);
}

}  // namespace
}  // namespace splatkit
