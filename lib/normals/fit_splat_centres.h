// fit_splat_centres: moves every splat centre along its normal onto the plane fitted to its point
// and the neighbours on the same sheet of the surface, so that on a noisy scan the splats lie on
// the surface rather than scattered about it by the scanner's noise (σ along the normal becomes
// about σ/√(neighbours)).
//
// For point i with unit normal n_i and kNN row N(i) (k points, i included): the neighbours j with
// |n_j·n_i| >= kSameSheetCos (cover_splat.h: normals within 25°, either sign: orientation may not
// have run) are i's sheet, and c_i moves by n_i · mean_j((c_j − c_i)·n_i). Neighbours across a
// crease (robust normals) or on the far side of a thin part are left out, so creases stay sharp.
// All offsets are computed from the unmoved positions, then applied: the result does not depend on
// the order or the thread count.
#pragma once

#include <cstddef>
#include <span>

#include "normals/cover_splat.h"
#include "splatkit/spatial_index.h"
#include "splatkit/vec3.h"

namespace splatkit {

// index: built over `positions` (#N, moved in place); normals: #N unit. Returns the mean |shift|.
double fit_splat_centres(const SpatialIndex& index, std::span<Vec3f> positions,
                         std::span<const Vec3f> normals, std::size_t k);

}  // namespace splatkit
