// The scene/camera layer: a pinhole camera, its per-frame projection, and the orbit cameras that
// frame a model (--view AZ,EL[,DIST], the default three-quarter view, turntables).
//
// Conventions: scene units and the cloud's local frame (SplatCloud::positions). Image pixel (i, j)
// has its centre at pixel coordinates (i + 0.5, j + 0.5); x grows to the right, y downwards. The
// field of view is vertical, in degrees. Camera space has x right, y down, z forward (depth), so a
// point's camera-space z is its distance along the viewing axis.
#pragma once

#include <optional>

#include "splatkit/vec3.h"

namespace splatkit::render {

struct Camera {
  Vec3f eye{0, -5, 0};
  Vec3f target{0, 0, 0};
  Vec3f up{0, 0, 1};
  float fov_y_deg = 40.0f;
  int width = 1280;
  int height = 720;
};

struct BoundingSphere {
  Vec3f center{0, 0, 0};
  float radius = 0;
  // The box the splats' discs reach (each centre +- its radius per axis), which default views
  // fill the frame with; none (box_lo above box_hi) where unknown: the sphere frames the view.
  Vec3f box_lo{1, 1, 1}, box_hi{-1, -1, -1};
  bool has_box() const { return box_lo.x <= box_hi.x && box_lo.y <= box_hi.y && box_lo.z <= box_hi.z; }
};

// What every stage needs from the camera for one frame.
struct Projection {
  Vec3f eye;
  Vec3f right, down, forward;  // orthonormal camera axes in the scene frame
  float focal_px = 1;          // pixels per unit of tan(angle): height / (2 tan(fov_y / 2))
  float cx = 0, cy = 0;        // principal point, pixel coordinates (width / 2, height / 2)
  int width = 0, height = 0;
  float near = 0;  // splats reaching closer than this depth are not drawn

  // Direction (forward component 1, so its parameter is camera depth) of the ray through pixel
  // coordinates (x, y); the centre of pixel (i, j) is (i + 0.5, j + 0.5).
  Vec3f ray(float x, float y) const {
    return forward + right * ((x - cx) / focal_px) + down * ((y - cy) / focal_px);
  }
  // Camera-space coordinates of a scene point.
  Vec3f to_camera(const Vec3f& p) const {
    Vec3f d = p - eye;
    return {dot(d, right), dot(d, down), dot(d, forward)};
  }
};

// Throws Error(kUsage) when the camera is degenerate: eye == target, up parallel to the view
// direction, fov outside (0, 180), or an empty image.
Projection make_projection(const Camera& camera);

// Distance from the sphere's centre at which it fits the view (the smaller of the two fields of
// view) with a small margin.
float framing_distance(const BoundingSphere& sphere, float fov_y_deg, int width, int height);

// Distance from sphere.center along `dir` (towards the eye) at which a camera looking at the
// centre, its up from automatic_up(-dir, up), sees every corner of the sphere's box within both
// fields of view with the same margin: the model fills the frame (a wide building inside its
// bounding sphere covered 44-48 % of the width). No farther than the sphere's framing distance;
// that distance when there is no box.
float box_framing_distance(const BoundingSphere& sphere, const Vec3f& dir, const Vec3f& up,
                           float fov_y_deg, int width, int height);

// A camera on a sphere around `sphere.center`, looking at it: azimuth measured around `up` (0° on
// the axis most perpendicular to `up` among +x, +y, turning right-handed about `up`), elevation
// above the plane perpendicular to `up`. `distance` in scene units; default box_framing_distance().
// The camera's up vector is automatic_up(): `up`, or for a top or bottom view (|elevation| above
// 89.19°) the azimuth-90° axis.
Camera orbit_camera(const BoundingSphere& sphere, float azimuth_deg, float elevation_deg,
                    std::optional<float> distance, const Vec3f& up, float fov_y_deg, int width,
                    int height);

// Cosine of the largest angle between a viewing direction and `up` at which automatic_up() turns
// to another axis (0.81°).
inline constexpr float kAutoUpCos = 0.9999f;

// The up vector for a camera looking along `view` when the caller chose none: `up`, unless `view`
// lies within 0.81° of ±up (a top or bottom view: `up` would give the image no orientation, or
// one that spins with the smallest move of the eye); then the axis at azimuth 90° about `up`
// (orbit_camera's azimuth), so that azimuth 0° points right. For up +z that is +y: a top view is
// a map (+x right, +y up), a bottom view the same map seen from below (+x left, +y up). `up` is
// returned unchanged (not normalised) in the common case. `up` must not be zero.
Vec3f automatic_up(const Vec3f& view, const Vec3f& up);

// Whether `up` orients an image looking along `view`: false when the two are parallel (or either
// is zero), the cameras make_projection() refuses.
bool up_orients_view(const Vec3f& view, const Vec3f& up);

// `camera` turned by `angle_rad` (right-handed) about the line through camera.target along `axis`
// (non-zero): the eye moves on a circle around that line and the up vector turns with it, so a
// turntable of a top view (eye on the axis, up from automatic_up()) spins the model in the image.
// An up vector parallel to `axis` is kept bit for bit.
Camera turned_camera(const Camera& camera, const Vec3f& axis, float angle_rad);

// The default view: a three-quarter view (azimuth 35°, elevation 25°) that frames the model.
inline constexpr float kDefaultAzimuthDeg = 35.0f;
inline constexpr float kDefaultElevationDeg = 25.0f;

}  // namespace splatkit::render
