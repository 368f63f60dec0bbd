// The bytes of a QSplat .qs v11 file (formats/qsplat.md) for a tree: an optional comment fragment,
// then one tree fragment, big-endian, readable by the original QSplat viewer.
//
// Every child sphere is quantised against its parent's decoded sphere with the conservative
// encode_sphere (qsplat_codes.h): the decoded sphere of every node contains the node's true
// sphere (hence every splat below it) and lies inside its decoded parent. Deterministic for any
// thread count (groups are placed by a prefix sum, then filled in parallel).
#pragma once

#include <string>
#include <vector>

#include "qsplat/build_qsplat_tree.h"

namespace splatkit::qsplat {

struct EncodedQSplat {
  std::vector<unsigned char> bytes;  // the whole file
  uint64_t tree_bytes = 0;           // the tree fragment's node groups and offsets
  uint64_t leaves = 0;
};

// `comments`: text of the comment fragment (none when empty). Throws Error(kUnsupported) when the
// tree fragment would exceed 2^31 − 1 bytes (the format's int32 length; several fragments are
// not written), Error(kInternal) when the tree's root has no grandchildren (fewer than 5 leaves:
// callers refuse those first).
EncodedQSplat encode_qsplat(const QSplatTree& tree, const std::string& comments);

}  // namespace splatkit::qsplat
