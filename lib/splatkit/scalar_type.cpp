#include "splatkit/scalar_type.h"

#include <array>
#include <utility>

namespace splatkit {

std::size_t scalar_size(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8:
    case ScalarType::kUInt8:
      return 1;
    case ScalarType::kInt16:
    case ScalarType::kUInt16:
      return 2;
    case ScalarType::kInt32:
    case ScalarType::kUInt32:
    case ScalarType::kFloat32:
      return 4;
    case ScalarType::kInt64:
    case ScalarType::kUInt64:
    case ScalarType::kFloat64:
      return 8;
  }
  return 0;
}

std::string_view scalar_name(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8:
      return "int8";
    case ScalarType::kUInt8:
      return "uint8";
    case ScalarType::kInt16:
      return "int16";
    case ScalarType::kUInt16:
      return "uint16";
    case ScalarType::kInt32:
      return "int32";
    case ScalarType::kUInt32:
      return "uint32";
    case ScalarType::kInt64:
      return "int64";
    case ScalarType::kUInt64:
      return "uint64";
    case ScalarType::kFloat32:
      return "float32";
    case ScalarType::kFloat64:
      return "float64";
  }
  return "?";
}

std::optional<ScalarType> parse_scalar_name(std::string_view name) {
  static constexpr std::array<std::pair<std::string_view, ScalarType>, 18> kNames{{
      {"int8", ScalarType::kInt8},
      {"char", ScalarType::kInt8},
      {"uint8", ScalarType::kUInt8},
      {"uchar", ScalarType::kUInt8},
      {"int16", ScalarType::kInt16},
      {"short", ScalarType::kInt16},
      {"uint16", ScalarType::kUInt16},
      {"ushort", ScalarType::kUInt16},
      {"int32", ScalarType::kInt32},
      {"int", ScalarType::kInt32},
      {"uint32", ScalarType::kUInt32},
      {"uint", ScalarType::kUInt32},
      {"int64", ScalarType::kInt64},
      {"uint64", ScalarType::kUInt64},
      {"float32", ScalarType::kFloat32},
      {"float", ScalarType::kFloat32},
      {"float64", ScalarType::kFloat64},
      {"double", ScalarType::kFloat64},
  }};
  for (const auto& [n, t] : kNames)
    if (n == name) return t;
  return std::nullopt;
}

bool is_floating(ScalarType t) { return t == ScalarType::kFloat32 || t == ScalarType::kFloat64; }

}  // namespace splatkit
