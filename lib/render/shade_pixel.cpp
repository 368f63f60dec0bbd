#include "render/shade_pixel.h"

#include <algorithm>
#include <cmath>

namespace splatkit::render {

namespace {

inline float int_pow(float x, int e) {
  float r = 1.0f;
  for (; e > 0; e >>= 1, x *= x)
    if (e & 1) r *= x;
  return r;
}

}  // namespace

Shading make_shading(ShadeMode mode, const Projection& projection, const BoundingSphere& bounds) {
  Shading s;
  s.mode = mode;
  s.light =
      normalized(projection.right * -0.4f + projection.down * -0.6f + projection.forward * -1.0f);
  const float centre = dot(bounds.center - projection.eye, projection.forward);
  s.depth_near = std::max(0.0f, centre - bounds.radius);
  s.depth_far = std::max(s.depth_near + 1e-6f, centre + bounds.radius);
  s.linear_output = mode == ShadeMode::kPhong || mode == ShadeMode::kFlat;
  return s;
}

Vec3f shade_pixel(const Shading& shading, const Vec3f& normal, const Vec3f& view,
                  const Vec3f& albedo, float depth) {
  switch (shading.mode) {
    case ShadeMode::kFlat:
      return albedo;
    case ShadeMode::kNormals: {
      Vec3f n = normalized(normal);
      return {0.5f * (n.x + 1), 0.5f * (n.y + 1), 0.5f * (n.z + 1)};
    }
    case ShadeMode::kDepth: {
      float t = (shading.depth_far - depth) / (shading.depth_far - shading.depth_near);
      t = std::clamp(t, 0.0f, 1.0f);
      return {t, t, t};
    }
    case ShadeMode::kPhong:
      break;
  }
  Vec3f n = normalized(normal);
  // Two-sided: a normal facing away is mirrored in the plane perpendicular to the view, which
  // equals flipping it for a surface seen from behind and stays continuous at silhouettes, where
  // blended normals graze the view direction from either side.
  const float nv = dot(n, view);
  if (nv < 0) n = n - view * (2 * nv);
  const float lambert = std::max(0.0f, dot(n, shading.light));
  const Vec3f h = normalized(shading.light + view);
  const float spec = lambert > 0 ? int_pow(std::max(0.0f, dot(n, h)), shading.shininess) : 0.0f;
  const float k = shading.ambient + shading.diffuse * lambert;
  const float sp = shading.specular * spec;
  return {albedo.x * k + sp, albedo.y * k + sp, albedo.z * k + sp};
}

}  // namespace splatkit::render
