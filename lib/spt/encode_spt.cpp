#include "spt/encode_spt.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <limits>
#include <utility>

#include "formats/spt_codes.h"
#include "splatkit/aligned_buffer.h"
#include "splatkit/crc32c.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit::spt {

namespace {

using Clock = std::chrono::steady_clock;

// The nodes in node order as a sequence q = 0, 1, ...: the leaves, then the interior slots.
struct NodeSequence {
  std::size_t n = 0, total = 0;

  explicit NodeSequence(const SptTree& t) : n(t.leaves), total(t.size()) {}
  // f(is_leaf, index: leaf or slot) for q in [q0, q1), in order.
  template <class F>
  void each(std::size_t q0, std::size_t q1, F&& f) const {
    for (std::size_t q = q0; q < std::min(q1, n); ++q) f(true, static_cast<uint32_t>(q));
    for (std::size_t q = std::max(q0, n); q < q1; ++q) f(false, static_cast<uint32_t>(q - n));
  }
  uint32_t node(bool leaf, uint32_t index) const {
    return leaf ? index : static_cast<uint32_t>(n + index);
  }
};

}  // namespace

template <class T>
void release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

EncodedSpt encode_spt(SptTree& tree, SptSplats& in, const EncodeSptOptions& o, const SptSink& sink,
                      bool keep_map) {
  const std::size_t n = tree.leaves;
  const NodeSequence seq(tree);
  const std::size_t total = seq.total;
  SptHeader h;
  h.flags = (o.full ? kSptFlagFull : 0u) | (in.colors.empty() ? 0u : kSptFlagColor);
  h.entry_bytes = o.full ? kSptFullEntryBytes : kSptCompactEntryBytes;
  h.depth = tree.depth;
  h.input_points = n;
  h.origin = o.origin;
  h.epsilon = o.epsilon;
  h.color_weight = o.color_weight;
  h.box_min = tree.box_min;
  h.step = tree.step;

  // r = e_g / epsilon, kept finite (a far outlier can push it past the float range).
  auto r_of = [&](float error) {
    return std::min(error / o.epsilon, std::numeric_limits<float>::max());
  };
  h.r_lo = tree.error_lo <= tree.error_hi ? r_of(tree.error_lo) : 1.0f;
  h.r_hi = tree.error_lo <= tree.error_hi ? r_of(tree.error_hi) : 1.0f;
  // The decoded centre is within half a step per axis: the disc grows by that much.
  const float slack =
      o.full ? 0.0f
             : static_cast<float>(
                   0.5 * std::hypot(double(h.step.x), double(h.step.y), double(h.step.z)) * 1.0001);
  if (tree.radius_lo <= tree.radius_hi) {  // kept finite likewise (a radius near 3e38)
    constexpr float kMax = std::numeric_limits<float>::max();
    h.d_lo = std::min(2 * tree.radius_lo + 2 * slack, kMax);
    h.d_hi = std::min((2 * tree.radius_hi + 2 * slack) * 1.000001f, kMax);
  } else {
    h.d_lo = 1;
    h.d_hi = 1.000001f;
  }
  const LogScale rs = r_scale(h.r_lo, h.r_hi);
  const DiameterCoder diameter_code(d_scale(h.d_lo, h.d_hi));

  EncodedSpt out;
  if (keep_map) {
    out.parent.assign(total, kNoParent);
    std::copy(tree.leaf_parent.begin(), tree.leaf_parent.end(), out.parent.begin());
    seq.each(n, total, [&](bool, uint32_t s) { out.parent[n + s] = tree.records[s].parent; });
  }
  // r_min codes, then r_max codes in place of the parents (compact); full lists keep parents.
  const std::size_t interiors = tree.interiors;
  auto each_slot = [&](auto&& f) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, interiors, 1 << 14), [&](const auto& r) {
      for (std::size_t s = r.begin(); s < r.end(); ++s) f(s);
    });
  };
  each_slot(
      [&](std::size_t s) { tree.records[s].r_min = encode_r(r_of(tree.records[s].error), rs); });
  auto parent_code = [&](uint32_t p) -> uint32_t {
    return p == kNoParent ? kRInfinity : tree.records[p - n].r_min;
  };
  auto parent_r = [&](uint32_t p) -> float {
    return p == kNoParent ? INFINITY : r_of(tree.records[p - n].error);
  };
  // Compact: each node's key, its r_max code, or 0 when its interval is empty (left out); the
  // leaves' keys replace their parents, the interior slots' go to an array of their own.
  std::vector<uint16_t> slot_key;
  if (!o.full) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i)
        tree.leaf_parent[i] = parent_code(tree.leaf_parent[i]);  // r_min = 0: empty iff 0
    });
    sized_in_parallel(slot_key, interiors);
    each_slot([&](std::size_t s) {
      const uint32_t r_max = parent_code(tree.records[s].parent);
      slot_key[s] = r_max > tree.records[s].r_min ? static_cast<uint16_t>(r_max) : 0;
    });
  }

  // Compact: each leaf's codes (position, normal, diameter, colour: 12 bytes, as in its entry)
  // written over its own position's 12 bytes, in one pass; the normals, radii and colours are
  // then released. No new array: the splats' floats (31 bytes a splat) shrink to 12 bytes of
  // codes, and the leaves' r_max codes stay in leaf_parent.
  const bool has_color = !in.colors.empty();
  std::vector<Vec3f> leaf_codes;  // the positions' storage, holding codes
  static_assert(sizeof(Vec3f) == 12);
  auto leaf_bytes = [&](std::size_t i) {
    return reinterpret_cast<unsigned char*>(leaf_codes.data()) + 12 * i;
  };
  if (!o.full) {
    leaf_codes = std::move(in.positions);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
      for (std::size_t i = r.begin(); i < r.end(); ++i) {
        const Vec3f c = leaf_codes[i];
        const float radius = in.radii[i];
        unsigned char* const e = leaf_bytes(i);
        put_u16(e, encode_position(c.x, h.box_min.x, h.step.x));
        put_u16(e + 2, encode_position(c.y, h.box_min.y, h.step.y));
        put_u16(e + 4, encode_position(c.z, h.box_min.z, h.step.z));
        put_u16(e + 6, encode_normal(in.normals[i]));
        put_u16(e + 8, diameter_code.encode(radius > 0 ? 2 * radius + 2 * slack : 0.0f));
        put_u16(e + 10, has_color ? encode_rgb565(in.colors[i]) : 0);
      }
    });
    release(in.normals);
    release(in.radii);
    release(in.colors);
  }

  // One entry's bytes.
  auto encode = [&](bool leaf, uint32_t i, unsigned char* e) {
    if (o.full) {
      Vec3f c, nn;
      float radius, r_min, r_max;
      std::array<uint8_t, 3> col{0, 0, 0};
      if (leaf) {
        c = in.positions[i];
        nn = in.normals[i];
        radius = in.radii[i];
        r_min = 0;
        r_max = parent_r(tree.leaf_parent[i]);
        if (!in.colors.empty()) col = in.colors[i];
      } else {
        const SptFullRecord& f = tree.full_records[i];
        c = f.centre;
        nn = f.normal;
        radius = tree.records[i].radius;
        r_min = r_of(tree.records[i].error);
        r_max = parent_r(tree.records[i].parent);
        col = f.color;
      }
      const float f[9] = {c.x, c.y, c.z, nn.x, nn.y, nn.z, 2 * radius, r_min, r_max};
      for (int j = 0; j < 9; ++j) put_f32(e + 4 * j, f[j]);
      e[36] = col[0];
      e[37] = col[1];
      e[38] = col[2];
      e[39] = 0;
      return;
    }
    if (leaf) {
      const unsigned char* const codes = leaf_bytes(i);
      std::memcpy(e, codes, 10);
      put_u16(e + 10, 0);
      put_u16(e + 12, static_cast<uint16_t>(tree.leaf_parent[i]));
      std::memcpy(e + 14, codes + 10, 2);
    } else {
      const SptRecord& r = tree.records[i];
      put_u16(e, r.q[0]);
      put_u16(e + 2, r.q[1]);
      put_u16(e + 4, r.q[2]);
      put_u16(e + 6, r.normal);
      put_u16(e + 8, diameter_code.encode(r.radius > 0 ? 2 * r.radius + 2 * slack : 0.0f));
      put_u16(e + 10, r.r_min);
      put_u16(e + 12, slot_key[i]);
      put_u16(e + 14, r.rgb565);
    }
  };

  // Pieces of the node sequence, placed in parallel (their number does not depend on threads).
  const std::size_t piece = std::max<std::size_t>(std::size_t{1} << 16, (total + 15) / 16);
  const std::size_t pieces = (total + piece - 1) / piece;
  std::size_t kept = 0;
  // Compact: per piece and r_max code, where its first entry goes (a stable counting sort).
  std::vector<uint32_t> start;
  std::vector<uint32_t> dest;  // full: per node of the sequence, its place or kNoParent
  if (!o.full) {
    start.assign(pieces * 65536, 0);
    tbb::parallel_for(std::size_t{0}, pieces, [&](std::size_t c) {
      uint32_t* count = start.data() + c * 65536;
      seq.each(c * piece, std::min(total, (c + 1) * piece), [&](bool leaf, uint32_t i) {
        if (const uint32_t key = leaf ? tree.leaf_parent[i] : slot_key[i]) ++count[65535 - key];
      });
    });
    uint64_t sum = 0;
    for (std::size_t b = 0; b < 65536; ++b)
      for (std::size_t c = 0; c < pieces; ++c)
        sum += std::exchange(start[c * 65536 + b], static_cast<uint32_t>(sum));
    kept = sum;
  } else {
    std::vector<std::pair<float, uint32_t>> order;  // (r_max, sequence index)
    std::size_t q = 0;
    seq.each(0, total, [&](bool leaf, uint32_t i) {
      const float r_max = parent_r(leaf ? tree.leaf_parent[i] : tree.records[i].parent);
      const float r_min = leaf ? 0.0f : r_of(tree.records[i].error);
      if (r_max > r_min) order.push_back({r_max, static_cast<uint32_t>(q)});
      ++q;
    });
    tbb::parallel_sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    dest.assign(total, kNoParent);
    for (std::size_t k = 0; k < order.size(); ++k) dest[order[k].second] = static_cast<uint32_t>(k);
    kept = order.size();
  }

  out.entries = kept;
  out.dropped_empty = total - kept;
  h.entries = kept;
  out.bytes = kSptHeaderBytes + kept * h.entry_bytes;
  if (keep_map) {
    out.entry_of_node.assign(total, kNoParent);
  }
  unsigned char header[kSptHeaderBytes];
  write_spt_header(h, header);
  uint32_t crc = crc32c(0, header, 124);
  const bool patch = static_cast<bool>(sink.patch) && !o.full;
  // Compact lists go out in four slabs (each pass places and encodes only its slab's nodes),
  // each slab written while the next one is encoded (two buffers of a quarter of the list: the
  // same memory as one buffer of half of it): at its place in the file's reserved blocks when
  // the sink can reserve them (slabs then start on kSptBlock boundaries of the file, the first
  // one with the header's place, the header written last), else in order after the header.
  // Otherwise (full precision, or a pipe) the list is encoded whole, then written.
  const bool reserved = patch && sink.reserve && sink.reserve(out.bytes);
  const std::size_t slab_count = patch ? 4 : 1;
  // Slab k: entries [first[k], first[k + 1]), in the file from file_at[k] (the header's place
  // included in the first slab when reserved).
  std::vector<std::size_t> first(slab_count + 1, kept);
  std::vector<uint64_t> file_at(slab_count);
  std::size_t buffer_bytes = 0;
  for (std::size_t k = 0; k < slab_count; ++k) {
    std::size_t lo = std::min(kept, (kept + slab_count - 1) / slab_count * k);
    if (reserved && k > 0) {  // the first entry starting on a block boundary from there on
      const uint64_t at =
          (kSptHeaderBytes + lo * h.entry_bytes + kSptBlock - 1) / kSptBlock * kSptBlock;
      lo = std::min<std::size_t>(kept, (at - kSptHeaderBytes) / h.entry_bytes);
    }
    first[k] = lo;
    file_at[k] = reserved && k == 0 ? 0 : kSptHeaderBytes + lo * h.entry_bytes;
  }
  for (std::size_t k = 0; k < slab_count; ++k)
    buffer_bytes = std::max<std::size_t>(
        buffer_bytes, kSptHeaderBytes + first[k + 1] * h.entry_bytes - file_at[k]);
  // Uninitialised (the slab passes write every entry's bytes), aligned, the pages mapped in
  // parallel.
  AlignedBuffer buffers[2];
  for (std::size_t k = 0; k < std::min<std::size_t>(2, slab_count); ++k) {
    if (k == 1 && first[1] >= kept) break;  // one slab
    buffers[k] = make_aligned_buffer(buffer_bytes, kSptBlock);
    map_pages_in_parallel(buffers[k].get(), buffers[k].get() + buffer_bytes);
  }
  std::future<void> writing;  // of the slab before the one being encoded
  double write_s = 0;         // waiting for the sink
  auto wait_writing = [&] {
    if (!writing.valid()) return;
    const auto t0 = Clock::now();
    writing.get();
    write_s += std::chrono::duration<double>(Clock::now() - t0).count();
  };
  auto emit = [&](const unsigned char* p, std::size_t bytes) {
    const auto t0 = Clock::now();
    sink.write(p, bytes);
    write_s += std::chrono::duration<double>(Clock::now() - t0).count();
  };
  // Encodes entries [lo, hi) of the list into `buffer` and adds them to the checksum.
  auto encode_slab = [&](std::size_t lo, std::size_t hi, unsigned char* buffer) {
    // Compact: the slab holds the buckets (65535 - r_max code) from b_lo to b_hi; a pass
    // counts places within those buckets only and skips every other node.
    std::size_t b_lo = 0, b_hi = 0;
    if (!o.full && hi > lo) {
      auto bucket_of = [&](std::size_t d) {  // the last bucket starting at or before d
        return static_cast<std::size_t>(std::upper_bound(start.begin(), start.begin() + 65536, d) -
                                        start.begin() - 1);
      };
      b_lo = bucket_of(lo);
      b_hi = bucket_of(hi - 1);
    }
    // Compact: the nodes i0 <= i < i1 of one kind (leaves or interior slots, `key` their keys)
    // in the slab. Picked by runs without a branch per node (three in four are in other slabs,
    // unpredictably), then placed in order.
    auto place_compact = [&](bool leaf, const auto* key, std::size_t i0, std::size_t i1,
                             uint32_t* next) {
      constexpr std::size_t kRun = 1024;
      uint32_t picked[kRun];
      const std::size_t width = b_hi - b_lo;
      for (std::size_t r0 = i0; r0 < i1; r0 += kRun) {
        const std::size_t r1 = std::min(i1, r0 + kRun);
        std::size_t m = 0;
        for (std::size_t i = r0; i < r1; ++i) {  // key 0 (left out) is bucket 65535: never in
          picked[m] = static_cast<uint32_t>(i);
          m += std::size_t{65535} - key[i] - b_lo <= width;
        }
        for (std::size_t k = 0; k < m; ++k) {
          const uint32_t i = picked[k];
          const uint32_t d = next[65535 - key[i] - b_lo]++;
          if (d < lo || d >= hi) continue;
          encode(leaf, i, buffer + (d - lo) * h.entry_bytes);
          if (keep_map) out.entry_of_node[seq.node(leaf, i)] = d;
        }
      }
    };
    tbb::parallel_for(std::size_t{0}, pieces, [&](std::size_t c) {
      const std::size_t q0 = c * piece, q1 = std::min(total, q0 + piece);
      if (!o.full) {
        std::vector<uint32_t> next(start.begin() + c * 65536 + b_lo,
                                   start.begin() + c * 65536 + b_hi + 1);
        if (q0 < n) place_compact(true, tree.leaf_parent.data(), q0, std::min(q1, n), next.data());
        if (q1 > n) place_compact(false, slot_key.data(), std::max(q0, n) - n, q1 - n, next.data());
        return;
      }
      std::size_t q = q0;
      seq.each(q0, q1, [&](bool leaf, uint32_t i) {
        const uint32_t d = dest[q++];
        if (d == kNoParent || d < lo || d >= hi) return;
        encode(leaf, i, buffer + (d - lo) * h.entry_bytes);
        if (keep_map) out.entry_of_node[seq.node(leaf, i)] = d;
      });
    });
    crc = crc32c(crc, buffer, (hi - lo) * h.entry_bytes);
  };
  if (patch && !reserved) emit(header, kSptHeaderBytes);
  for (std::size_t k = 0, used = 0; k < slab_count; ++k) {
    const std::size_t lo = first[k], hi = first[k + 1];
    if (k > 0 && lo >= hi) continue;  // empty (small lists: boundaries rounded to one block)
    unsigned char* const buffer = buffers[used++ % 2].get();
    const std::size_t skip = kSptHeaderBytes + lo * h.entry_bytes - file_at[k];  // the header's
    std::memset(buffer, 0, skip);
    encode_slab(lo, hi, buffer + skip);
    if (patch) {  // one slab written at a time, in order; the other buffer is then free
      wait_writing();
      const std::size_t bytes = skip + (hi - lo) * h.entry_bytes;
      writing = std::async(std::launch::async, [&, buffer, bytes, at = file_at[k]] {
        if (!reserved)
          sink.write(buffer, bytes);
        else if (sink.write_through)
          sink.write_through(at, buffer, bytes);
        else
          sink.patch(at, buffer, bytes);
      });
    }
  }
  wait_writing();
  h.checksum = crc;
  write_spt_header(h, header);
  if (reserved) {
    sink.patch(0, header, kSptHeaderBytes);
  } else if (patch) {
    sink.patch(124, header + 124, 4);
  } else {
    emit(header, kSptHeaderBytes);
    emit(buffers[0].get(), kept * h.entry_bytes);
  }
  out.write_seconds = write_s;
  return out;
}

