// Compact coding of neighbour lists (compressed rows of splat indices): the payload of the graph
// chunk. Varint (LEB128) + delta coding; safe for untrusted input.
//
// Rows are strictly ascending lists of indices in [0, n), never the row's own index (the layout
// of splatkit::NeighborGraph). Byte stream, row after row, nothing else (the container chunk
// around it states n and the mode and carries the checksum):
//
//   kFull  — every row in full:  varint(degree), then for degree > 0
//            varint(zigzag(j_0 - i)), varint(j_1 - j_0 - 1), ..., varint(j_last - j_prev - 1)
//   kUpper — a symmetric graph, each edge once: row i holds only its neighbours j > i:
//            varint(count), then varint(j_0 - i - 1), varint(j_1 - j_0 - 1), ...
//            The decoder mirrors every stored (i, j) into row j, giving the full rows back.
//
// varint: unsigned LEB128, 7 bits per byte, low group first, high bit = more bytes follow; at
// most 10 bytes (64 bits), shortest form only. zigzag(x) = (x << 1) ^ (x >> 63).
// Indices of a spatially ordered cloud are close to their row's, so most deltas take one byte:
// kUpper costs about one byte per undirected edge plus one per row (figures: docs/design/graph.md
// and docs/design/spatial-index.md).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace splatkit::graph {

enum class NeighborListMode : uint8_t { kFull = 0, kUpper = 1 };

struct NeighborLists {
  std::vector<uint64_t> offsets;    // #n + 1, offsets[0] = 0
  std::vector<uint32_t> neighbors;  // row i = neighbors[offsets[i] .. offsets[i + 1])
};

// Encodes rows offsets (#n + 1) / neighbors. Throws std::invalid_argument if the input breaks the
// layout: offsets empty, not starting at 0, decreasing, not ending at neighbors.size(); a row not
// strictly ascending, holding its own index or an index >= n; n >= 2^32. kUpper assumes the
// graph is symmetric (j in row i iff i in row j) and stores only the j > i entries; a
// non-symmetric input is not detected and decodes to its symmetric closure of those entries.
std::vector<uint8_t> encode_neighbor_lists(std::span<const uint64_t> offsets,
                                           std::span<const uint32_t> neighbors,
                                           NeighborListMode mode);
// The layout check of encode_neighbor_lists alone: throws std::invalid_argument naming the first
// violation (the same one for any thread count).
void check_neighbor_layout(std::span<const uint64_t> offsets, std::span<const uint32_t> neighbors);
// encode_neighbor_lists' bytes appended to `out`, for rows that passed check_neighbor_layout;
// out's capacity is made room_after bytes larger than they need, for what the caller appends next
// (a graph chunk's flags), so that growing it does not copy the stream.
void append_neighbor_lists(std::span<const uint64_t> offsets, std::span<const uint32_t> neighbors,
                           NeighborListMode mode, std::vector<uint8_t>& out,
                           std::size_t room_after = 0);
// The same bytes for rows the caller is done with: the neighbours' pages are handed back to the
// system as their rows are coded (lib/graph/release_pages.h), so that the rows and their code
// are not both held in full; `neighbors` is left empty.
void append_neighbor_lists(std::span<const uint64_t> offsets, std::vector<uint32_t>&& neighbors,
                           NeighborListMode mode, std::vector<uint8_t>& out,
                           std::size_t room_after = 0);

// Decodes num_rows rows. Treats bytes as hostile: throws splatkit::Error (kBadInput) via
// throw_bad_input(name, ...) with its own message for each case — a row count larger than the
// payload can hold, a truncated varint, a varint over 64 bits, a non-shortest varint, a degree
// larger than the bytes left, a neighbour index out of range (also what a delta overflowing past
// n gives: rows cannot be non-monotone by construction), a row holding its own index (kFull), and
// bytes left after the last row. Allocates at most O(bytes.size() + num_rows).
//
// kUpper with `upper_values` (one byte per stored entry, in stream order) and `values`: each
// stored entry's byte is also put at both of its places in the full rows (values: #entries of
// the result), in the same pass that mirrors the rows; when the stream stores another number of
// entries than upper_values holds, values is left empty (the caller reports the mismatch).
NeighborLists decode_neighbor_lists(std::span<const uint8_t> bytes, uint64_t num_rows,
                                    NeighborListMode mode, const std::string& name,
                                    std::span<const uint8_t> upper_values = {},
                                    std::vector<uint8_t>* values = nullptr);

}  // namespace splatkit::graph
