#include "graph_io/graph_chunks.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "formats/splk.h"
#include "graph/neighbor_list_codec.h"
#include "graph/varint.h"
#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit::graph {
namespace {

constexpr uint32_t kChunkFlags = kSplkChunkTiedToSplats;

RawChunk make_chunk(const char (&type)[4], std::vector<unsigned char> payload) {
  RawChunk chunk;
  std::memcpy(chunk.type, type, 4);
  chunk.flags = kChunkFlags;
  chunk.payload = std::move(payload);
  return chunk;
}

void put_u8(std::vector<unsigned char>& out, uint8_t v) { out.push_back(v); }
void put_le(std::vector<unsigned char>& out, uint64_t v, int bytes) {
  for (int b = 0; b < bytes; ++b) out.push_back(static_cast<unsigned char>(v >> (8 * b)));
}

// Bounds-checked little-endian reader over one chunk payload; every failure names the chunk and
// the byte offset inside its payload.
class PayloadReader {
 public:
  PayloadReader(const RawChunk& chunk, const std::string& name)
      : bytes_(chunk.payload), name_(name), type_(chunk.type, 4) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw_bad_input(name_, type_ + " chunk, payload byte " + std::to_string(pos_) + ": " + what);
  }
  uint64_t remaining() const { return bytes_.size() - pos_; }
  std::size_t pos() const { return pos_; }

  uint64_t le(int size, const char* field) {
    if (remaining() < static_cast<uint64_t>(size))
      fail(std::string("truncated: ") + field + " needs " + std::to_string(size) + " bytes, " +
           std::to_string(remaining()) + " left");
    uint64_t v = 0;
    for (int b = 0; b < size; ++b) v |= uint64_t{bytes_[pos_ + b]} << (8 * b);
    pos_ += size;
    return v;
  }
  uint64_t varint(const char* field) {
    uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      if (remaining() == 0) fail(std::string("truncated varint (") + field + ")");
      const uint8_t byte = bytes_[pos_++];
      if (shift == 63 && byte > 1) fail(std::string("varint over 64 bits (") + field + ")");
      v |= uint64_t{byte & 0x7fu} << shift;
      if ((byte & 0x80) == 0) {
        if (byte == 0 && shift > 0) fail(std::string("non-shortest varint (") + field + ")");
        return v;
      }
    }
  }
  std::span<const unsigned char> take(uint64_t size) {
    std::span<const unsigned char> s(bytes_.data() + pos_, size);
    pos_ += size;
    return s;
  }
  // The leading u64 N every payload starts with must equal SPLT's count.
  void splat_count(uint64_t num_splats) {
    const uint64_t n = le(8, "splat count");
    if (n != num_splats)
      fail("splat count " + std::to_string(n) + " differs from SPLT's " +
           std::to_string(num_splats));
  }
  void end() {
    if (remaining() != 0) fail(std::to_string(remaining()) + " trailing bytes after the data");
  }

 private:
  const std::vector<unsigned char>& bytes_;
  const std::string& name_;
  std::string type_;
  std::size_t pos_ = 0;
};

}  // namespace

const RawChunk* find_chunk(const LoadedCloud& doc, const char (&type)[4]) {
  for (const RawChunk& c : doc.chunks)
    if (std::memcmp(c.type, type, 4) == 0) return &c;
  return nullptr;
}

const RawChunk* find_single_chunk(const LoadedCloud& doc, const char (&type)[4], const char* what,
                                  const std::string& name) {
  const RawChunk* found = nullptr;
  for (const RawChunk& c : doc.chunks) {
    if (std::memcmp(c.type, type, 4) != 0) continue;
    if (found != nullptr)
      throw_bad_input(
          name, "two " + std::string(type, 4) + " chunks (" + what + "); a file holds at most one");
    found = &c;
  }
  return found;
}

void put_chunk(LoadedCloud& doc, RawChunk chunk) {
  for (RawChunk& c : doc.chunks)
    if (std::memcmp(c.type, chunk.type, 4) == 0) {
      c = std::move(chunk);
      return;
    }
  doc.chunks.push_back(std::move(chunk));
}

