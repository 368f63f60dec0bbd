// The .splk chunks of the splat graph: exact round trips, the exact GRPH bytes of a tiny graph,
// and each malformed payload rejected with its own message.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "formats/splk.h"
#include "graph_io/graph_chunks.h"
#include "splatkit/error.h"

namespace {

using namespace splatkit::graph;
using splatkit::RawChunk;

// Triangle 0-1-2 plus the edge 2-3; 0-2 sharp, 2-3 sharp and crossing.
splatkit::NeighborGraph tiny_graph() {
  splatkit::NeighborGraph g;
  g.offsets = {0, 2, 4, 7, 8};
  g.neighbors = {1, 2, 0, 2, 0, 1, 3, 2};
  return g;
}
std::vector<uint8_t> tiny_flags() {
  // rows: 0:{1,2} 1:{0,2} 2:{0,1,3} 3:{2}
  return {
      0, kEdgeSharp, 0, 0, kEdgeSharp, 0, kEdgeSharp | kEdgeCrossing, kEdgeSharp | kEdgeCrossing};
}

std::string error_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const splatkit::Error& e) {
    EXPECT_EQ(e.kind(), splatkit::ErrorKind::kBadInput);
    return e.what();
  }
  return "no error";
}

void expect_error(const std::function<void()>& fn, const std::string& part) {
  const std::string what = error_of(fn);
  EXPECT_NE(what.find(part), std::string::npos) << what;
}

TEST(GraphChunks, GraphRoundTripAndExactBytes) {
  const RawChunk c = encode_graph_chunk(tiny_graph(), tiny_flags(), 0.9f);
  EXPECT_EQ(std::string(c.type, 4), "GRPH");
  EXPECT_EQ(c.flags, splatkit::kSplkChunkTiedToSplats);
  // N=4, mode 1, flags 0, E=4, w_s, L=8, stream, one flag byte.
  const std::vector<unsigned char> stream = {2, 0, 0, 1, 0, 1, 0, 0};
  ASSERT_EQ(c.payload.size(), 8u + 1 + 1 + 8 + 4 + 8 + stream.size() + 1);
  EXPECT_EQ(c.payload[0], 4);
  EXPECT_EQ(c.payload[8], 1);
  EXPECT_EQ(c.payload[10], 4);
  EXPECT_EQ(c.payload[22], 8);
  EXPECT_EQ(std::vector<unsigned char>(c.payload.begin() + 30, c.payload.end() - 1), stream);
  // edges in order (0,1)=0, (0,2)=1, (1,2)=0, (2,3)=3 -> 0b11'00'01'00
  EXPECT_EQ(c.payload.back(), 0xC4);
  const DecodedGraph d = decode_graph_chunk(c, 4, "t");
  EXPECT_EQ(d.graph.offsets, tiny_graph().offsets);
  EXPECT_EQ(d.graph.neighbors, tiny_graph().neighbors);
  EXPECT_EQ(d.edge_flags, tiny_flags());
  EXPECT_EQ(d.sharp_threshold, 0.9f);
}

