#include "formats/read_qsplat.h"

#include <cmath>
#include <cstring>
#include <deque>
#include <string_view>

#include "formats/qsplat_codes.h"
#include "splatkit/error.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit {

namespace {

constexpr std::size_t kHeaderBytes = 40, kCommentHeaderBytes = 20;
constexpr uint32_t kOptionColor = 1, kOptionComment = 2;

uint32_t be32(const unsigned char* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}
float be_float(const unsigned char* p) {
  const uint32_t u = be32(p);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

class Parser {
 public:
  Parser(std::span<const unsigned char> b, const std::string& name) : b_(b), name_(name) {}

  QSplatModel run() {
    m_.file_bytes = b_.size();
    if (b_.empty()) fail(0, "empty file");
    std::size_t pos = 0;
    while (pos < b_.size()) pos = fragment(pos);
    if (m_.tree_fragments == 0) fail(pos, "no tree fragment (only comments)");
    return std::move(m_);
  }

 private:
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw_bad_input(name_, "byte " + std::to_string(at) + ": " + what);
  }

  std::size_t fragment(std::size_t pos) {
    const std::size_t left = b_.size() - pos;
    if (left < 6 || std::memcmp(b_.data() + pos, "QSplat", 6) != 0)
      fail(pos, "not a QSplat fragment (magic \"QSplat\" missing)");
    if (left < kCommentHeaderBytes) fail(pos, "truncated fragment header");
    if (std::memcmp(b_.data() + pos + 6, "11", 2) != 0)
      throw_unsupported(name_,
                        "byte " + std::to_string(pos + 6) + ": QSplat version '" +
                            std::string(reinterpret_cast<const char*>(b_.data() + pos + 6), 2) +
                            "' (only 11 is read)");
    const uint32_t length = be32(b_.data() + pos + 8);
    const uint32_t leaves = be32(b_.data() + pos + 12);
    const uint32_t options = be32(b_.data() + pos + 16);
    if (options & ~(kOptionColor | kOptionComment))
      throw_unsupported(name_, "byte " + std::to_string(pos + 16) + ": unknown option bits " +
                                   std::to_string(options));
    if (length % 4 != 0)
      fail(pos + 8, "fragment length " + std::to_string(length) + " is not a multiple of 4");
    if (length > left)
      fail(pos + 8, "fragment length " + std::to_string(length) + " beyond the end of the file (" +
                        std::to_string(left) + " bytes left)");
    if (options & kOptionComment) {
      if (length < kCommentHeaderBytes) fail(pos + 8, "comment fragment shorter than its header");
      const char* text = reinterpret_cast<const char*>(b_.data() + pos + kCommentHeaderBytes);
      std::string_view s(text, length - kCommentHeaderBytes);
      s = s.substr(0, s.find('\0'));  // zero padding
      m_.comments.append(s);
      ++m_.comment_fragments;
      return pos + length;
    }
    if (length < kHeaderBytes || left < kHeaderBytes) fail(pos, "truncated tree fragment header");
    const bool color = options & kOptionColor;
    if (m_.tree_fragments > 0 && color != m_.has_color)
      fail(pos + 16, "fragments disagree on colour");
    m_.has_color = color;
    if (color && m_.colors.size() != m_.centres.size()) m_.colors.resize(m_.centres.size());
    ++m_.tree_fragments;
    tree(pos, length, leaves);
    return pos + length;
  }

  struct Group {
    std::size_t pos;  // first byte (its offset field when it has one)
    uint32_t parent;  // node index
    int depth;        // of its members
    bool has_offset;
  };

  void tree(std::size_t frag, std::size_t length, uint32_t leaves_declared) {
    const unsigned char* h = b_.data() + frag;
    const Vec3f c{be_float(h + 20), be_float(h + 24), be_float(h + 28)};
    const float r = be_float(h + 32);
    const uint32_t root_children = be32(h + 36);
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
      fail(frag + 20, "root centre is not finite");
    if (!(std::isfinite(r) && r > 0))
      fail(frag + 32, "root radius is not a positive finite number");
    if (root_children < 1 || root_children > 4)
      fail(frag + 36, "root has " + std::to_string(root_children) + " children (1 to 4 allowed)");
    const std::size_t end = frag + length;
    const std::size_t node_bytes = m_.has_color ? 6 : 4;
    // At most one node per node_bytes of the fragment, and the root: the arrays never move, and
    // their pages are mapped in parallel up front (a fresh page costs more than filling it).
    const std::size_t most = m_.size() + 1 + (length - kHeaderBytes) / node_bytes;
    auto make_room = [&](auto& v) {
      v.reserve(most);
      map_pages_in_parallel(v.data() + v.size(), v.data() + most);
    };
    make_room(m_.centres);
    make_room(m_.radii);
    make_room(m_.normal_codes);
    make_room(m_.cones);
    if (m_.has_color) make_room(m_.colors);
    make_room(m_.first_child);
    make_room(m_.child_count);
    const auto root = static_cast<uint32_t>(push_node(c, r, 0, 3, 0));
    m_.roots.push_back(root);
    m_.child_count[root] = static_cast<uint8_t>(root_children);
    uint64_t leaves = 0;
    // The root's group always starts with an offset (the original reader reads one).
    std::deque<Group> queue{{frag + kHeaderBytes, root, 1, true}};
    std::size_t tail = frag + kHeaderBytes + 4 + root_children * node_bytes;
    while (!queue.empty()) {
      const Group g = queue.front();
      queue.pop_front();
      const uint32_t count = m_.child_count[g.parent];
      std::size_t p = g.pos;
      const std::size_t need = (g.has_offset ? 4 : 0) + count * node_bytes;
      if (need > end - p) fail(p, "node group runs past the end of its fragment");
      if (g.has_offset) {
        const uint32_t offset = be32(b_.data() + p);
        if (offset != tail - p)
          fail(p, "child offset " + std::to_string(offset) + " does not point at the next group (" +
                      std::to_string(tail - p) + ")");
        p += 4;
      }
      const qsplat::Sphere parent{m_.centres[g.parent], m_.radii[g.parent]};
      m_.first_child[g.parent] = static_cast<uint32_t>(m_.size());
      for (uint32_t i = 0; i < count; ++i, p += node_bytes) {
        const unsigned char* n = b_.data() + p;
        const unsigned w0 = (unsigned{n[0]} << 8) | n[1], w1 = (unsigned{n[2]} << 8) | n[3];
        const unsigned s = w0 >> 3, kids = w0 & 3, grand = (w0 >> 2) & 1;
        if (s >= static_cast<unsigned>(qsplat::kSphereCells))
          fail(p, "sphere code " + std::to_string(s) + " outside the table");
        if ((w1 >> 2) >= static_cast<unsigned>(qsplat::kNormalCodes))
          fail(p + 2, "normal code " + std::to_string(w1 >> 2) + " outside the table");
        if (kids == 0 && grand) fail(p, "leaf flagged with grandchildren");
        if (kids != 0 && !g.has_offset) fail(p, "node with children in a group without offset");
        const qsplat::Sphere d = qsplat::decode_sphere(qsplat::sphere_cells()[s], parent);
        const std::size_t idx = push_node(d.centre, d.radius, static_cast<uint16_t>(w1 >> 2),
                                          static_cast<uint8_t>(w1 & 3), g.depth);
        if (m_.has_color) m_.colors[idx] = static_cast<uint16_t>((unsigned{n[4]} << 8) | n[5]);
        if (kids == 0) {
          ++leaves;
          continue;
        }
        m_.child_count[idx] = static_cast<uint8_t>(kids + 1);
        const std::size_t size = (grand ? 4 : 0) + (kids + 1) * node_bytes;
        queue.push_back({tail, static_cast<uint32_t>(idx), g.depth + 1, grand != 0});
        tail += size;
        if (tail > end) fail(p, "children beyond the end of the fragment");
      }
    }
    if (end - tail > 3)
      fail(tail, std::to_string(end - tail) + " bytes after the tree (at most 3 of padding)");
    if (leaves != leaves_declared)
      fail(frag + 12, "header says " + std::to_string(leaves_declared) + " leaves, the tree has " +
                          std::to_string(leaves));
    m_.leaves += leaves;
  }

  std::size_t push_node(const Vec3f& c, float r, uint16_t normal, uint8_t cone, int depth) {
    m_.centres.push_back(c);
    m_.radii.push_back(r);
    m_.normal_codes.push_back(normal);
    m_.cones.push_back(cone);
    if (m_.has_color) m_.colors.push_back(0);
    m_.first_child.push_back(0);
    m_.child_count.push_back(0);
    if (static_cast<uint32_t>(depth) > m_.levels) m_.levels = static_cast<uint32_t>(depth);
    return m_.centres.size() - 1;
  }

  std::span<const unsigned char> b_;
  const std::string& name_;
  QSplatModel m_;
};

}  // namespace

QSplatModel parse_qsplat(std::span<const unsigned char> bytes, const std::string& name) {
  return Parser(bytes, name).run();
}

QSplatModel read_qsplat(InputStream& in) {
  std::vector<unsigned char> bytes;
  if (in.size_hint()) {
    bytes.reserve(*in.size_hint());
    map_pages_in_parallel(bytes.data(), bytes.data() + bytes.capacity());
  }
  unsigned char buf[1 << 16];
  for (std::size_t n; (n = in.read_some(buf, sizeof buf)) > 0;)
    bytes.insert(bytes.end(), buf, buf + n);
  return parse_qsplat(bytes, in.name());
}

bool looks_like_qsplat(std::string_view head) { return head.starts_with("QSplat"); }

}  // namespace splatkit