namespace {

// encode_graph_chunk; with `consumed` (the graph's neighbours and the flags, which edge_flags
// and graph.neighbors view) the flags are freed once packed and the neighbours as they are coded.
struct Consumed {
  std::vector<uint32_t>& neighbors;
  std::vector<uint8_t>& flags;
};

RawChunk encode_graph(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                      float sharp_threshold, const Consumed* consumed) {
  if (edge_flags.size() != graph.neighbors.size())
    throw std::invalid_argument("encode_graph_chunk: edge_flags does not match the graph");
  check_neighbor_layout(graph.offsets, graph.neighbors);
  // The upper edges' 2-bit flags, four to a byte, in edge order: fixed chunks of rows count
  // their upper edges, then pack theirs after the earlier chunks', in parallel. A byte that two
  // chunks share (at most the first and the last of each) is written with an atomic OR.
  constexpr std::size_t kRows = 16384;
  const std::size_t n = graph.num_points(), chunks = chunk_count(n, kRows);
  std::vector<uint64_t> first(chunks + 1, 0);
  for_each_chunk(n, kRows, [&](std::size_t c, std::size_t begin, std::size_t end) {
    uint64_t count = 0;  // without branches: half of each row is below i
    for (std::size_t i = begin; i < end; ++i)
      for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k)
        count += graph.neighbors[k] > i;
    first[c + 1] = count;
  });
  for (std::size_t c = 0; c < chunks; ++c) first[c + 1] += first[c];
  const uint64_t edges = first[chunks];
  std::vector<uint8_t> bits((edges + 3) / 4);
  for_each_chunk(n, kRows, [&](std::size_t c, std::size_t begin, std::size_t end) {
    if (first[c] == first[c + 1]) return;
    const uint64_t shared_first = first[c] / 4, shared_last = (first[c + 1] - 1) / 4;
    uint64_t e = first[c];
    unsigned byte = 0;
    auto flush = [&](uint64_t b) {
      if (b == shared_first || b == shared_last)
        std::atomic_ref<uint8_t>(bits[b]).fetch_or(static_cast<uint8_t>(byte),
                                                   std::memory_order_relaxed);
      else
        bits[b] = static_cast<uint8_t>(byte);
      byte = 0;
    };
    for (std::size_t i = begin; i < end; ++i)
      for (uint64_t k = graph.offsets[i]; k < graph.offsets[i + 1]; ++k) {
        if (graph.neighbors[k] < i) continue;
        byte |= (edge_flags[k] & 3u) << (2 * (e % 4));
        if (++e % 4 == 0) flush(e / 4 - 1);
      }
    if (e % 4 != 0) flush(e / 4);
  });
  if (consumed) std::vector<uint8_t>().swap(consumed->flags);
  // The payload is built in place, the stream's length patched in after it (the stream is the
  // chunk's bulk: a copy of it had been the graph tools' peak of memory).
  std::vector<unsigned char> out;
  put_le(out, graph.num_points(), 8);
  put_u8(out, static_cast<uint8_t>(NeighborListMode::kUpper));
  put_u8(out, 0);
  put_le(out, edges, 8);
  put_le(out, std::bit_cast<uint32_t>(sharp_threshold), 4);
  const std::size_t length_at = out.size();
  put_le(out, 0, 8);
  if (consumed)
    append_neighbor_lists(graph.offsets, std::move(consumed->neighbors), NeighborListMode::kUpper,
                          out, bits.size());
  else
    append_neighbor_lists(graph.offsets, graph.neighbors, NeighborListMode::kUpper, out,
                          bits.size());
  const uint64_t stream_bytes = out.size() - length_at - 8;
  for (std::size_t b = 0; b < 8; ++b)
    out[length_at + b] = static_cast<unsigned char>(stream_bytes >> (8 * b));
  out.insert(out.end(), bits.begin(), bits.end());
  return make_chunk(kGraphChunkType, std::move(out));
}

}  // namespace