// The consuming encoder writes the same chunk and leaves the graph and flags empty; the flags of
// a graph of many row chunks, whose edges share bytes across chunks, come back as they went in.
TEST(GraphChunks, ConsumingEncoderWritesTheSameBytes) {
  for (uint32_t n : {2u, 100003u}) {
    // A ring of n splats, each linked to 1 and 3 places on either side.
    splatkit::NeighborGraph g;
    g.offsets.push_back(0);
    std::vector<uint8_t> flags;
    for (uint32_t i = 0; i < n; ++i) {
      std::vector<uint32_t> row;
      for (uint32_t d : {1u, 3u})
        for (uint32_t j : {(i + d) % n, (i + n - d) % n})
          if (j != i) row.push_back(j);
      // And i to i + 2 for every third i: chunks of rows then hold edge counts that are not
      // multiples of four, so they share bytes of the packed flags.
      if (i % 3 == 0 && i + 2 < n) row.push_back(i + 2);
      if (i >= 2 && (i - 2) % 3 == 0) row.push_back(i - 2);
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      for (uint32_t j : row) {
        g.neighbors.push_back(j);
        const uint64_t a = std::min(i, j), b = std::max(i, j);
        const uint8_t kinds[3] = {0, kEdgeSharp, kEdgeSharp | kEdgeCrossing};
        flags.push_back(kinds[((a * 2654435761u + b * 40503u) >> 7) % 3]);
      }
      g.offsets.push_back(g.neighbors.size());
    }
    const RawChunk expected = encode_graph_chunk(std::as_const(g), flags, 0.5f);
    const DecodedGraph d = decode_graph_chunk(expected, n, "t");
    EXPECT_EQ(d.graph.neighbors, g.neighbors);
    EXPECT_EQ(d.edge_flags, flags);
    splatkit::NeighborGraph consumed = g;
    std::vector<uint8_t> consumed_flags = flags;
    const RawChunk c = encode_graph_chunk(std::move(consumed), std::move(consumed_flags), 0.5f);
    EXPECT_EQ(c.payload, expected.payload) << n;
    EXPECT_TRUE(consumed.neighbors.empty() && consumed.offsets.empty() && consumed_flags.empty());
  }
}

TEST(GraphChunks, GraphMalformed) {
  const RawChunk good = encode_graph_chunk(tiny_graph(), tiny_flags(), 0.9f);
  auto with = [&](auto&& edit) {
    RawChunk c = good;
    edit(c.payload);
    return c;
  };
  expect_error([&] { decode_graph_chunk(good, 5, "t"); }, "differs from SPLT's 5");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p.resize(5); }), 4, "t"); },
               "truncated: splat count");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p[8] = 0; }), 4, "t"); },
               "unknown graph mode 0");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p[9] = 2; }), 4, "t"); },
               "reserved flag bits");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p[21] = 0x7f; }), 4, "t"); },
               "w_s is not a number");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p[22] = 100; }), 4, "t"); },
               "neighbour stream of 100 bytes");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p[10] = 9; }), 4, "t"); },
               "edge count 9 does not fit");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p.push_back(0); }), 4, "t"); },
               "does not fit");
  // Stream: row 0 count 2 -> 3 (neighbour past the end), caught by the codec.
  const std::string codec =
      error_of([&] { decode_graph_chunk(with([](auto& p) { p[30] = 3; }), 4, "t"); });
  EXPECT_NE(codec, "no error");
  expect_error([&] { decode_graph_chunk(with([](auto& p) { p.back() = 0xC6; }), 4, "t"); },
               "crosses but is not sharp");
}

TEST(GraphChunks, GraphUnusedFlagBits) {
  splatkit::NeighborGraph g;
  g.offsets = {0, 1, 2};
  g.neighbors = {1, 0};
  RawChunk c = encode_graph_chunk(g, std::vector<uint8_t>{1, 1}, 0.5f);
  EXPECT_EQ(decode_graph_chunk(c, 2, "t").edge_flags, (std::vector<uint8_t>{1, 1}));
  c.payload.back() |= 0x10;
  expect_error([&] { decode_graph_chunk(c, 2, "t"); }, "unused bits");
}

TEST(GraphChunks, ClassRoundTripAndMalformed) {
  const std::vector<SplatClass> classes = {SplatClass::kSmooth, SplatClass::kEdge,
                                           SplatClass::kIntersection};
  RawChunk c = encode_class_chunk(classes);
  EXPECT_EQ(std::string(c.type, 4), "CLAS");
  EXPECT_EQ(c.payload.size(), 11u);
  EXPECT_EQ(decode_class_chunk(c, 3, "t"), classes);
  RawChunk bad = c;
  bad.payload[10] = 3;
  expect_error([&] { decode_class_chunk(bad, 3, "t"); }, "unknown class 3 of splat 2");
  bad = c;
  bad.payload.pop_back();
  expect_error([&] { decode_class_chunk(bad, 3, "t"); }, "truncated: 3 classes");
  bad = c;
  bad.payload.push_back(0);
  expect_error([&] { decode_class_chunk(bad, 3, "t"); }, "1 trailing bytes");
}

