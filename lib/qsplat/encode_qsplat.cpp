#include "qsplat/encode_qsplat.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "splatkit/error.h"

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

}  // namespace

EncodedQSplat encode_qsplat(const QSplatTree& t, const std::string& comments) {
  const std::size_t m = t.size();
  const bool color = !t.colors.empty();
  const std::size_t nb = color ? 6 : 4;
  // Group of each node with children (breadth first = file order), its size and position.
  std::vector<uint8_t> grand(m, 0);
  std::vector<uint32_t> group(m, 0);
  std::vector<uint64_t> pos;  // byte of each group relative to the fragment start
  uint64_t at = 40;
  EncodedQSplat e;
  std::vector<Sphere> decoded;  // fresh pages are dear: made beside the layout walk
  tbb::parallel_invoke([&] { decoded.resize(m); },
                       [&] {
                         for (std::size_t i = 0; i < m; ++i) {
                           const int c = t.child_count[i];
                           if (c == 0) {
                             ++e.leaves;
                             continue;
                           }
                           for (int k = 0; k < c; ++k)
                             grand[i] |= t.child_count[t.first_child[i] + k] > 0;
                           group[i] = static_cast<uint32_t>(pos.size());
                           pos.push_back(at);
                           at += (grand[i] ? 4 : 0) + c * nb;
                         }
                       });
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
  e.bytes.resize(frag + length, 0);
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

  decoded[0] = root;
  for (std::size_t l = 0; l + 1 < t.levels(); ++l) {
    tbb::parallel_for(
        tbb::blocked_range<uint32_t>(t.level_begin[l], t.level_begin[l + 1], 512),
        [&](const auto& r) {
          for (uint32_t i = r.begin(); i < r.end(); ++i) {
            const int c = t.child_count[i];
            if (c == 0) continue;
            unsigned char* p = f + pos[group[i]];
            const uint32_t first = t.first_child[i];
            if (grand[i]) {
              uint32_t j = first;
              while (t.child_count[j] == 0) ++j;  // first member with children
              put32(p, static_cast<uint32_t>(pos[group[j]] - pos[group[i]]));
              p += 4;
            }
            for (int k = 0; k < c; ++k, p += nb) {
              const uint32_t j = first + static_cast<uint32_t>(k);
              const Sphere& s = t.spheres[j];
              const double centre[3] = {s.centre.x, s.centre.y, s.centre.z};
              const double need = t.child_count[j] ? s.radius * (1 + kInteriorMargin) : s.radius;
              const int code = encode_sphere(decoded[i], centre, need);
              if (code < 0)
                throw Error(ErrorKind::kInternal, "QSplat node " + std::to_string(j) +
                                                      " lies outside its decoded parent");
              decoded[j] =
                  decode_sphere(sphere_cells()[static_cast<std::size_t>(code)], decoded[i]);
              const unsigned kids = t.child_count[j] ? t.child_count[j] - 1u : 0u;
              put16(p, (static_cast<unsigned>(code) << 3) | (grand[j] ? 4u : 0u) | kids);
              put16(p + 2, (static_cast<unsigned>(t.normal_codes[j]) << 2) | t.cones[j]);
              if (color) put16(p + 4, t.colors[j]);
            }
          }
        });
  }
  double sum = 0;
  for (std::size_t i = 0; i < m; ++i)
    if (t.child_count[i] == 0) {
      const double g = double{decoded[i].radius} / t.spheres[i].radius;
      sum += g;
      e.leaf_growth_max = std::max(e.leaf_growth_max, g);
    }
  e.leaf_growth_mean = e.leaves ? sum / static_cast<double>(e.leaves) : 0;
  return e;
}

}  // namespace splatkit::qsplat
