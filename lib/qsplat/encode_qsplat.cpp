#include "qsplat/encode_qsplat.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "qsplat/choose_leaf_group_cell.h"
#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit::qsplat {

namespace {

void put32(unsigned char* p, uint32_t v) {
  p[0] = static_cast<unsigned char>(v >> 24);
  p[1] = static_cast<unsigned char>(v >> 16);
  p[2] = static_cast<unsigned char>(v >> 8);
  p[3] = static_cast<unsigned char>(v);
}
void put_float(unsigned char* p, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put32(p, u);
}
void put16(unsigned char* p, unsigned v) {
  p[0] = static_cast<unsigned char>(v >> 8);
  p[1] = static_cast<unsigned char>(v);
}

void write_comment_fragment(std::vector<unsigned char>& out, const std::string& text) {
  const std::size_t pad = (4 - text.size() % 4) % 4;
  const std::size_t len = 20 + text.size() + pad;
  if (len > 0x7FFFFFFFu) throw Error(ErrorKind::kUnsupported, "comments too long for a fragment");
  const std::size_t at = out.size();
  out.resize(at + len, 0);
  std::memcpy(&out[at], "QSplat11", 8);
  put32(&out[at + 8], static_cast<uint32_t>(len));
  put32(&out[at + 12], 0);
  put32(&out[at + 16], 2);
  std::memcpy(&out[at + 20], text.data(), text.size());
}

// Node j found no code inside its decoded parent. When float32's steps across the model are wider
// than its smallest leaf (a splat 1e20 away from the rest), rounding can leave a node on its
// parent's edge: the input's fault, Error(kBadInput); otherwise Error(kInternal).
[[noreturn]] void fail_outside_parent(const QSplatTree& t, uint32_t j) {
  const Sphere& root = t.spheres[0];
  const float far = std::max({std::fabs(root.centre.x), std::fabs(root.centre.y),
                              std::fabs(root.centre.z)}) +
                    root.radius;
  float smallest = far;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t.child_count[i] == 0) smallest = std::min(smallest, t.spheres[i].radius);
  if (far * 0x1p-23f > smallest) {
    char what[256];
    std::snprintf(what, sizeof what,
                  "the splats span %.3g units, too wide for QSplat's float32 spheres to hold "
                  "splats of radius %.3g (a far outlier? estimate-normals --outliers removes them)",
                  double(far), double(smallest));
    throw Error(ErrorKind::kBadInput, what);
  }
  throw Error(ErrorKind::kInternal,
              "QSplat node " + std::to_string(j) + " lies outside its decoded parent");
}

}  // namespace

