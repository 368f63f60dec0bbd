#include "graph/neighbor_list_codec.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "graph/release_pages.h"
#include "splatkit/sized_in_parallel.h"
#include "graph/varint.h"
#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit::graph {
namespace {

constexpr std::size_t kRowChunk = 16384;  // rows per parallel task of the encoder
constexpr std::size_t kWindow = 32;       // chunks the encoder writes between two releases
constexpr std::size_t kAhead = 32;        // entries the decoder's mirror prefetches ahead

// The first violation of the layout in rows [begin, end), or "".
std::string layout_error(std::span<const uint64_t> offsets, std::span<const uint32_t> neighbors,
                         uint64_t begin, uint64_t end) {
  const uint64_t n = offsets.size() - 1;
  for (uint64_t i = begin; i < end; ++i) {
    if (offsets[i + 1] < offsets[i]) return "offsets decrease at row " + std::to_string(i);
    for (uint64_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      if (neighbors[k] >= n || neighbors[k] == i)
        return "row " + std::to_string(i) + ": bad index " + std::to_string(neighbors[k]);
      if (k > offsets[i] && neighbors[k] <= neighbors[k - 1])
        return "row " + std::to_string(i) + " is not strictly ascending";
    }
  }
  return {};
}

// A bounds-checked reader over the payload; every failure names the byte and the row.
class Cursor {
 public:
  Cursor(std::span<const uint8_t> bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  std::size_t pos() const { return pos_; }
  std::size_t left() const { return bytes_.size() - pos_; }

  [[noreturn]] void fail(uint64_t row, std::size_t at, const std::string& what) const {
    throw_bad_input(name_, "graph payload: row " + std::to_string(row) + ": byte " +
                               std::to_string(at) + ": " + what);
  }

  uint64_t varint(uint64_t row) {
    const std::size_t start = pos_;
    uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      if (pos_ >= bytes_.size()) fail(row, start, "truncated varint");
      const uint8_t b = bytes_[pos_++];
      if (shift == 63 && b > 1) fail(row, start, "varint overflows 64 bits");
      v |= static_cast<uint64_t>(b & 0x7F) << shift;
      if (!(b & 0x80)) {
        if (b == 0 && shift > 0) fail(row, start, "varint not in shortest form");
        return v;
      }
    }
  }

 private:
  std::span<const uint8_t> bytes_;
  const std::string& name_;
  std::size_t pos_ = 0;
};

// Passes the varints of rows [first, last) to put, in order.
template <class Put>
void code_rows(std::span<const uint64_t> offsets, std::span<const uint32_t> neighbors,
               NeighborListMode mode, uint64_t first, uint64_t last, Put&& put) {
  for (uint64_t i = first; i < last; ++i) {
    uint64_t begin = offsets[i];
    const uint64_t end = offsets[i + 1];
    if (mode == NeighborListMode::kUpper)
      while (begin < end && neighbors[begin] < i) ++begin;
    put(end - begin);
    for (uint64_t k = begin; k < end; ++k) {
      if (k > begin)
        put(uint64_t{neighbors[k]} - neighbors[k - 1] - 1);
      else if (mode == NeighborListMode::kUpper)
        put(neighbors[k] - i - 1);
      else
        put(zigzag(static_cast<int64_t>(neighbors[k]) - static_cast<int64_t>(i)));
    }
  }
}

}  // namespace

void check_neighbor_layout(std::span<const uint64_t> offsets, std::span<const uint32_t> neighbors) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("encode_neighbor_lists: " + what);
  };
  if (offsets.empty() || offsets[0] != 0 || offsets.back() != neighbors.size())
    fail("offsets must run from 0 to the neighbour count");
  const uint64_t n = offsets.size() - 1;
  if (n >= (uint64_t{1} << 32)) fail("more than 2^32 - 1 rows");
  // Chunks past a decreasing offset may read rows out of range: each chunk stops at its first
  // violation, and only the first chunk with one is reported.
  for (uint64_t i = 0; i < n; ++i)
    if (offsets[i + 1] < offsets[i]) fail("offsets decrease at row " + std::to_string(i));
  std::vector<std::string> errors(chunk_count(n, kRowChunk));
  for_each_chunk(n, kRowChunk, [&](std::size_t c, std::size_t begin, std::size_t end) {
    errors[c] = layout_error(offsets, neighbors, begin, end);
  });
  for (const std::string& e : errors)
    if (!e.empty()) fail(e);
}

