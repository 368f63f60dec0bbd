// check_splats: the one rule every tool that consumes splats applies (splat-view,
// build-splat-graph, segment-surfaces), so that what one tool writes the next reads.
//
// A splat has a position, a normal and a radius. The cloud must hold normals and radii; every
// normal finite and not zero, with a float length that neither underflows nor overflows
// (consumers normalise), every radius finite and positive.
// Throws Error(kBadInput) "<name>: splat <i>: <what>" for the lowest bad index i, e.g.
// "scan.ply: splat 17: normal is zero", "splat 3: radius -1 is negative", or "<name>: the cloud
// has no normals; run estimate-normals first" when an attribute is missing. Positions are the
// readers' business (they reject non-finite coordinates).
#pragma once

#include <string>

#include "splatkit/splat_cloud.h"

namespace splatkit {

void check_splats(const SplatCloud& cloud, const std::string& name);

}  // namespace splatkit