RawChunk encode_graph_chunk(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                            float sharp_threshold) {
  return encode_graph(graph, edge_flags, sharp_threshold, nullptr);
}

RawChunk encode_graph_chunk(NeighborGraph&& graph, std::vector<uint8_t>&& edge_flags,
                            float sharp_threshold) {
  const Consumed consumed{graph.neighbors, edge_flags};
  RawChunk chunk = encode_graph(graph, edge_flags, sharp_threshold, &consumed);
  graph = NeighborGraph();
  return chunk;
}

DecodedGraph decode_graph_chunk(const RawChunk& chunk, uint64_t num_splats,
                                const std::string& name) {
  PayloadReader in(chunk, name);
  in.splat_count(num_splats);
  const uint64_t mode = in.le(1, "mode");
  if (mode != static_cast<uint8_t>(NeighborListMode::kUpper))
    in.fail("unknown graph mode " + std::to_string(mode) + " (1.x writes 1, upper)");
  const uint64_t flags = in.le(1, "flags");
  if (flags != 0) in.fail("reserved flag bits set: " + std::to_string(flags));
  const uint64_t edges = in.le(8, "edge count");
  DecodedGraph out;
  out.sharp_threshold = std::bit_cast<float>(static_cast<uint32_t>(in.le(4, "w_s")));
  if (!(out.sharp_threshold >= -1.0f && out.sharp_threshold <= 1.0f))
    in.fail("sharp threshold w_s is not a number in [-1, 1]");
  const uint64_t stream_bytes = in.le(8, "stream length");
  if (stream_bytes > in.remaining())
    in.fail("neighbour stream of " + std::to_string(stream_bytes) + " bytes, only " +
            std::to_string(in.remaining()) + " left");
  // Upper mode spends at least one byte per stored edge, and the flag bytes follow it.
  const uint64_t after_stream = in.remaining() - stream_bytes;
  if (edges > stream_bytes || (edges + 3) / 4 != after_stream)
    in.fail("edge count " + std::to_string(edges) + " does not fit a " +
            std::to_string(stream_bytes) + "-byte stream and " + std::to_string(after_stream) +
            " flag bytes");
  const std::size_t stream_pos = in.pos();
  const std::span<const unsigned char> stream = in.take(stream_bytes);
  const std::span<const unsigned char> bits = in.take(after_stream);
  // The flag of each stored edge, one byte each, so that the decoder puts it at both ends of
  // the edge in the pass that mirrors the rows (one walk through the rows in random order, not
  // two). Checked below, in the order the errors were always reported.
  constexpr std::size_t kFlagChunk = std::size_t{1} << 20;  // flags per parallel task
  std::vector<uint8_t> stored_flags(edges);
  for_each_chunk(edges, kFlagChunk, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e) stored_flags[e] = (bits[e / 4] >> (2 * (e % 4))) & 3u;
  });
  NeighborLists lists =
      decode_neighbor_lists(stream, num_splats, NeighborListMode::kUpper,
                            name + ", GRPH chunk at payload byte " + std::to_string(stream_pos),
                            stored_flags, &out.edge_flags);
  out.graph.offsets = std::move(lists.offsets);
  out.graph.neighbors = std::move(lists.neighbors);
  if (out.graph.neighbors.size() != 2 * edges)
    in.fail("the stream holds " + std::to_string(out.graph.neighbors.size() / 2) +
            " edges, the header says " + std::to_string(edges));
  if (edges % 4 != 0 && (bits.back() >> (2 * (edges % 4))) != 0)
    in.fail("unused bits of the last edge-flag byte are set");
  // The first crossing edge that is not sharp.
  const std::size_t crossing = first_in_chunks(
      edges, kFlagChunk, [&](std::size_t e) { return stored_flags[e] == kEdgeCrossing; });
  if (crossing < edges) in.fail("edge " + std::to_string(crossing) + " crosses but is not sharp");
  return out;
}

