// Deferred shading: one colour per pixel from the reconstructed surface (blended normal, albedo,
// depth), after all fragments are resolved ([IvoMSc] §6.3).
//   phong:   ambient + Lambert diffuse + Blinn-Phong specular, one white light above-left of the
//            camera (fixed relative to the camera), two-sided (a normal facing away is mirrored to
//            face the viewer);
//   normals: world-space normal mapped to RGB as (n + 1) / 2;
//   depth:   1 at the near side of the scene's bounding sphere, 0 at its far side;
//   flat:    the albedo.
// phong and flat give linear colour (written sRGB-encoded to 8-bit images); normals and depth are
// data and are written as they are.
#pragma once

#include "render/camera.h"

namespace splatkit::render {

enum class ShadeMode { kPhong, kNormals, kDepth, kFlat };

struct Shading {
  ShadeMode mode = ShadeMode::kPhong;
  Vec3f light{0, 0, 1};  // unit, towards the light, scene frame
  float ambient = 0.12f, diffuse = 0.8f, specular = 0.25f;
  int shininess = 32;                   // Blinn-Phong exponent
  float depth_near = 0, depth_far = 1;  // depth mode's range
  bool linear_output = true;            // false: the colour is data (no sRGB encoding)
};

// The shading of one frame: the light follows the camera; the depth range is the bounding
// sphere's.
Shading make_shading(ShadeMode mode, const Projection& projection, const BoundingSphere& bounds);

// Colour of a surface point with (not necessarily unit, non-zero) normal `normal`, albedo, camera
// depth, seen along `view` (unit, from the point towards the eye).
Vec3f shade_pixel(const Shading& shading, const Vec3f& normal, const Vec3f& view,
                  const Vec3f& albedo, float depth);

}  // namespace splatkit::render