namespace {

// append_neighbor_lists, and with `release` the neighbours' pages handed back as their rows are
// coded. The stream is sized first (chunks of rows in parallel), then written in windows of
// chunks: out grows by one window at a time (its pages are touched as they are written, not all
// up front), each window's chunks are written in place in parallel, and the rows before the
// window's end are released.
void append_rows(std::span<const uint64_t> offsets, std::span<const uint32_t> neighbors,
                 NeighborListMode mode, std::vector<uint8_t>& out, std::size_t room_after,
                 bool release) {
  const uint64_t n = offsets.size() - 1;
  const std::size_t chunks = chunk_count(n, kRowChunk);
  std::vector<std::size_t> at(chunks + 1, 0);
  for_each_chunk(n, kRowChunk, [&](std::size_t c, std::size_t first, std::size_t last) {
    std::size_t bytes = 0;
    code_rows(offsets, neighbors, mode, first, last, [&](uint64_t v) { bytes += varint_size(v); });
    at[c + 1] = bytes;
  });
  at[0] = out.size();
  for (std::size_t c = 1; c < at.size(); ++c) at[c] += at[c - 1];
  out.reserve(at.back() + room_after);
  uint64_t released = 0;  // neighbours before this entry are released
  for (std::size_t c0 = 0; c0 < chunks; c0 += kWindow) {
    const std::size_t c1 = std::min(chunks, c0 + kWindow);
    out.resize(at[c1]);
    tbb::parallel_for(c0, c1, [&](std::size_t c) {
      uint8_t* p = out.data() + at[c];
      code_rows(offsets, neighbors, mode, c * kRowChunk, std::min<uint64_t>(n, (c + 1) * kRowChunk),
                [&](uint64_t v) { p = write_varint(p, v); });
    });
    if (!release) continue;
    const uint64_t end = offsets[std::min<uint64_t>(n, c1 * kRowChunk)];
    release_pages(neighbors.data() + released, neighbors.data() + end);
    released = end;
  }
}

}  // namespace

void append_neighbor_lists(std::span<const uint64_t> offsets, std::span<const uint32_t> neighbors,
                           NeighborListMode mode, std::vector<uint8_t>& out,
                           std::size_t room_after) {
  append_rows(offsets, neighbors, mode, out, room_after, false);
}

void append_neighbor_lists(std::span<const uint64_t> offsets, std::vector<uint32_t>&& neighbors,
                           NeighborListMode mode, std::vector<uint8_t>& out,
                           std::size_t room_after) {
  append_rows(offsets, neighbors, mode, out, room_after, true);
  std::vector<uint32_t>().swap(neighbors);
}

std::vector<uint8_t> encode_neighbor_lists(std::span<const uint64_t> offsets,
                                           std::span<const uint32_t> neighbors,
                                           NeighborListMode mode) {
  check_neighbor_layout(offsets, neighbors);
  std::vector<uint8_t> out;
  append_neighbor_lists(offsets, neighbors, mode, out);
  return out;
}

