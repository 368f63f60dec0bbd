#include "graph_io/chunks_to_attributes.h"

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

namespace {

// Chunk `type` (at most one) as attribute `attribute`, made by to_attribute(chunk), unless the
// cloud has that attribute already.
template <class ToAttribute>
void chunk_to_attribute(LoadedCloud& doc, const char (&type)[4], const char* what,
                        const char* attribute, const std::string& name, ToAttribute to_attribute) {
  if (doc.cloud.find_extra(attribute) != nullptr) return;
  const RawChunk* chunk = find_single_chunk(doc, type, what, name);
  if (chunk == nullptr) return;
  doc.cloud.extras.push_back(to_attribute(*chunk));
  std::erase_if(doc.chunks, [&](const RawChunk& c) { return std::memcmp(c.type, type, 4) == 0; });
}

}  // namespace

void chunks_to_attributes(LoadedCloud& doc, const std::string& name) {
  const uint64_t n = doc.cloud.size();
  chunk_to_attribute(
      doc, kSurfaceChunkType, "surface ids", "surface_id", name,
      [&](const RawChunk& c) { return surface_id_attribute(decode_surface_chunk(c, n, name)); });
  chunk_to_attribute(doc, kClassChunkType, "splat classes", "class", name, [&](const RawChunk& c) {
    return class_attribute(decode_class_chunk(c, n, name));
  });
}

}  // namespace splatkit::graph
