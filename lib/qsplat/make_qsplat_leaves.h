// The leaves of a QSplat tree from a splat cloud or a triangle mesh [Rusinkiewicz00].
#pragma once

#include <string>

#include "qsplat/qsplat_leaves.h"
#include "splatkit/splat_cloud.h"

namespace splatkit::qsplat {

// A cloud with faces is a mesh: every vertex used by a face becomes a leaf whose normal is the
// area-weighted sum of its faces' normals and whose radius is the largest radius among the
// minimal bounding spheres of its faces (polygons are split into fans of triangles); vertices in
// no face, of zero radius (degenerate faces only) or with a zero normal are dropped and counted.
// A cloud without faces must hold normals and radii (estimate-normals); splats of radius 0 are
// dropped and counted. Colours (8 or 16 bits) become 8-bit. Throws Error(kBadInput) naming `name`
// when the splats lack normals or radii (the message names estimate-normals), or a normal or
// radius is not usable (check_splats.h's rules). Taken by value: pass std::move(cloud) to let the
// leaves take over its arrays instead of copying them.
QSplatLeaves make_qsplat_leaves(SplatCloud cloud, const std::string& name);

}  // namespace splatkit::qsplat