RawChunk encode_class_chunk(std::span<const SplatClass> classes) {
  std::vector<unsigned char> out;
  out.reserve(8 + classes.size());
  put_le(out, classes.size(), 8);
  for (SplatClass c : classes) put_u8(out, static_cast<uint8_t>(c));
  return make_chunk(kClassChunkType, std::move(out));
}

std::vector<SplatClass> decode_class_chunk(const RawChunk& chunk, uint64_t num_splats,
                                           const std::string& name) {
  PayloadReader in(chunk, name);
  in.splat_count(num_splats);
  if (in.remaining() < num_splats)
    in.fail("truncated: " + std::to_string(num_splats) + " classes, " +
            std::to_string(in.remaining()) + " bytes left");
  std::vector<SplatClass> classes(num_splats);
  for (uint64_t i = 0; i < num_splats; ++i) {
    const uint64_t c = in.le(1, "class");
    if (c > static_cast<uint8_t>(SplatClass::kIntersection))
      in.fail("unknown class " + std::to_string(c) + " of splat " + std::to_string(i));
    classes[i] = static_cast<SplatClass>(c);
  }
  in.end();
  return classes;
}

RawChunk encode_clip_chunk(const ClipPartnerTable& table) {
  table.check_consistent();
  const std::size_t n = table.num_splats();
  uint64_t records = 0;
  for (std::size_t i = 0; i < n; ++i) records += table.offsets[i + 1] > table.offsets[i];
  std::vector<unsigned char> out;
  put_le(out, n, 8);
  put_le(out, records, 8);
  put_le(out, table.partners.size(), 8);
  uint64_t next = 0;  // the first index the next record may have
  for (std::size_t i = 0; i < n; ++i) {
    const uint64_t begin = table.offsets[i], end = table.offsets[i + 1];
    if (begin == end) continue;
    put_varint(out, i - next);
    next = i + 1;
    put_u8(out, table.splat_flags[i]);
    put_varint(out, end - begin);
    for (uint64_t k = begin; k < end; ++k) {
      put_varint(out, zigzag(static_cast<int64_t>(table.partners[k]) - static_cast<int64_t>(i)));
      put_u8(out, table.flags[k]);
    }
  }
  return make_chunk(kClipChunkType, std::move(out));
}

