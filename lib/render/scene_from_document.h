// A render scene from a loaded file, with the splat graph's data when the file has it
// (formats/splk.md, lib/graph/README.md):
//   CLIP chunk (build-splat-graph)  -> RenderScene::clip, clip_planes (attach_clip_partners);
//   SURF chunk (segment-surfaces)   -> RenderScene::surface_ids; without SURF the `surface_id`
//                                      attribute (segment-surfaces' PLY output) is used. When both
//                                      are present SURF wins: it is checked against the splat
//                                      count and its ids against its own surface count, while an
//                                      attribute is only a number per splat;
//   CLAS chunk (build-splat-graph)  -> classes (for --shade sharp); without CLAS the `class`
//                                      attribute (segment-surfaces' PLY output) when every value
//                                      is 0, 1 or 2; an attribute of that name with other values
//                                      is another tool's (scene labels, a classification) and is
//                                      left alone.
// Chunks are decoded as hostile input (graph_chunks.h): a malformed one throws Error(kBadInput)
// naming `name`, the chunk and the byte.
#pragma once

#include <string>
#include <vector>

#include "formats/loaded_cloud.h"
#include "graph/build_splat_graph.h"
#include "render/render_scene.h"

namespace splatkit::render {

struct DocumentScene {
  RenderScene scene;
  std::vector<graph::SplatClass> classes;  // #N, or empty when the file has none
  std::string surface_source;              // "SURF", "surface_id" (the attribute) or "" (no ids)
  std::string class_source;                // "CLAS", "class" or ""
};

// Takes the cloud out of `doc`. Errors of make_render_scene, plus the chunk errors above.
DocumentScene scene_from_document(LoadedCloud&& doc, const std::string& name);

}  // namespace splatkit::render
