// The per-splat attributes that stand for the graph's per-splat chunks in PLY and XYZ, the
// formats without chunks that keep extra attributes: SURF as `surface_id` (uint32; 4294967295,
// kNoSurface, for a splat in no surface) and CLAS as `class` (uint8: 0 smooth, 1 edge, 2
// intersection). segment-surfaces writes them into its PLY output, splat-convert into PLY and XYZ.
#pragma once

#include <span>
#include <string>

#include "formats/loaded_cloud.h"
#include "graph/build_splat_graph.h"
#include "graph/segment_surfaces.h"

namespace splatkit::graph {

ExtraAttribute surface_id_attribute(const Segmentation& segmentation);
ExtraAttribute class_attribute(std::span<const SplatClass> classes);

// Replaces doc's SURF and CLAS chunks by those attributes. A cloud that has an attribute of that
// name already keeps it, and the chunk stays a chunk (a writer without chunks then drops it and
// says so): a file's own `class` labels are never overwritten. The chunks are decoded as every
// reader decodes them: a malformed one, or two of a type, throws Error(kBadInput) naming `name`.
void chunks_to_attributes(LoadedCloud& doc, const std::string& name);

}  // namespace splatkit::graph