EncodedQSplat encode_qsplat(QSplatTree& t, const std::string& comments) {
  const std::size_t m = t.size();
  const bool color = t.colors.size > 0;
  const std::size_t nb = color ? 6 : 4;
  // Where each node's group of children starts, relative to the fragment (breadth first = file
  // order): chunks of nodes add up their groups' bytes, then place them after the earlier chunks'.
  constexpr std::size_t kChunk = std::size_t{1} << 16;
  std::vector<uint8_t> grand;
  std::vector<uint32_t> offset;  // for nodes with children
  sized_in_parallel(grand, m);
  sized_in_parallel(offset, m);
  std::vector<uint64_t> chunk_at(chunk_count(m, kChunk) + 1, 0);
  std::vector<std::size_t> chunk_leaves(chunk_at.size(), 0);
  // The bytes of node i's group (i has children): the offset to its first child with children,
  // when it has one, then one record per child.
  auto group_bytes = [&](std::size_t i) {
    return (grand[i] ? 4u : 0u) + static_cast<uint32_t>(t.child_count[i] * nb);
  };
  EncodedQSplat e;
  for_each_chunk(m, kChunk, [&](std::size_t c, std::size_t lo, std::size_t hi) {
    uint64_t bytes = 0;
    for (std::size_t i = lo; i < hi; ++i) {
      const int k = t.child_count[i];
      if (k == 0) {
        ++chunk_leaves[c];
        continue;
      }
      for (int q = 0; q < k; ++q) grand[i] |= t.child_count[t.first_child[i] + q] > 0;
      bytes += group_bytes(i);
    }
    chunk_at[c + 1] = bytes;
  });
  chunk_at[0] = 40;
  for (std::size_t c = 1; c < chunk_at.size(); ++c) {
    chunk_at[c] += chunk_at[c - 1];
    e.leaves += chunk_leaves[c - 1];
  }
  const uint64_t at = chunk_at.back();
  if (m == 0 || !grand[0])
    throw Error(ErrorKind::kInternal, "QSplat tree whose root has no grandchildren");
  e.tree_bytes = at - 40;
  const uint64_t length = (at + 3) / 4 * 4;
  if (length > 0x7FFFFFFFu)
    throw Error(ErrorKind::kUnsupported,
                "the QSplat tree takes " + std::to_string(length) +
                    " bytes, more than one fragment holds (2^31 - 1); split the input");
  if (!comments.empty()) write_comment_fragment(e.bytes, comments);
  const std::size_t frag = e.bytes.size();
  sized_in_parallel(e.bytes, frag + length);
  for_each_chunk(m, kChunk, [&](std::size_t c, std::size_t lo, std::size_t hi) {
    auto here = static_cast<uint32_t>(chunk_at[c]);  // below 2^31: checked above
    for (std::size_t i = lo; i < hi; ++i) {
      if (t.child_count[i] == 0) continue;
      offset[i] = here;
      here += group_bytes(i);
    }
  });
  unsigned char* f = e.bytes.data() + frag;
  std::memcpy(f, "QSplat11", 8);
  put32(f + 8, static_cast<uint32_t>(length));
  put32(f + 12, static_cast<uint32_t>(e.leaves));
  put32(f + 16, color ? 1 : 0);
  Sphere root = t.spheres[0];
  const double grown = root.radius * (1 + kInteriorMargin);
  root.radius = static_cast<float>(grown);
  if (root.radius < grown) root.radius = std::nextafter(root.radius, 2 * root.radius);
  put_float(f + 20, root.centre.x);
  put_float(f + 24, root.centre.y);
  put_float(f + 28, root.centre.z);
  put_float(f + 32, root.radius);
  put32(f + 36, t.child_count[0]);

  // Level by level, each node's children against its decoded sphere, their true spheres then
  // replaced by their decoded ones. The leaves' growth sums per fixed chunk of parents, added in
  // order: the same mean for any thread count.
  constexpr std::size_t kParents = 512;
  t.spheres[0] = root;
  // Nodes over leaves larger than this get their cell chosen for their leaves' sake.
  const double search_above = kLeafGroupSearchAbove * root.radius;
  double growth_sum = 0;
  for (std::size_t l = 0; l + 1 < t.levels(); ++l) {
    const uint32_t lb = t.level_begin[l], le = t.level_begin[l + 1];
    std::vector<double> chunk_sum(chunk_count(le - lb, kParents), 0),
        chunk_max(chunk_sum.size(), 0);
    for_each_chunk(le - lb, kParents, [&](std::size_t ch, std::size_t lo, std::size_t hi) {
      for (uint32_t i = lb + static_cast<uint32_t>(lo); i < lb + hi; ++i) {
        const int c = t.child_count[i];
        if (c == 0) continue;
        unsigned char* p = f + offset[i];
        const uint32_t first = t.first_child[i];
        if (grand[i]) {
          uint32_t j = first;
          while (t.child_count[j] == 0) ++j;  // first member with children
          put32(p, offset[j] - offset[i]);
          p += 4;
        }
        const Sphere parent = t.spheres[i];  // decoded
        const SphereEncoder encode(parent);
        for (int k = 0; k < c; ++k, p += nb) {
          const uint32_t j = first + static_cast<uint32_t>(k);
          const Sphere s = t.spheres[j];  // true
          const double centre[3] = {s.centre.x, s.centre.y, s.centre.z};
          int code;
          Sphere decoded;
          if (t.child_count[j]) {
            const double margin = grand[j] ? kInteriorMargin : kLeafParentMargin;
            code = encode(centre, s.radius * (1 + margin), SphereSearch::kNearestFirst, &decoded);
            if (!grand[j] && code >= 0 && s.radius > search_above) {
              const uint32_t f0 = t.first_child[j];
              code = choose_leaf_group_cell(parent, s, code, decoded, &t.spheres[f0],
                                            &t.normal_codes[f0], t.child_count[j], &decoded);
            }
          } else {  // a leaf: drawn as a disc
            code =
                encode.nearest_disc(centre, s.radius, decode_normal(t.normal_codes[j]), &decoded);
          }
          if (code < 0) fail_outside_parent(t, j);
          t.spheres[j] = decoded;
          if (t.child_count[j] == 0) {
            const double g = double{t.spheres[j].radius} / s.radius;
            chunk_sum[ch] += g;
            chunk_max[ch] = std::max(chunk_max[ch], g);
          }
          const unsigned kids = t.child_count[j] ? t.child_count[j] - 1u : 0u;
          put16(p, (static_cast<unsigned>(code) << 3) | (grand[j] ? 4u : 0u) | kids);
          put16(p + 2, (static_cast<unsigned>(t.normal_codes[j]) << 2) | t.cones[j]);
          if (color) put16(p + 4, t.colors[j]);
        }
      }
    });
    for (std::size_t ch = 0; ch < chunk_sum.size(); ++ch) {
      growth_sum += chunk_sum[ch];
      e.leaf_growth_max = std::max(e.leaf_growth_max, chunk_max[ch]);
    }
  }
  e.leaf_growth_mean = e.leaves ? growth_sum / static_cast<double>(e.leaves) : 0;
  return e;
}

}  // namespace splatkit::qsplat
