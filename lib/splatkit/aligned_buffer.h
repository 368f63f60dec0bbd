// AlignedBuffer: uninitialised bytes on an alignment boundary, e.g. whole blocks for
// OutputFile::write_through (O_DIRECT needs aligned memory).
#pragma once

#include <cstddef>
#include <memory>
#include <new>

namespace splatkit {

struct AlignedDelete {
  std::size_t alignment = alignof(std::max_align_t);
  void operator()(unsigned char* p) const { ::operator delete[](p, std::align_val_t{alignment}); }
};
using AlignedBuffer = std::unique_ptr<unsigned char[], AlignedDelete>;

// `bytes` (at least 1) uninitialised bytes at a multiple of `alignment` (a power of two).
inline AlignedBuffer make_aligned_buffer(std::size_t bytes, std::size_t alignment) {
  return AlignedBuffer(new (std::align_val_t{alignment}) unsigned char[bytes > 0 ? bytes : 1],
                       AlignedDelete{alignment});
}

}  // namespace splatkit
