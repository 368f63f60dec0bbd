// fit_surface_primitive: the plane, sphere or cylinder that best explains one surface's splats,
// fitted robustly (draft).
#pragma once

#include <cstdint>
#include <limits>
#include <span>

#include "graph/vec3d.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

enum class PrimitiveKind : uint8_t { kNone, kPlane, kSphere, kCylinder };

struct SurfacePrimitive {
  PrimitiveKind kind = PrimitiveKind::kNone;
  Vec3d point;         // plane: a point on it; sphere: the centre; cylinder: a point on the axis
  Vec3d direction;     // plane: unit normal, oriented like the splats' normals; cylinder: axis
  double radius = 0;   // sphere, cylinder
  double outward = 1;  // sphere, cylinder: +1 when the splats' normals point away from the
                       // centre or axis, -1 when towards it
  double scale = std::numeric_limits<double>::infinity();  // robust residual scale

  double distance(const Vec3d& p) const;
  double signed_distance(const Vec3d& p) const;  // > 0 on the side the normals point to
  Vec3d normal_at(const Vec3d& p) const;
};

SurfacePrimitive fit_surface_primitive(std::span<const Vec3f> positions,
                                       std::span<const Vec3f> normals,
                                       std::span<const uint32_t> members);

}  // namespace splatkit::graph
