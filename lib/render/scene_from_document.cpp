#include "render/scene_from_document.h"

#include <optional>

#include "graph_io/graph_chunks.h"

namespace splatkit::render {

namespace {

// The splat classes of a `class` attribute, or empty when a value is not one (0 smooth, 1 edge,
// 2 intersection): then the attribute is another tool's.
std::vector<graph::SplatClass> classes_from_attribute(const ExtraAttribute& a) {
  std::vector<graph::SplatClass> out(a.values.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double v = a.values[i];
    if (!(v == 0 || v == 1 || v == 2)) return {};
    out[i] = static_cast<graph::SplatClass>(static_cast<int>(v));
  }
  return out;
}

}  // namespace

DocumentScene scene_from_document(LoadedCloud&& doc, const std::string& name) {
  DocumentScene out;
  const uint64_t n = doc.cloud.size();
  std::optional<graph::ClipPartnerTable> clip;
  if (const RawChunk* c = graph::find_chunk(doc, graph::kClipChunkType))
    clip = graph::decode_clip_chunk(*c, n, name);
  std::optional<graph::Segmentation> surfaces;
  if (const RawChunk* c = graph::find_chunk(doc, graph::kSurfaceChunkType))
    surfaces = graph::decode_surface_chunk(*c, n, name);
  if (const RawChunk* c = graph::find_chunk(doc, graph::kClassChunkType)) {
    out.classes = graph::decode_class_chunk(*c, n, name);
    out.class_source = "CLAS";
  } else if (const ExtraAttribute* a = doc.cloud.find_extra("class")) {
    out.classes = classes_from_attribute(*a);
    if (!out.classes.empty()) out.class_source = "class";
  }
  const bool id_attribute = doc.cloud.find_extra("surface_id") != nullptr;
  out.scene = make_render_scene(std::move(doc.cloud), name);
  if (surfaces) {
    out.scene.surface_ids = std::move(surfaces->surface);
    out.surface_source = "SURF";
  } else if (id_attribute) {
    out.surface_source = "surface_id";
  }
  if (clip) attach_clip_partners(out.scene, std::move(*clip), name);
  return out;
}

}  // namespace splatkit::render
