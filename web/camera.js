// The camera of splat-view (lib/render/camera.h, camera.cpp), in JavaScript, so that
// #view=AZ,EL[,DIST] shows a model from the same camera as `splat-view IN OUT --view AZ,EL[,DIST]`
// at the window's size: vertical field of view 40 degrees, up +z, the same orbit frame, framing
// distance and automatic up for top and bottom views. Scene units, the model's local frame.
// Camera space: x right, y down, z forward; pixel (i, j) has its centre at (i + 0.5, j + 0.5).

export const DEFAULT_AZIMUTH = 35;
export const DEFAULT_ELEVATION = 25;
export const DEFAULT_FOV = 40;
const DEG = Math.PI / 180;
const AUTO_UP_COS = 0.9999;

export const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
export const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                                a[0] * b[1] - a[1] * b[0]];
export const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
export const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
export const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
export const norm = (a) => Math.hypot(a[0], a[1], a[2]);
export const normalized = (a) => { const n = norm(a); return n > 0 ? scale(a, 1 / n) : [0, 0, 0]; };

// The orbit's frame about unit w: a at azimuth 0, b = w x a at azimuth 90.
export function orbitAxes(w) {
  const ref = Math.abs(w[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
  const a = normalized(sub(ref, scale(w, dot(ref, w))));
  return { a, b: cross(w, a) };
}

export function automaticUp(view, up) {
  const w = normalized(up);
  if (!(Math.abs(dot(normalized(view), w)) > AUTO_UP_COS)) return up;
  return orbitAxes(w).b;
}

export function framingDistance(radius, fovY, width, height) {
  const halfY = 0.5 * fovY * DEG;
  const halfX = Math.atan(Math.tan(halfY) * width / Math.max(height, 1));
  return 1.08 * Math.max(radius, 1e-6) / Math.sin(Math.min(halfX, halfY));
}

// render::box_framing_distance: the distance along dir (towards the eye) at which every corner of
// bounds.box lies within both fields of view with the same margin; never farther than the
// sphere's framing distance, which it is without a box. In float64 where splat-view computes in
// float32: the distances agree to about 1e-7 of themselves.
export function boxFramingDistance(bounds, dir, up, fovY, width, height) {
  const loose = framingDistance(bounds.radius, fovY, width, height);
  const b = bounds.box;
  if (!b) return loose;
  const tanY = Math.tan(0.5 * fovY * DEG);
  const tanX = tanY * width / Math.max(height, 1);
  const forward = scale(normalized(dir), -1);
  const right = normalized(cross(forward, automaticUp(forward, up)));
  const down = cross(forward, right);
  let d = 0;
  for (let k = 0; k < 8; ++k) {
    const corner = [(k & 1) ? b[3] : b[0], (k & 2) ? b[4] : b[1], (k & 4) ? b[5] : b[2]];
    const o = sub(corner, bounds.center);
    const z = dot(o, forward);
    d = Math.max(d, 1.08 * Math.abs(dot(o, right)) / tanX - z,
                 1.08 * Math.abs(dot(o, down)) / tanY - z, 0.1 * bounds.radius - z);
  }
  return Number.isFinite(d) && d > 0 ? Math.min(d, loose) : loose;
}

// {eye, target, up}: the camera on the sphere around bounds' centre at azimuth, elevation
// (degrees) and distance (default: boxFramingDistance).
export function orbitCamera(bounds, az, el, distance, up, fovY, width, height) {
  const w = normalized(up);
  const { a, b } = orbitAxes(w);
  const A = az * DEG, E = el * DEG;
  const dir = add(add(scale(a, Math.cos(E) * Math.cos(A)), scale(b, Math.cos(E) * Math.sin(A))),
                  scale(w, Math.sin(E)));
  const d = distance ?? boxFramingDistance(bounds, dir, w, fovY, width, height);
  const target = bounds.center;
  const eye = add(target, scale(dir, d));
  return { eye, target, up: automaticUp(sub(target, eye), w), fovY };
}

// What every pass needs for one frame (render::Projection).
export function makeProjection(cam, width, height) {
  const view = sub(cam.target, cam.eye);
  const distance = norm(view);
  const forward = scale(view, 1 / distance);
  const right = normalized(cross(forward, cam.up));
  const down = cross(forward, right);
  return {
    eye: cam.eye, right, down, forward, width, height,
    focal: 0.5 * height / Math.tan(0.5 * cam.fovY * DEG),
    cx: 0.5 * width, cy: 0.5 * height, near: 1e-4 * distance,
  };
}

// #view=AZ,EL[,DIST] -> {az, el, dist} or null when malformed.
export function parseView(text) {
  const parts = text.split(',').map(Number);
  if (parts.length < 2 || parts.length > 3 || parts.some((v) => !Number.isFinite(v))) return null;
  if (parts.length === 3 && !(parts[2] > 0)) return null;
  return { az: parts[0], el: parts[1], dist: parts.length === 3 ? parts[2] : undefined };
}