ClipPartnerTable decode_clip_chunk(const RawChunk& chunk, uint64_t num_splats,
                                   const std::string& name) {
  PayloadReader in(chunk, name);
  in.splat_count(num_splats);
  const uint64_t records = in.le(8, "record count");
  const uint64_t partners = in.le(8, "partner count");
  if (records > num_splats)
    in.fail(std::to_string(records) + " records for " + std::to_string(num_splats) + " splats");
  if (partners > kMaxClipPartners)
    in.fail(std::to_string(partners) + " partners: more than 2^32 - 1");
  // A record takes at least 3 bytes plus 2 per partner.
  if (records > in.remaining() / 3 || partners > in.remaining() / 2)
    in.fail(std::to_string(records) + " records / " + std::to_string(partners) +
            " partners do not fit the " + std::to_string(in.remaining()) + " bytes left");
  ClipPartnerTable table;
  table.offsets.assign(num_splats + 1, 0);
  table.splat_flags.assign(num_splats, 0);
  table.partners.reserve(partners);
  table.flags.reserve(partners);
  uint64_t next = 0;
  for (uint64_t r = 0; r < records; ++r) {
    const uint64_t skip = in.varint("splat index delta");
    if (skip >= num_splats - next)
      in.fail("record " + std::to_string(r) + ": splat index past the splat count");
    const uint64_t i = next + skip;
    const auto filled = static_cast<uint32_t>(table.partners.size());
    for (uint64_t s = next; s <= i; ++s) table.offsets[s + 1] = filled;
    const uint64_t splat_flags = in.le(1, "splat flags");
    if ((splat_flags & ~uint64_t{kClipSplatFlagsKnown}) != 0)
      in.fail("unknown splat flag bits " + std::to_string(splat_flags));
    table.splat_flags[i] = static_cast<uint8_t>(splat_flags);
    const uint64_t count = in.varint("partner count");
    if (count == 0) in.fail("record of splat " + std::to_string(i) + " has no partners");
    if (count > partners - table.partners.size())
      in.fail("record of splat " + std::to_string(i) + ": more partners than the header's " +
              std::to_string(partners));
    for (uint64_t k = 0; k < count; ++k) {
      const uint64_t code = in.varint("partner delta");
      const int64_t delta = unzigzag(code);
      // |delta| < 2^63 and i < 2^32 here, so the sum is computed without overflow in int64 when
      // it is in range; anything else is rejected before the cast.
      if (delta == 0) in.fail("splat " + std::to_string(i) + " is its own clip partner");
      if ((delta < 0 && static_cast<uint64_t>(-(delta + 1)) >= i) ||
          (delta > 0 && static_cast<uint64_t>(delta) >= num_splats - i))
        in.fail("clip partner of splat " + std::to_string(i) + " out of range");
      const uint64_t flags = in.le(1, "partner flags");
      if ((flags & ~uint64_t{kClipPartnerFlagsKnown}) != 0)
        in.fail("unknown partner flag bits " + std::to_string(flags));
      if (k == 0 && (flags & kClipSubsetStart) == 0)
        in.fail("first partner of splat " + std::to_string(i) + " does not start a subset");
      table.partners.push_back(static_cast<uint32_t>(static_cast<int64_t>(i) + delta));
      table.flags.push_back(static_cast<uint8_t>(flags));
    }
    table.offsets[i + 1] = static_cast<uint32_t>(table.partners.size());
    next = i + 1;
  }
  if (table.partners.size() != partners)
    in.fail("records hold " + std::to_string(table.partners.size()) +
            " partners, the header says " + std::to_string(partners));
  for (uint64_t s = next; s < num_splats; ++s)
    table.offsets[s + 1] = static_cast<uint32_t>(table.partners.size());
  in.end();
  return table;
}

RawChunk encode_surface_chunk(const Segmentation& segmentation) {
  std::vector<unsigned char> out;
  out.reserve(12 + 4 * segmentation.surface.size());
  put_le(out, segmentation.surface.size(), 8);
  put_le(out, segmentation.count(), 4);
  for (uint32_t id : segmentation.surface) put_le(out, id, 4);
  return make_chunk(kSurfaceChunkType, std::move(out));
}

Segmentation decode_surface_chunk(const RawChunk& chunk, uint64_t num_splats,
                                  const std::string& name) {
  PayloadReader in(chunk, name);
  in.splat_count(num_splats);
  const uint64_t count = in.le(4, "surface count");
  if (count > num_splats)
    in.fail(std::to_string(count) + " surfaces for " + std::to_string(num_splats) + " splats");
  if (in.remaining() / 4 < num_splats)
    in.fail("truncated: " + std::to_string(num_splats) + " surface ids, " +
            std::to_string(in.remaining()) + " bytes left");
  Segmentation seg;
  seg.surface.resize(num_splats);
  seg.sizes.assign(count, 0);
  uint32_t next_new = 0;  // ids appear first in ascending order
  for (uint64_t i = 0; i < num_splats; ++i) {
    const uint32_t id = static_cast<uint32_t>(in.le(4, "surface id"));
    if (id != kNoSurface) {
      if (id >= count)
        in.fail("surface id " + std::to_string(id) + " of splat " + std::to_string(i) +
                " is not below the surface count " + std::to_string(count));
      if (id > next_new)
        in.fail("surface id " + std::to_string(id) + " of splat " + std::to_string(i) +
                " appears before id " + std::to_string(next_new));
      if (id == next_new) ++next_new;
      ++seg.sizes[id];
    }
    seg.surface[i] = id;
  }
  if (next_new != count)
    in.fail("surface ids " + std::to_string(next_new) + ".." + std::to_string(count - 1) +
            " are never used");
  in.end();
  return seg;
}

}  // namespace splatkit::graph
