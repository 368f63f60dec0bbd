// Reading QSplat .qs v11 files [Rusinkiewicz00] (layout: formats/qsplat.md) into a decoded tree.
//
// Safe for untrusted input: every fragment length, group offset and node count is checked against
// the bytes left before it is used, memory is bounded by the file size (26 bytes per 4-byte
// node), and the walk is linear in the file size. The tree must be laid out as the original
// writer lays it out (sibling groups breadth first, each offset pointing at the next unread
// group), which is what makes one pass enough. Failures throw Error(kBadInput) "<name>: byte
// <offset>: <what>", each cause with its own message (bad magic, truncated header, fragment length
// beyond the file, unknown option bits (kUnsupported), a group past its fragment, an offset that
// does not point at the next group, a sphere or normal code outside its table, a leaf flagged with
// grandchildren, children under a group without offset, a leaf count that differs from the
// header, bytes after the tree beyond the 3 of padding).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "splatkit/input_stream.h"
#include "splatkit/vec3.h"

namespace splatkit {

// Every node of every tree fragment, decoded: the roots first (one per tree fragment, from the
// fragment header: no normal, cone code 3), then each tree's nodes breadth first as in the file.
struct QSplatModel {
  bool has_color = false;
  uint64_t file_bytes = 0;
  uint32_t tree_fragments = 0, comment_fragments = 0;
  std::string comments;         // the text of the comment fragments, in file order
  uint64_t leaves = 0;          // nodes without children, all fragments
  uint32_t levels = 0;          // depth of the deepest leaf below its root (the root's children: 1)
  std::vector<uint32_t> roots;  // #T node indices
  std::vector<Vec3f> centres;   // #M decoded sphere centres
  std::vector<float> radii;     // #M decoded sphere radii
  std::vector<uint16_t> normal_codes;  // #M 14-bit codes (qsplat_codes.h: decode_normal)
  std::vector<uint8_t> cones;          // #M 2-bit cone codes
  std::vector<uint16_t> colors;        // #M RGB 5-6-5, or empty
  std::vector<uint32_t> first_child;   // #M index of the first child (children are consecutive)
  std::vector<uint8_t> child_count;    // #M 0 (leaf) or 2..4 (roots: 1..4)
  std::size_t size() const { return centres.size(); }
};

// Decodes the whole file held in `bytes`; `name` is used in messages.
QSplatModel parse_qsplat(std::span<const unsigned char> bytes, const std::string& name);
// Reads `in` to its end and decodes it.
QSplatModel read_qsplat(InputStream& in);

// Whether `head` (a file's first bytes) starts with the QSplat magic "QSplat".
bool looks_like_qsplat(std::string_view head);

}  // namespace splatkit
