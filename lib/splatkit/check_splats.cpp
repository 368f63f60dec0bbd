#include "splatkit/check_splats.h"

#include <cmath>
#include <sstream>
#include <vector>

#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"

namespace splatkit {

namespace {

std::string number(float v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// What is wrong with splat i, or empty.
std::string splat_fault(const SplatCloud& cloud, std::size_t i) {
  const Vec3f& n = cloud.normals[i];
  if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
    return "normal is not finite";
  // Consumers normalise in float: a length that underflows or overflows there is as bad as zero.
  const float length = norm(n);
  if (n.x == 0 && n.y == 0 && n.z == 0) return "normal is zero";
  if (!(length > 0) || !std::isfinite(length))
    return "normal cannot be normalised (length " + number(length) + ")";
  const float r = cloud.radii[i];
  if (!std::isfinite(r)) return "radius " + number(r) + " is not finite";
  if (r < 0) return "radius " + number(r) + " is negative";
  if (r == 0) return "radius is zero";
  if (!cloud.has_ellipses()) return {};
  const Vec3f& u = cloud.axes[i];
  const float m = cloud.minor_radii[i];
  if (!std::isfinite(u.x) || !std::isfinite(u.y) || !std::isfinite(u.z))
    return "ellipse axis is not finite";
  if (std::fabs(norm(u) - 1) > 1e-3f) return "ellipse axis is not a unit vector";
  if (std::fabs(dot(u, n)) > 1e-3f * length) return "ellipse axis is not in the splat's plane";
  if (!(m > 0) || !std::isfinite(m)) return "minor radius " + number(m) + " is not positive";
  if (m > r * (1 + 1e-6f)) return "minor radius " + number(m) + " exceeds the radius " + number(r);
  return {};
}

// Whether splat i passes splat_fault's checks of the normal and radius, without its strings: a
// normal whose squared length is positive and finite has a length that is too (and is finite
// and not zero).
bool plain_splat_ok(const SplatCloud& cloud, std::size_t i) {
  const float s = squared_norm(cloud.normals[i]), r = cloud.radii[i];
  return s > 0 && std::isfinite(s) && r > 0 && std::isfinite(r);
}

}  // namespace

void check_splats(const SplatCloud& cloud, const std::string& name) {
  if (!cloud.has_normals() && !cloud.has_radii())
    throw_bad_input(name, "the cloud has no normals and no radii; run estimate-normals first");
  if (!cloud.has_normals())
    throw_bad_input(name, "the cloud has no normals; run estimate-normals first");
  if (!cloud.has_radii())
    throw_bad_input(name, "the cloud has no radii; run estimate-normals first");
  // Chunks in parallel, each noting its first bad splat: the first of all is the one reported.
  const std::size_t n = cloud.size();
  const std::size_t bad =
      first_in_chunks(n, std::size_t{1} << 16, [&, ellipses = cloud.has_ellipses()](std::size_t i) {
        return (ellipses || !plain_splat_ok(cloud, i)) && !splat_fault(cloud, i).empty();
      });
  if (bad < n)
    throw_bad_input(name, "splat " + std::to_string(bad) + ": " + splat_fault(cloud, bad));
}

}  // namespace splatkit
