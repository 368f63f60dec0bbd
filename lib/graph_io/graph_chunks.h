// The .splk chunks of the splat graph (formats/splk.md): GRPH (neighbour graph with its edge
// flags), CLAS (per-splat class), CLIP (clip partners) and SURF (surface ids). Encoders take the
// library's in-memory forms and give a RawChunk (flags: tied to splats, non-critical); decoders
// take a RawChunk from LoadedCloud::chunks and the cloud's splat count.
//
// Decoders treat the payload as hostile: every count is checked against the bytes left before
// anything is allocated, and each malformed case throws splatkit::Error (kBadInput) via
// throw_bad_input(name, ...) with its own message naming the chunk and the byte offset inside
// the payload (truncated, splat count differing from SPLT's, unknown mode or flag bits, a value
// out of range, counts that do not add up, trailing bytes).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/loaded_cloud.h"
#include "formats/splk.h"
#include "graph/build_splat_graph.h"
#include "graph/clip_record.h"
#include "graph/segment_surfaces.h"
#include "splatkit/spatial_index.h"

namespace splatkit::graph {

// The four chunk type codes (registered in formats/splk.h).
inline constexpr const char (&kGraphChunkType)[4] = kSplkGraphType;
inline constexpr const char (&kClassChunkType)[4] = kSplkClassType;
inline constexpr const char (&kClipChunkType)[4] = kSplkClipType;
inline constexpr const char (&kSurfaceChunkType)[4] = kSplkSurfaceType;

// The first chunk of doc.chunks with this type, or nullptr.
const RawChunk* find_chunk(const LoadedCloud& doc, const char (&type)[4]);
// The chunk of this type, or nullptr; a second one is an error (which of them would count?):
// Error(kBadInput) naming `name` and `what` the chunk holds.
const RawChunk* find_single_chunk(const LoadedCloud& doc, const char (&type)[4], const char* what,
                                  const std::string& name);
// Replaces the first chunk of the same type, or appends.
void put_chunk(LoadedCloud& doc, RawChunk chunk);

// GRPH. graph: symmetric rows (NeighborGraph layout), edge_flags: kEdgeSharp / kEdgeCrossing
// bits parallel to graph.neighbors, symmetric. Stored in upper mode, each edge once with its two
// flag bits. Throws std::invalid_argument when the sizes do not match or the graph breaks the
// codec's layout.
RawChunk encode_graph_chunk(const NeighborGraph& graph, std::span<const uint8_t> edge_flags,
                            float sharp_threshold);
// The same chunk from a graph the caller is done with (build-splat-graph): the flags are freed
// once packed and the neighbour rows as they are coded, so that the graph and the chunk are not
// both held in full. graph and edge_flags are left empty.
RawChunk encode_graph_chunk(NeighborGraph&& graph, std::vector<uint8_t>&& edge_flags,
                            float sharp_threshold);

struct DecodedGraph {
  NeighborGraph graph;              // full symmetric rows
  std::vector<uint8_t> edge_flags;  // parallel to graph.neighbors, same flag on i->j and j->i
  float sharp_threshold = 0;        // w_s the flags were computed with
};
DecodedGraph decode_graph_chunk(const RawChunk& chunk, uint64_t num_splats,
                                const std::string& name);

// CLAS: one byte per splat, 0 smooth, 1 edge, 2 intersection.
RawChunk encode_class_chunk(std::span<const SplatClass> classes);
std::vector<SplatClass> decode_class_chunk(const RawChunk& chunk, uint64_t num_splats,
                                           const std::string& name);

// CLIP. Throws std::logic_error when the table is not consistent (ClipPartnerTable).
RawChunk encode_clip_chunk(const ClipPartnerTable& table);
ClipPartnerTable decode_clip_chunk(const RawChunk& chunk, uint64_t num_splats,
                                   const std::string& name);

// SURF. surface: #N ids, each < count or kNoSurface; every id 0..count-1 used, numbered in the
// order of their lowest splat index. The decoder checks all of this and rebuilds sizes.
RawChunk encode_surface_chunk(const Segmentation& segmentation);
Segmentation decode_surface_chunk(const RawChunk& chunk, uint64_t num_splats,
                                  const std::string& name);

}  // namespace splatkit::graph
