// The scalar types that point-cloud formats store, with their names in PLY and byte sizes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace splatkit {

enum class ScalarType : uint8_t {
  kInt8 = 1,
  kUInt8,
  kInt16,
  kUInt16,
  kInt32,
  kUInt32,
  kInt64,
  kUInt64,
  kFloat32,
  kFloat64,
};

// Bytes of one value (1, 2, 4 or 8).
std::size_t scalar_size(ScalarType t);
// Canonical name: int8 uint8 int16 uint16 int32 uint32 int64 uint64 float32 float64.
std::string_view scalar_name(ScalarType t);
// Parses canonical names and PLY's aliases (char uchar short ushort int uint float double).
std::optional<ScalarType> parse_scalar_name(std::string_view name);
bool is_floating(ScalarType t);

}  // namespace splatkit