SptBytes build_spt_bytes(const SplatCloud& cloud, float color_weight,
                         const EncodeSptOptions& options, bool keep_map, const Bounds* frame) {
  SplatCloud copy;
  copy.positions = cloud.positions;
  copy.normals = cloud.normals;
  copy.radii = cloud.radii;
  copy.colors = cloud.colors;
  copy.color_bits = cloud.color_bits;
  SptSplats splats = take_spt_splats(copy);
  std::vector<uint32_t> old_index;
  const SptOrder order = sort_spt_splats(splats, keep_map ? &old_index : nullptr, frame);
  SptTree tree = build_spt_tree(splats, order, {color_weight, options.full});
  SptBytes out;
  out.depth = tree.depth;
  SptSink sink;
  sink.write = [&](const unsigned char* p, std::size_t k) {
    out.bytes.insert(out.bytes.end(), p, p + k);
  };
  sink.patch = [&](uint64_t at, const unsigned char* p, std::size_t k) {
    std::copy(p, p + k, out.bytes.begin() + static_cast<std::ptrdiff_t>(at));
  };
  out.info = encode_spt(tree, splats, options, sink, keep_map);
  if (keep_map) {  // leaves by their index in `cloud`
    const std::size_t n = cloud.size();
    std::vector<uint32_t> entry(n), parent(n);
    for (std::size_t i = 0; i < n; ++i) {
      entry[old_index[i]] = out.info.entry_of_node[i];
      parent[old_index[i]] = out.info.parent[i];
    }
    std::copy(entry.begin(), entry.end(), out.info.entry_of_node.begin());
    std::copy(parent.begin(), parent.end(), out.info.parent.begin());
  }
  return out;
}

}  // namespace splatkit::spt
