// .splk, splatkit's own container, versions 1.0 and 1.1. Spec: formats/splk.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"
#include "splatkit/output_file.h"

namespace splatkit {

// Chunk flag bits (splk.md): an unknown critical chunk makes readers fail; a chunk tied to the
// splats indexes them, so a tool that reorders, adds or removes splats must drop or rebuild it.
inline constexpr uint32_t kSplkChunkCritical = 1u << 0;
inline constexpr uint32_t kSplkChunkTiedToSplats = 1u << 1;

// The chunk types registered in version 1.1 (formats/splk.md), decoded by the stages that own them
// (graph_io/graph_chunks.h): neighbour graph, splat classes, clip partners, surface ids.
inline constexpr char kSplkGraphType[4] = {'G', 'R', 'P', 'H'};
inline constexpr char kSplkClassType[4] = {'C', 'L', 'A', 'S'};
inline constexpr char kSplkClipType[4] = {'C', 'L', 'I', 'P'};
inline constexpr char kSplkSurfaceType[4] = {'S', 'U', 'R', 'F'};

// True when the first bytes are the .splk magic (bytes 1-4 "SPLK" after 0x89, or 0x09 when a 7-bit
// transfer stripped the high bit, so that read_splk reports a damaged magic as such). The fixed
// header is 16 bytes: 8-byte magic, major and minor version, file flags.
bool is_splk_magic(std::string_view first_bytes);

// Reads every chunk: META into doc.metadata, SPLT into doc.cloud, FACE into the cloud's faces, any
// other chunk (known to a later stage, or unknown and not critical) into doc.chunks in file order;
// doc.header gets {"version": "1.0" or "1.1" (the file's own; any 1.x minor is read), "flags": 0,
// "chunks": [{"type", "offset", "flags", "bytes", "crc" (8 hex digits)}, ...]} in file order, END
// included (what splat-info shows). Checks
// every size and checksum; works on pipes (no seeking; allocations grow with the bytes read).
// Throws Error(kBadInput) for damaged files, Error(kUnsupported) for an unknown major version, file
// flag, chunk flag or critical chunk.
LoadedCloud read_splk(InputStream& in, const ReadOptions& options = {});

// Writes META (doc.metadata), SPLT (doc.cloud), FACE (when the cloud has faces), then doc.chunks in
// order, then END; version 1.1 when doc.chunks holds one of the types registered in 1.1 (GRPH,
// CLAS, CLIP, SURF), else 1.0. Deterministic: the same doc gives the same bytes. Throws
// Error(kOutput) for what the format cannot hold (non-finite positions, empty or duplicate extra
// names, a carried chunk with an invalid or reserved type) and for write failures.
void write_splk(const LoadedCloud& doc, OutputFile& out);

// Removes the carried chunks flagged kSplkChunkTiedToSplats: for tools that reorder, add or remove
// splats, whose carried per-splat data would otherwise refer to the wrong splats. Returns how many.
std::size_t drop_chunks_tied_to_splats(LoadedCloud& doc);

}  // namespace splatkit
