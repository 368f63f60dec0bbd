// The values of one extra per-point attribute, held at the width of their scalar type (a uint8
// classification takes one byte per point, not the eight of a double: a LAS file's eight
// standard attributes take 17 bytes per point instead of 64) and read and written as doubles.
// A double read back is the value stored exactly, except 64-bit integers above 2^53; a double
// stored is converted as the writers convert it (floats: rounded to the type; integers: rounded
// to nearest, clamped to the type's range, NaN as 0). Code that handles a whole column at once
// reaches the values in their own type with `as<T>()` after dispatching on type().
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "splatkit/scalar_type.h"

namespace splatkit {

// Calls f(T{}) with the C++ type of `t` (int8_t ... double).
template <class F>
decltype(auto) visit_scalar_type(ScalarType t, F&& f) {
  switch (t) {
    case ScalarType::kInt8: return f(int8_t{});
    case ScalarType::kUInt8: return f(uint8_t{});
    case ScalarType::kInt16: return f(int16_t{});
    case ScalarType::kUInt16: return f(uint16_t{});
    case ScalarType::kInt32: return f(int32_t{});
    case ScalarType::kUInt32: return f(uint32_t{});
    case ScalarType::kInt64: return f(int64_t{});
    case ScalarType::kUInt64: return f(uint64_t{});
    case ScalarType::kFloat32: return f(float{});
    case ScalarType::kFloat64: break;
  }
  return f(double{});
}

// v as a T the way writers store it: floats rounded to T; integers rounded to nearest (exact
// ones at once), saturated, NaN as 0.
template <class T>
T convert_scalar(double v) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(v);
  } else {
    const double lo = static_cast<double>(std::numeric_limits<T>::min());
    const double hi_excl = std::ldexp(1.0, std::numeric_limits<T>::digits);
    if (v >= lo && v < hi_excl) {
      const T t = static_cast<T>(v);  // truncates
      if (static_cast<double>(t) == v) return t;
    }
    if (std::isnan(v)) return 0;
    const double r = std::round(v);
    if (r < lo) return std::numeric_limits<T>::min();
    if (r >= hi_excl) return std::numeric_limits<T>::max();
    return static_cast<T>(r);
  }
}

class ExtraValues {
 public:
  explicit ExtraValues(ScalarType type = ScalarType::kFloat32);

  ScalarType type() const { return type_; }
  std::size_t size() const { return bytes_.size() >> shift_; }
  bool empty() const { return bytes_.empty(); }
  double operator[](std::size_t i) const {
    return visit_scalar_type(type_, [&](auto zero) {
      decltype(zero) v;
      std::memcpy(&v, bytes_.data() + (i << shift_), sizeof v);
      return static_cast<double>(v);
    });
  }
  double at(std::size_t i) const;  // std::out_of_range beyond size()
  void set(std::size_t i, double v) {
    visit_scalar_type(type_, [&](auto zero) {
      const auto x = convert_scalar<decltype(zero)>(v);
      std::memcpy(bytes_.data() + (i << shift_), &x, sizeof x);
    });
  }
  void push_back(double v) {
    const std::size_t at = bytes_.size();
    if (at == bytes_.capacity()) bytes_.reserve(std::max<std::size_t>(2 * at, 64));
    bytes_.resize(at + (std::size_t{1} << shift_));
    set(at >> shift_, v);
  }
  void reserve(std::size_t n) { bytes_.reserve(n << shift_); }
  void resize(std::size_t n) { bytes_.resize(n << shift_, 0); }  // new values are 0
  std::size_t capacity() const { return bytes_.capacity() >> shift_; }
  void shrink_to_fit() { bytes_.shrink_to_fit(); }
  // Value `from` copied over value `to` (as it is stored: no conversion).
  void copy_value(std::size_t to, std::size_t from) {
    std::memmove(bytes_.data() + (to << shift_), bytes_.data() + (from << shift_),
                 std::size_t{1} << shift_);
  }
  // The values in their own type T, which must be type()'s (std::logic_error otherwise).
  template <class T>
  std::span<T> as() {
    check<T>();
    return {reinterpret_cast<T*>(bytes_.data()), size()};
  }
  template <class T>
  std::span<const T> as() const {
    check<T>();
    return {reinterpret_cast<const T*>(bytes_.data()), size()};
  }
  std::vector<double> doubles() const;
  // Same type and the same stored values.
  friend bool operator==(const ExtraValues&, const ExtraValues&) = default;

 private:
  template <class T>
  void check() const {
    const bool same = visit_scalar_type(type_, [](auto zero) {
      return std::is_same_v<std::remove_const_t<T>, decltype(zero)>;
    });
    if (!same) throw std::logic_error("extra values read as another type than theirs");
  }

  ScalarType type_;
  unsigned shift_;  // log2 of the width in bytes
  std::vector<unsigned char> bytes_;
};

}  // namespace splatkit