namespace {

// Parses and checks every row of the stream: row(i, degree, at) before its entries (at: the row's
// first byte), entry(i, j) for each (j in range, never i). Throws on the first malformed byte.
template <class Row, class Entry>
void parse_rows(std::span<const uint8_t> bytes, uint64_t num_rows, NeighborListMode mode,
                const std::string& name, Row&& row, Entry&& entry) {
  Cursor in(bytes, name);
  for (uint64_t i = 0; i < num_rows; ++i) {
    const std::size_t at = in.pos();
    const uint64_t degree = in.varint(i);
    if (degree > in.left())  // each entry takes at least one byte
      in.fail(i, at,
              "degree " + std::to_string(degree) + " exceeds the " + std::to_string(in.left()) +
                  " bytes left");
    row(i, degree, at);
    uint64_t prev = 0;
    for (uint64_t k = 0; k < degree; ++k) {
      const std::size_t entry_at = in.pos();
      const uint64_t code = in.varint(i);
      uint64_t j;
      // A code >= num_rows gives an index >= num_rows; testing it first keeps the sums below
      // from wrapping around 2^64 back into range.
      if (k > 0) {
        j = code >= num_rows ? ~uint64_t{0} : prev + 1 + code;
      } else if (mode == NeighborListMode::kUpper) {
        j = code >= num_rows ? ~uint64_t{0} : i + 1 + code;
      } else {
        const int64_t delta = unzigzag(code);
        // i < 2^64 / 2 here (num_rows <= bytes.size()), so the sum cannot wrap past a valid index.
        j = delta < 0 && static_cast<uint64_t>(-(delta + 1)) >= i
                ? ~uint64_t{0}
                : i + static_cast<uint64_t>(delta);
      }
      // kFull rows may pass over their own index (0 -> 1 -> 3 in row 2) but never land on it.
      if (j == i) in.fail(i, entry_at, "row lists its own index");
      if (j >= num_rows)
        in.fail(i, entry_at,
                "neighbour index " +
                    (j == ~uint64_t{0} ? std::string("overflow") : std::to_string(j)) +
                    " out of range (rows: " + std::to_string(num_rows) + ")");
      entry(i, static_cast<uint32_t>(j));
      prev = j;
    }
  }
  if (in.left() != 0)
    throw_bad_input(name, "graph payload: byte " + std::to_string(in.pos()) + ": " +
                              std::to_string(in.left()) + " trailing bytes after the last row");
}

// A varint of a stream parse_rows has checked.
inline uint64_t checked_varint(const uint8_t*& p) {
  uint64_t v = 0;
  for (int shift = 0;; shift += 7) {
    const uint8_t b = *p++;
    v |= static_cast<uint64_t>(b & 0x7F) << shift;
    if (!(b & 0x80)) return v;
  }
}

constexpr std::size_t kDecodeRows = 16384;  // rows per parallel task of the kUpper decoder
constexpr std::size_t kBlock = 4096;  // entries a task gathers before it visits their rows

// kUpper: the full rows straight from the stream, so that the stored halves are never held.
// Row j = the i < j that store j, ascending, then its own stored j' > j.
//  1. One sequential pass checks the stream, and notes each row's stored degree and where every
//     task's rows start (byte, and stored entries before them).
//  2. In parallel, each stored (i, j) counts one more entry in row j's lower part (an atomic
//     add: a walk in random order through the rows of a cloud in no spatial order, so the
//     entries are gathered in blocks and each add is fetched kAhead entries early).
//  3. The row offsets are summed; in parallel again, every stored (i, j) goes into row i's own
//     part, where its place is known, and at the next free place of row j's lower part (atomic).
//  4. Each lower part is sorted: the rows of a sequential decode, for any thread count.
NeighborLists decode_upper(std::span<const uint8_t> bytes, uint64_t num_rows,
                           const std::string& name, std::span<const uint8_t> upper_values,
                           std::vector<uint8_t>* values) {
  NeighborLists full;
  std::vector<uint64_t>& offsets = full.offsets;  // row i's stored degree at i + 1, then sums
  offsets.assign(num_rows + 1, 0);
  std::vector<std::size_t> task_byte;  // where task t's first row starts
  std::vector<uint64_t> task_entry;    // the stored entries before it
  task_byte.reserve(chunk_count(num_rows, kDecodeRows));
  task_entry.reserve(chunk_count(num_rows, kDecodeRows));
  uint64_t entries = 0;
  parse_rows(
      bytes, num_rows, NeighborListMode::kUpper, name,
      [&](uint64_t i, uint64_t degree, std::size_t at) {
        if (i % kDecodeRows == 0) {
          task_byte.push_back(at);
          task_entry.push_back(entries);
        }
        offsets[i + 1] = degree;
        entries += degree;
      },
      [](uint64_t, uint32_t) {});

  // lower[j]: the entries of row j stored by earlier rows; counted, then counted again as they
  // are placed.
  std::vector<uint32_t> lower;
  sized_in_parallel(lower, num_rows);
  auto bump = [&](uint32_t j) {
    return std::atomic_ref<uint32_t>(lower[j]).fetch_add(1, std::memory_order_relaxed);
  };
  for_each_chunk(num_rows, kDecodeRows, [&](std::size_t t, std::size_t first, std::size_t last) {
    std::vector<uint32_t> block;
    block.reserve(kBlock);
    auto count = [&] {
      for (std::size_t k = 0; k < block.size(); ++k) {
        if (k + kAhead < block.size()) __builtin_prefetch(&lower[block[k + kAhead]], 1);
        bump(block[k]);
      }
      block.clear();
    };
    const uint8_t* p = bytes.data() + task_byte[t];
    for (uint64_t i = first; i < last; ++i) {
      const uint64_t degree = checked_varint(p);
      if (block.size() + degree > kBlock) count();
      uint64_t j = i;
      for (uint64_t k = 0; k < degree; ++k) block.push_back(j += 1 + checked_varint(p));
    }
    count();
  });
  for (uint64_t i = 0; i < num_rows; ++i) {
    offsets[i + 1] += offsets[i] + lower[i];
    lower[i] = 0;
  }

  sized_in_parallel(full.neighbors, offsets[num_rows]);
  const bool mirror_values = values != nullptr && upper_values.size() == entries;
  if (values != nullptr) values->clear();
  if (mirror_values) sized_in_parallel(*values, full.neighbors.size());
  uint32_t* const neighbors = full.neighbors.data();
  uint8_t* const value = mirror_values ? values->data() : nullptr;
  struct Mirror {
    uint32_t i, j;
    uint64_t own;  // the entry's place in row i
  };
  for_each_chunk(num_rows, kDecodeRows, [&](std::size_t t, std::size_t first, std::size_t last) {
    std::vector<Mirror> block;
    block.reserve(kBlock);
    auto mirror = [&] {
      for (std::size_t k = 0; k < block.size(); ++k) {
        if (k + kAhead < block.size()) {
          __builtin_prefetch(&offsets[block[k + kAhead].j]);
          __builtin_prefetch(&lower[block[k + kAhead].j], 1);
        }
        if (k + kAhead / 2 < block.size()) {
          const uint32_t soon = block[k + kAhead / 2].j;
          __builtin_prefetch(&neighbors[offsets[soon] + lower[soon]], 1);
          if (value) __builtin_prefetch(&value[offsets[soon] + lower[soon]], 1);
        }
        const Mirror& m = block[k];
        const uint64_t at = offsets[m.j] + bump(m.j);
        neighbors[at] = m.i;
        if (value) value[at] = value[m.own];
      }
      block.clear();
    };
    const uint8_t* p = bytes.data() + task_byte[t];
    uint64_t stored = task_entry[t];  // upper_values' index of the next stored entry
    for (uint64_t i = first; i < last; ++i) {
      const uint64_t degree = checked_varint(p);
      if (block.size() + degree > kBlock) mirror();
      uint64_t own = offsets[i + 1] - degree, j = i;
      for (uint64_t k = 0; k < degree; ++k, ++own) {
        j += 1 + checked_varint(p);
        neighbors[own] = static_cast<uint32_t>(j);
        if (value) value[own] = upper_values[stored++];
        block.push_back({static_cast<uint32_t>(i), static_cast<uint32_t>(j), own});
      }
    }
    mirror();
  });

  for_each_chunk(num_rows, kDecodeRows, [&](std::size_t, std::size_t first, std::size_t last) {
    for (std::size_t j = first; j < last; ++j) {
      const uint64_t b = offsets[j], e = b + lower[j];
      for (uint64_t k = b + 1; k < e; ++k) {  // insertion sort: a few entries each
        const uint32_t n = neighbors[k];
        const uint8_t v = value ? value[k] : 0;
        uint64_t at = k;
        for (; at > b && neighbors[at - 1] > n; --at) {
          neighbors[at] = neighbors[at - 1];
          if (value) value[at] = value[at - 1];
        }
        neighbors[at] = n;
        if (value) value[at] = v;
      }
    }
  });
  return full;
}

}  // namespace

