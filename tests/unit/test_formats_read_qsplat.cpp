// The .qs reader (formats/read_qsplat.h): a hand-built file decoded field by field, and one
// test per malformed case, each rejected with its own message. Files are built byte by byte
// here, independently of the writer.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <string>
#include <vector>

#include "formats/qsplat_codes.h"
#include "formats/read_qsplat.h"
#include "splatkit/error.h"

namespace splatkit {
namespace {

using Bytes = std::vector<unsigned char>;

void be32(Bytes& b, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<unsigned char>(v >> s));
}
void be16(Bytes& b, unsigned v) {
  b.push_back(static_cast<unsigned char>(v >> 8));
  b.push_back(static_cast<unsigned char>(v));
}
void magic(Bytes& b) { b.insert(b.end(), {'Q', 'S', 'p', 'l', 'a', 't', '1', '1'}); }

// The 5-point model of test_qsplat_encode_qsplat.cpp: root (2,0,0) r 2.4; A (4 leaves), B leaf.
Bytes five(bool color = false) {
  Bytes b;
  magic(b);
  be32(b, color ? 80 : 68);
  be32(b, 5);
  be32(b, color ? 1 : 0);
  for (float f : {2.0f, 0.0f, 0.0f, 2.4f}) be32(b, std::bit_cast<uint32_t>(f));
  be32(b, 2);
  be32(b, color ? 16 : 12);
  const unsigned words[6] = {0xED2B, 0xEDB8, 0x7E98, 0x7340, 0x67E8, 0xEDB8};
  for (unsigned w : words) {
    be16(b, w);
    be16(b, 0xBE88);
    if (color) be16(b, 0xF800);
  }
  return b;
}

std::string error_of(const Bytes& b) {
  try {
    parse_qsplat(b, "t.qs");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(ReadQSplat, DecodesTheFivePointModel) {
  const QSplatModel m = parse_qsplat(five(), "five.qs");
  EXPECT_EQ(m.tree_fragments, 1u);
  EXPECT_EQ(m.leaves, 5u);
  EXPECT_EQ(m.levels, 2u);
  ASSERT_EQ(m.size(), 7u);
  EXPECT_FALSE(m.has_color);
  EXPECT_EQ(m.child_count[0], 2);
  EXPECT_EQ(m.child_count[1], 4);
  EXPECT_EQ(m.child_count[2], 0);
  EXPECT_EQ(m.first_child[1], 3u);
  // A = cell 7589: centre 2 + 2.4 * (-2/13), radius 2.4 * 11/13.
  EXPECT_NEAR(m.centres[1].x, 2 - 2.4 * 2 / 13, 1e-5);
  EXPECT_NEAR(m.radii[1], 2.4 * 11 / 13, 1e-5);
  EXPECT_EQ(qsplat::decode_normal(m.normal_codes[3]).z, qsplat::decode_normal(m.normal_codes[3]).z);
  EXPECT_GT(qsplat::decode_normal(m.normal_codes[3]).z, 0.999f);
  const QSplatModel c = parse_qsplat(five(true), "five.qs");
  EXPECT_TRUE(c.has_color);
  EXPECT_EQ(c.colors[2], 0xF800);
}

TEST(ReadQSplat, ReadsCommentFragments) {
  Bytes b;
  magic(b);
  be32(b, 24);
  be32(b, 0);
  be32(b, 2);
  b.insert(b.end(), {'h', 'i', '\n', 0});
  const Bytes t = five();
  b.insert(b.end(), t.begin(), t.end());
  const QSplatModel m = parse_qsplat(b, "c.qs");
  EXPECT_EQ(m.comments, "hi\n");
  EXPECT_EQ(m.comment_fragments, 1u);
}

TEST(ReadQSplat, EachMalformedCaseHasItsOwnMessage) {
  std::vector<std::pair<Bytes, std::string>> cases;
  auto with = [](auto edit) {
    Bytes b = five();
    edit(b);
    return b;
  };
  cases.push_back({{}, "empty file"});
  cases.push_back({with([](Bytes& b) { b[0] = 'X'; }), "magic \"QSplat\" missing"});
  cases.push_back({with([](Bytes& b) { b.resize(12); }), "truncated fragment header"});
  cases.push_back({with([](Bytes& b) { b[11] = 70; }), "is not a multiple of 4"});
  cases.push_back({with([](Bytes& b) { b[11] = 72; }), "beyond the end of the file"});
  cases.push_back({with([](Bytes& b) { b[15] = 6; }), "header says 6 leaves, the tree has 5"});
  cases.push_back({with([](Bytes& b) {
                     b[35] = 0x7F;
                     b[32] = 0xFF;
                   }),
                   "root radius"});
  cases.push_back({with([](Bytes& b) {
                     b[20] = 0x7F;
                     b[21] = 0xC0;
                   }),
                   "root centre is not finite"});
  cases.push_back({with([](Bytes& b) { b[39] = 5; }), "root has 5 children"});
  cases.push_back({with([](Bytes& b) { b[43] = 8; }), "does not point at the next group"});
  cases.push_back({with([](Bytes& b) { b[44] = 0xFF; }), "sphere code 8165 outside the table"});
  cases.push_back({with([](Bytes& b) { b[46] = 0xFF; }), "normal code"});
  cases.push_back({with([](Bytes& b) { b[49] |= 4; }), "leaf flagged with grandchildren"});
  cases.push_back(
      {with([](Bytes& b) { b[53] |= 1; }), "node with children in a group without offset"});
  cases.push_back({with([](Bytes& b) { b[49] |= 3; }), "children beyond the end of the fragment"});
  cases.push_back({with([](Bytes& b) {
                     b[11] = 72;
                     b.insert(b.end(), {0, 0, 0, 0});
                   }),
                   "4 bytes after the tree"});
  cases.push_back({with([](Bytes& b) {
                     b[39] = 4;  // the root's group no longer fits in a 52-byte fragment
                     b[11] = 52;
                     b.resize(52);
                   }),
                   "node group runs past the end of its fragment"});
  for (const auto& [bytes, expected] : cases) {
    const std::string msg = error_of(bytes);
    EXPECT_NE(msg.find(expected), std::string::npos)
        << "expected '" << expected << "', got '" << msg << "'";
    EXPECT_EQ(msg.rfind("t.qs: ", 0), 0u) << msg;
  }
  Bytes unknown = five();
  unknown[19] = 8;
  try {
    parse_qsplat(unknown, "t.qs");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kUnsupported);
    EXPECT_NE(std::string(e.what()).find("unknown option bits 8"), std::string::npos);
  }
}

}  // namespace
}  // namespace splatkit
