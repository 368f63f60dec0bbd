// A synthetic city for occlusion-culling tests and benches: a grid of blocks × blocks buildings
// (boxes of random footprint and height, with outer walls, a roof and a floor slab every storey)
// along streets, on a ground plane, sampled as splats on a regular grid per rectangle (spacing h
// chosen so that the whole city gets about `points` splats; radius a little over half a cell's
// diagonal, so neighbouring discs overlap and the surfaces have no holes). Units are
// metres, +z up, the city's centre at the origin. Deterministic for a given seed.
//
// Also a street-level walkthrough: a camera path (eye 1.7 m above the street) along the street
// south of the middle row of buildings, turning into a cross street halfway.
#pragma once

#include <cstdint>
#include <vector>

#include "splatkit/splat_cloud.h"

namespace splatkit {

struct CityOptions {
  std::size_t points = 10'000'000;  // approximately (within a few per cent)
  int blocks = 8;                   // buildings per side, >= 2
  uint64_t seed = 1;
  int walk_frames = 60;  // cameras of the walkthrough
};

struct CityCamera {
  Vec3f eye, target;
};

SplatCloud make_city(const CityOptions& options);
std::vector<CityCamera> city_walkthrough(const CityOptions& options);

}  // namespace splatkit