ClipPartnerTable tiny_clip() {
  ClipPartnerTable t;
  t.offsets = {0, 0, 2, 2, 3};
  t.partners = {0, 3, 1};
  t.flags = {kClipSubsetStart | kClipFront, kClipSubsetStart | kClipSubsetIntersection,
             kClipSubsetStart};
  t.splat_flags = {0, kClipCombineIntersection, 0, 0};
  return t;
}

TEST(GraphChunks, ClipRoundTrip) {
  const RawChunk c = encode_clip_chunk(tiny_clip());
  EXPECT_EQ(std::string(c.type, 4), "CLIP");
  // header 24, record of 1: skip 1, flags, count 2, (zz(-1)=1, f), (zz(2)=4, f);
  // record of 3: skip 1, flags, count 1, (zz(-2)=3, f)
  const std::vector<unsigned char> body = {1, 1, 2, 1, 3, 4, 6, 1, 0, 1, 3, 2};
  EXPECT_EQ(std::vector<unsigned char>(c.payload.begin() + 24, c.payload.end()), body);
  const ClipPartnerTable d = decode_clip_chunk(c, 4, "t");
  EXPECT_EQ(d.offsets, tiny_clip().offsets);
  EXPECT_EQ(d.partners, tiny_clip().partners);
  EXPECT_EQ(d.flags, tiny_clip().flags);
  EXPECT_EQ(d.splat_flags, tiny_clip().splat_flags);
}

TEST(GraphChunks, ClipMalformed) {
  const RawChunk good = encode_clip_chunk(tiny_clip());
  auto with = [&](auto&& edit) {
    RawChunk c = good;
    edit(c.payload);
    return c;
  };
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[8] = 5; }), 4, "t"); },
               "5 records for 4 splats");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[16] = 200; }), 4, "t"); },
               "do not fit");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[24] = 9; }), 4, "t"); },
               "splat index past");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[25] = 2; }), 4, "t"); },
               "unknown splat flag bits 2");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[26] = 0; }), 4, "t"); },
               "has no partners");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[27] = 0; }), 4, "t"); },
               "its own clip partner");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[27] = 5; }), 4, "t"); },
               "out of range");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[28] = 8; }), 4, "t"); },
               "unknown partner flag bits 8");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p[28] = 1; }), 4, "t"); },
               "does not start a subset");
  expect_error(
      [&] {
        decode_clip_chunk(with([](auto& p) {
                            p[16] = 4;
                            p.push_back(0);
                            p.push_back(0);
                          }),
                          4, "t");
      },
      "records hold 3 partners, the header says 4");
  expect_error([&] { decode_clip_chunk(with([](auto& p) { p.push_back(0); }), 4, "t"); },
               "trailing bytes");
  expect_error(
      [&] {
        decode_clip_chunk(with([](auto& p) {
                            p[8] = 1;
                            p[16] = 1;
                            p[26] = 1;
                            p[27] = 0x80;
                            p[28] = 0x80;
                            p.resize(29);
                          }),
                          4, "t");
      },
      "truncated varint");
}

