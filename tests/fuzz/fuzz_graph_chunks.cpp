// libFuzzer target for the decoders of the graph chunks (GRPH, CLAS, CLIP, SURF). Input layout:
// byte 0 picks the chunk type, bytes 1-2 the splat count (little-endian), the rest is the
// payload. Any input must decode or throw splatkit::Error; a decoded chunk must encode back to
// the same payload (the encoding is canonical).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "graph_io/graph_chunks.h"
#include "splatkit/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const uint64_t n = data[1] | (uint64_t{data[2]} << 8);
  splatkit::RawChunk chunk;
  chunk.payload.assign(data + 3, data + size);
  try {
    switch (data[0] % 4) {
      case 0: {
        std::memcpy(chunk.type, "GRPH", 4);
        auto g = splatkit::graph::decode_graph_chunk(chunk, n, "fuzz");
        auto again = splatkit::graph::encode_graph_chunk(g.graph, g.edge_flags, g.sharp_threshold);
        if (again.payload != chunk.payload) throw std::logic_error("GRPH round trip differs");
        break;
      }
      case 1: {
        std::memcpy(chunk.type, "CLAS", 4);
        auto c = splatkit::graph::decode_class_chunk(chunk, n, "fuzz");
        if (splatkit::graph::encode_class_chunk(c).payload != chunk.payload)
          throw std::logic_error("CLAS round trip differs");
        break;
      }
      case 2: {
        std::memcpy(chunk.type, "CLIP", 4);
        auto t = splatkit::graph::decode_clip_chunk(chunk, n, "fuzz");
        if (splatkit::graph::encode_clip_chunk(t).payload != chunk.payload)
          throw std::logic_error("CLIP round trip differs");
        break;
      }
      default: {
        std::memcpy(chunk.type, "SURF", 4);
        auto s = splatkit::graph::decode_surface_chunk(chunk, n, "fuzz");
        if (splatkit::graph::encode_surface_chunk(s).payload != chunk.payload)
          throw std::logic_error("SURF round trip differs");
        break;
      }
    }
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
