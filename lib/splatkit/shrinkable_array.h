// ShrinkableArray: a uint32 array in one malloc block (or the spill arena's, spill_arena.h), so
// that it shrinks in place (realloc keeps a shrinking block where it is): an array compacted into
// its own front needs no second array at its peak.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <utility>

#include "splatkit/spill_arena.h"

namespace splatkit {

class ShrinkableArray {
 public:
  explicit ShrinkableArray(std::size_t size)
      : data_(static_cast<uint32_t*>(spill::allocate_block(size * 4))), size_(size) {
    if (!data_) throw std::bad_alloc();
  }
  ShrinkableArray(ShrinkableArray&& o) noexcept
      : data_(std::exchange(o.data_, nullptr)), size_(std::exchange(o.size_, 0)) {}
  ShrinkableArray& operator=(ShrinkableArray&& o) noexcept {
    std::swap(data_, o.data_);
    std::swap(size_, o.size_);
    return *this;
  }
  ~ShrinkableArray() { spill::free_block(data_); }
  void shrink(std::size_t size) {
    if (size >= size_) return;
    if (spill::shrink(data_, size * 4)) {
      size_ = size;
      return;
    }
    if (void* p = std::realloc(data_, std::max<std::size_t>(size, 1) * 4))
      data_ = static_cast<uint32_t*>(p);
    size_ = size;
  }
  std::size_t size() const { return size_; }
  uint32_t* data() { return data_; }
  const uint32_t* data() const { return data_; }
  uint32_t& operator[](std::size_t i) { return data_[i]; }
  uint32_t operator[](std::size_t i) const { return data_[i]; }

 private:
  uint32_t* data_;
  std::size_t size_;
};

}  // namespace splatkit