TEST(GraphChunks, SurfaceRoundTripAndMalformed) {
  Segmentation s;
  s.surface = {0, 0, 1, kNoSurface, 1, 2};
  s.sizes = {2, 2, 1};
  const RawChunk c = encode_surface_chunk(s);
  EXPECT_EQ(std::string(c.type, 4), "SURF");
  EXPECT_EQ(c.payload.size(), 8u + 4 + 6 * 4);
  const Segmentation d = decode_surface_chunk(c, 6, "t");
  EXPECT_EQ(d.surface, s.surface);
  EXPECT_EQ(d.sizes, s.sizes);
  auto with = [&](auto&& edit) {
    RawChunk b = c;
    edit(b.payload);
    return b;
  };
  expect_error([&] { decode_surface_chunk(with([](auto& p) { p[8] = 9; }), 6, "t"); },
               "9 surfaces for 6 splats");
  expect_error([&] { decode_surface_chunk(with([](auto& p) { p[8] = 4; }), 6, "t"); },
               "ids 3..3 are never used");
  expect_error([&] { decode_surface_chunk(with([](auto& p) { p[12] = 1; }), 6, "t"); },
               "appears before id 0");
  expect_error([&] { decode_surface_chunk(with([](auto& p) { p[32] = 3; }), 6, "t"); },
               "not below the surface count 3");
  expect_error([&] { decode_surface_chunk(with([](auto& p) { p.pop_back(); }), 6, "t"); },
               "truncated: 6 surface ids");
  expect_error([&] { decode_surface_chunk(with([](auto& p) { p.push_back(1); }), 6, "t"); },
               "1 trailing bytes");
}

TEST(GraphChunks, FindAndPutChunk) {
  splatkit::LoadedCloud doc;
  EXPECT_EQ(find_chunk(doc, kSurfaceChunkType), nullptr);
  Segmentation s;
  s.surface = {0};
  s.sizes = {1};
  put_chunk(doc, encode_surface_chunk(s));
  put_chunk(doc, encode_surface_chunk(s));
  ASSERT_EQ(doc.chunks.size(), 1u);
  EXPECT_NE(find_chunk(doc, kSurfaceChunkType), nullptr);
}

// Every single-byte change and every truncation of the four chunks either decodes or throws
// splatkit::Error(kBadInput); nothing else escapes (a std::exception other than Error, or a
// crash under the sanitizers, is a bug).
TEST(GraphChunks, MutatedPayloadsThrowOnlyBadInput) {
  Segmentation s;
  s.surface = {0, 0, 1, 2};
  s.sizes = {2, 1, 1};
  const std::vector<SplatClass> classes(4, SplatClass::kEdge);
  const std::vector<RawChunk> chunks = {encode_graph_chunk(tiny_graph(), tiny_flags(), 0.9f),
                                        encode_class_chunk(classes), encode_clip_chunk(tiny_clip()),
                                        encode_surface_chunk(s)};
  auto decode = [](const RawChunk& c) {
    switch (c.type[1]) {
      case 'R':
        decode_graph_chunk(c, 4, "t");
        break;
      case 'L':
        if (c.type[2] == 'A')
          decode_class_chunk(c, 4, "t");
        else
          decode_clip_chunk(c, 4, "t");
        break;
      default:
        decode_surface_chunk(c, 4, "t");
    }
  };
  int rejected = 0, accepted = 0;
  auto run = [&](const RawChunk& c) {
    try {
      decode(c);
      ++accepted;
    } catch (const splatkit::Error& e) {
      EXPECT_EQ(e.kind(), splatkit::ErrorKind::kBadInput) << e.what();
      ++rejected;
    }
  };
  for (const RawChunk& good : chunks) {
    for (std::size_t k = 0; k < good.payload.size(); ++k) {
      for (unsigned char v : {0x00, 0x01, 0x7f, 0x80, 0xff}) {
        RawChunk c = good;
        c.payload[k] = v;
        run(c);
      }
      RawChunk cut = good;
      cut.payload.resize(k);
      EXPECT_THROW(decode(cut), splatkit::Error) << std::string(good.type, 4) << " cut at " << k;
    }
  }
  EXPECT_GT(rejected, 100);
  EXPECT_GT(accepted, 0);  // e.g. a class byte changed to 1 stays valid
}

}  // namespace
