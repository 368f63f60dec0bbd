#include "graph_io/chunks_to_attributes.h"

#include <algorithm>
#include <cstring>

#include "graph_io/graph_chunks.h"

namespace splatkit::graph {

ExtraAttribute surface_id_attribute(const Segmentation& segmentation) {
  ExtraAttribute a("surface_id", ScalarType::kUInt32);
  a.values.reserve(segmentation.surface.size());
  for (uint32_t id : segmentation.surface) a.values.push_back(id);
  return a;
}

ExtraAttribute class_attribute(std::span<const SplatClass> classes) {
  ExtraAttribute a("class", ScalarType::kUInt8);
  a.values.reserve(classes.size());
  for (SplatClass c : classes) a.values.push_back(static_cast<double>(c));
  return a;
}

void chunks_to_attributes(LoadedCloud& doc, const std::string& name) {
  const uint64_t n = doc.cloud.size();
  if (const RawChunk* surf = find_chunk(doc, kSurfaceChunkType))
    doc.cloud.set_extra(surface_id_attribute(decode_surface_chunk(*surf, n, name)));
  if (const RawChunk* clas = find_chunk(doc, kClassChunkType))
    doc.cloud.set_extra(class_attribute(decode_class_chunk(*clas, n, name)));
  std::erase_if(doc.chunks, [](const RawChunk& c) {
    return std::memcmp(c.type, kSurfaceChunkType, 4) == 0 ||
           std::memcmp(c.type, kClassChunkType, 4) == 0;
  });
}

}  // namespace splatkit::graph
