// Synthetic shapes sampled with exact normals and exact smooth-patch labels: the ground truth for
// tests and benchmarks (normals accuracy, orientation, segmentation, rendering against analytic
// images). Deterministic for a given seed on every platform (own RNG, no std:: distributions,
// single-threaded). One caveat: std::sin/cos/log are not required to be correctly rounded, so a
// libm that differs in the last bit could change a float's last bit; tests/e2e/synth.sh compares
// the checked-in data-samples byte for byte and would show it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "splatkit/splat_cloud.h"

namespace splatkit {

enum class ShapeKind {
  kSphere,      // unit sphere at the origin
  kTorus,       // major radius 1, minor radius 0.35, axis +z
  kCadPart,     // a prism with a 60° bevel, a cylindrical boss and a through hole: planes and
                // cylinders meeting at creases of 60°, 90° and 120°, closed; 9 labelled patches
                // (layout and dimensions in synthetic_shapes.cpp and data-samples/README.md)
  kTwoSpheres,  // two unit spheres, centres 1.2 apart on x, interpenetrating; red and blue
  kCube,        // axis-aligned cube of side 2 at the origin, six patches
};

struct ShapeOptions {
  ShapeKind kind = ShapeKind::kSphere;
  std::size_t points = 10000;  // random: exactly; stratified: within rounding (±2 % from 1000
                               // points up; a tiny request can give a few more or fewer, even 0)
  uint64_t seed = 1;
  double noise = 0.0;   // Gaussian noise, standard deviation as a fraction of the bbox diagonal,
                        // applied along the true normal; true normals stay exact
  bool random = false;  // false: stratified (near-uniform) sampling; true: i.i.d. uniform
  // Scan lines, as a line scanner samples: > 1 puts the points on parallel lines (planes: rows of
  // constant v; surfaces of revolution: circles of constant profile position) spaced
  // sqrt(scan_lines)·h apart, i.i.d. uniform along each line, so they are scan_lines times denser
  // along a line than across (h = sqrt(area / points)). Implies random. 0 or 1: off.
  double scan_lines = 0;
  bool keep_inside = false;  // kTwoSpheres: keep the parts of each sphere inside the other
                             // (false: the visible union, a closed surface whose intersection
                             // circle is a crease; true: two whole interpenetrating spheres)
  // Attributes as a scanner records them: colours from a smooth texture over the surface (a few
  // periods across the model) with sensor noise (standard deviation 6 of 255), and an extra
  // attribute "intensity" (uint16, the texture's brightness around 2000, noise 40). Positions,
  // normals and radii are the same as without.
  bool texture = false;
};

// Returns positions, exact outward unit normals, radii (mean distance to 5 nearest neighbours of
// the ideal sampling density, so splats overlap), colours (kTwoSpheres: patch 0 red, patch 1 blue;
// else light grey 200) and an extra attribute "patch_id" (uint32: the true smooth patch each point
// was sampled from). Units: the shapes' own (unit sphere, cube of side 2, ...), origin zero.
//
// Sampling is area-uniform. Stratified (random = false): each patch is cut into rows of cells of
// area h², h² = total area / points; one point per cell, jittered over the central half of the
// cell, so spacing is near-uniform and every point of a cell lies within the radius of the cell's
// sample (planar faces: except thin slivers that rows cut off along slanted edges and holes, within
// h/2 of a crease). Random: i.i.d. uniform, exactly `points` points. Radius: stratified,
// max(1.05 h = the measured mean 5-NN distance, the cell's covering distance), 1.06 h for square
// cells; random, 1.71 h (the mean 5-NN distance of a Poisson sample, 0.90 h, would leave ~8 % of
// the surface uncovered; 1.71 h leaves 1e-4). Points are ordered patch by patch (random: in draw
// order). Noise moves points after sampling, so the same seed with and without noise gives the
// same normals and labels. Scan lines: i.i.d. samples moved to the middle of their line's band
// (the area-uniform draw picks the line; the radius is the random one's times sqrt(scan_lines)).
// Throws Error(kUsage) for points == 0 or > 2^30, noise negative or not finite, or scan_lines
// not finite, negative or above 1000.
SplatCloud make_shape(const ShapeOptions& options);

// Parses "sphere", "torus", "cad", "two-spheres", "cube"; throws Error(kUsage) otherwise.
ShapeKind parse_shape_kind(const std::string& name);
std::string shape_kind_name(ShapeKind kind);

// For kCadPart (and kCube): distance from p to the nearest crease (edge between two patches),
// used to report accuracy per distance band. kTwoSpheres: distance to the intersection circle
// (a crease of the union; where the surfaces cross with keep_inside). kSphere, kTorus: +infinity.
float distance_to_crease(ShapeKind kind, const Vec3f& p);

// Names of the smooth patches, indexed by patch_id ("bottom", "boss-side", "+x", ...).
std::vector<std::string> shape_patch_names(const ShapeOptions& options);

// Axis-aligned bounds of the noiseless shape; noise is a fraction of their diagonal.
Bounds shape_bounds(const ShapeOptions& options);

// Euclidean distance from p to the noiseless surface, and to one patch of it (patch < number of
// patches, else std::out_of_range). Exact up to float rounding.
float distance_to_shape(const ShapeOptions& options, const Vec3f& p);
float distance_to_patch(const ShapeOptions& options, uint32_t patch, const Vec3f& p);

}  // namespace splatkit