NeighborLists decode_neighbor_lists(std::span<const uint8_t> bytes, uint64_t num_rows,
                                    NeighborListMode mode, const std::string& name,
                                    std::span<const uint8_t> upper_values,
                                    std::vector<uint8_t>* values) {
  if (mode != NeighborListMode::kFull && mode != NeighborListMode::kUpper)
    throw_bad_input(name, "graph payload: unknown neighbour list mode " +
                              std::to_string(static_cast<int>(mode)));
  // Every row takes at least its degree byte: bounds the allocations by the payload size.
  if (num_rows > bytes.size())
    throw_bad_input(name, "graph payload: " + std::to_string(num_rows) + " rows cannot fit in " +
                              std::to_string(bytes.size()) + " bytes");
  if (mode == NeighborListMode::kUpper)
    return decode_upper(bytes, num_rows, name, upper_values, values);
  NeighborLists rows;
  rows.offsets.reserve(num_rows + 1);
  rows.offsets.push_back(0);
  // At most one entry per byte left after the degrees: room for all of a usual graph's entries
  // (no regrowth and copy), capped so that a hostile payload cannot reserve much more.
  rows.neighbors.reserve(std::min<uint64_t>(bytes.size() - num_rows, 32 * num_rows));
  parse_rows(
      bytes, num_rows, mode, name,
      [&](uint64_t i, uint64_t, std::size_t) {  // a row starts: the previous one has ended
        if (i > 0) rows.offsets.push_back(rows.neighbors.size());
      },
      [&](uint64_t, uint32_t j) { rows.neighbors.push_back(j); });
  if (num_rows > 0) rows.offsets.push_back(rows.neighbors.size());
  return rows;
}

}  // namespace splatkit::graph
