// SlotArray: n uninitialised elements of a trivially copyable T (malloc, or the spill arena's
// file when it runs: large blocks are fresh pages, and pages never written take no memory), for
// arrays of which only some entries are ever written, or whose entries are all written by a
// parallel pass that should fault their pages in itself (no zeroing pass first).
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>

#include "splatkit/spill_arena.h"

namespace splatkit {

template <class T>
struct SlotArray {
  static_assert(std::is_trivially_copyable_v<T>);
  struct Free {
    void operator()(T* p) const { spill::free_block(p); }
  };
  std::unique_ptr<T, Free> data;
  std::size_t size = 0;
  void allocate(std::size_t n) {
    data.reset(static_cast<T*>(spill::allocate_block(n * sizeof(T))));
    if (!data) throw std::bad_alloc();
    size = n;
  }
  T& operator[](std::size_t i) const { return data.get()[i]; }
  T* get() const { return data.get(); }  // null before the first allocate
};

}  // namespace splatkit
