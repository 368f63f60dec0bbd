// Value types shared by the disc–disc intersection functions ([IvoMSc] §4.2, docs/references.md): a
// line in 3D, a closed interval of its parameter, and a splat as a disc or an ellipse in object
// space.
#pragma once

#include "graph/vec3d.h"
#include "splatkit/vec3.h"

namespace splatkit::graph {

// The line point + t * direction. plane_plane_line returns a unit direction, so t is a length in
// the units of the positions.
struct Line3 {
  Vec3d point;
  Vec3d direction;
};

// The closed interval [t0, t1] of a line's parameter, t0 <= t1 (t0 == t1 for a tangent line).
struct Interval {
  double t0 = 0, t1 = 0;
};

// A splat in object space. Circular (the default): centre, unit normal, radius. Elliptic: also
// two unit axes u, v in the splat's plane (orthogonal to each other and to the normal) with their
// semi-axes; a point P of the plane is inside iff u² + v² <= 1, u = (P - C)·axis_u / semi_u,
// v = (P - C)·axis_v / semi_v. `radius` is the bounding-sphere radius in both cases (for an
// ellipse, the larger semi-axis), which is what the neighbour graph uses.
struct SplatDisc {
  Vec3f center;
  Vec3f normal;
  float radius = 0;
  Vec3f axis_u, axis_v;
  float semi_u = 0, semi_v = 0;  // both > 0 for an ellipse; 0 for a circular splat

  bool is_ellipse() const { return semi_u > 0 && semi_v > 0; }

  static SplatDisc circle(const Vec3f& c, const Vec3f& n, float r) {
    SplatDisc s;
    s.center = c;
    s.normal = n;
    s.radius = r;
    return s;
  }
  static SplatDisc ellipse(const Vec3f& c, const Vec3f& n, const Vec3f& u, const Vec3f& v, float a,
                           float b) {
    SplatDisc s;
    s.center = c;
    s.normal = n;
    s.radius = a > b ? a : b;
    s.axis_u = u;
    s.axis_v = v;
    s.semi_u = a;
    s.semi_v = b;
    return s;
  }
};

}  // namespace splatkit::graph
