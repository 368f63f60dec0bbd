// Synthetic shapes sampled with exact normals and exact smooth-patch labels: the ground truth for
// tests and benchmarks (normals accuracy, orientation, segmentation, rendering against analytic
// images). Deterministic for a given seed on every platform (own RNG, no std:: distributions).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "splatkit/splat_cloud.h"

namespace splatkit {

enum class ShapeKind {
  kSphere,      // unit sphere at the origin
  kTorus,       // major radius 1, minor radius 0.35, axis +z
  kCadPart,     // a block with a cylindrical boss and a chamfer: planes and cylinders meeting at
                // 60–120° creases, closed, every face a labelled smooth patch
  kTwoSpheres,  // two unit spheres, centres 1.2 apart on x, interpenetrating; red and blue
  kCube,        // axis-aligned cube of side 2 at the origin, six patches
};

struct ShapeOptions {
  ShapeKind kind = ShapeKind::kSphere;
  std::size_t points = 10000;  // approximately: uniform area sampling hits it within rounding
  uint64_t seed = 1;
  double noise = 0.0;  // Gaussian noise, standard deviation as a fraction of the bbox diagonal,
                       // applied along the true normal; true normals stay exact
  bool random = false;   // false: stratified (near-uniform) sampling; true: i.i.d. uniform
  bool keep_inside = false;  // kTwoSpheres: keep the parts of each sphere inside the other
};

// Returns positions, exact outward unit normals, radii (mean distance to 5 nearest neighbours of
// the ideal sampling density, so splats overlap), colours (kTwoSpheres: red/blue; else grey) and
// an extra attribute "patch_id" (uint32: the true smooth patch each point was sampled from).
SplatCloud make_shape(const ShapeOptions& options);

// Parses "sphere", "torus", "cad", "two-spheres", "cube"; throws Error(kUsage) otherwise.
ShapeKind parse_shape_kind(const std::string& name);
std::string shape_kind_name(ShapeKind kind);

// For kCadPart (and kCube): distance from p to the nearest crease (edge between two patches),
// used to report accuracy per distance band.
float distance_to_crease(ShapeKind kind, const Vec3f& p);

}  // namespace splatkit
