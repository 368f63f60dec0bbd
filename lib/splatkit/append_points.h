// append_points: some points of one cloud added to the end of another, for tools that gather
// points from several files (splat-tile).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "splatkit/splat_cloud.h"

namespace splatkit {

// Appends src's points `indices` (each < src.size(), any order, repeats allowed) to dst, with
// every per-point array: normals, radii, ellipses, colours, extra attributes. Positions move from
// src's frame to dst's (file coordinates src.origin + p, then minus dst.origin, rounded to
// float32: exact when both origins are equal; set dst.origin before the first append). A dst
// without points takes src's fields first (its origin stays). Faces and the viewpoint are not
// carried (points only).
// Throws Error(kBadInput) naming `src_name` when src's attributes differ from dst's (a field one
// has and the other lacks, an attribute of another type, another colour depth): the message says
// which. dst is left unchanged then.
// What `other` has that `first` lacks or holds otherwise (fields, attribute names and types,
// colour depth), in words starting with "has" ("has no normals, the earlier inputs do"); empty
// when append_points would accept other's points after first's.
std::string fields_difference(const SplatCloud& first, const SplatCloud& other);

void append_points(SplatCloud& dst, const SplatCloud& src, std::span<const uint32_t> indices,
                   const std::string& src_name);

}  // namespace splatkit
