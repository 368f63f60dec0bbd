#include "graph/convexity.h"

#include <stdexcept>

#include "graph/vec3d.h"

namespace splatkit::graph {
namespace {

// Accumulates the signs of the values of one test.
struct SignTally {
  double tol;
  bool pos = false, neg = false;
  void add(double v) {
    pos |= v > tol;
    neg |= v < -tol;
  }
  Convexity result() const {
    if (pos && neg) return Convexity::kMixed;
    if (pos) return Convexity::kConcave;
    if (neg) return Convexity::kConvex;
    return Convexity::kFlat;
  }
};

}  // namespace

Convexity partner_set_convexity(std::span<const Vec3f> centres, std::span<const Vec3f> normals,
                                double tol) {
  if (centres.size() != normals.size())
    throw std::invalid_argument("partner_set_convexity: centres and normals differ in size");
  if (centres.empty()) return Convexity::kFlat;
  Vec3d m;
  for (const Vec3f& c : centres) m += to_vec3d(c);
  m = m / static_cast<double>(centres.size());
  SignTally tally{tol};
  for (std::size_t k = 0; k < centres.size(); ++k)
    tally.add(dot(m - to_vec3d(centres[k]), to_vec3d(normals[k])));
  return tally.result();
}

Convexity splat_partner_convexity(const Vec3f& c, const Vec3f& n, std::span<const Vec3f> centres,
                                  double tol) {
  SignTally tally{tol};
  for (const Vec3f& ck : centres) tally.add(dot(to_vec3d(ck) - to_vec3d(c), to_vec3d(n)));
  return tally.result();
}

ClipRule clip_rule(Convexity partners, ClipSide side) {
  switch (partners) {
    case Convexity::kConcave:
      return side == ClipSide::kBehind ? ClipRule::kUnion : ClipRule::kIntersection;
    case Convexity::kConvex:
      return side == ClipSide::kBehind ? ClipRule::kIntersection : ClipRule::kUnion;
    case Convexity::kFlat:
      return ClipRule::kUnion;
    case Convexity::kMixed:
      break;
  }
  return ClipRule::kIntersection;
}

}  // namespace splatkit::graph
