// Surface splatting in WebGL2 after Botsch, Hornung, Zwicker and Kobbelt 2005 (docs/references.md):
//   1. visibility: every splat's depth, pushed back along the ray by epsilon, into the depth
//      buffer (no colour);
//   2. attributes: the splats within epsilon of the nearest surface add weight x normal and
//      weight x colour into two float targets (additive blending, depth test only);
//   3. normalisation and deferred shading: each pixel divides by the summed weight and is shaded
//      as splat-view shades (lib/render/shade_pixel.h: one white light above-left of the camera,
//      ambient 0.12, diffuse 0.8, Blinn-Phong specular 0.25 with exponent 32, two-sided).
// With surface ids (segment-surfaces), a pass before them finds the nearest splat's surface per
// pixel and the attribute pass sets aside the other surfaces' fragments, as splat-view does
// (lib/render/reconstruct_pixel.h); clipping at partners' planes is not done here.
// Splats are point sprites; the fragment shader intersects the pixel's ray with the splat's disc
// (or ellipse) exactly, so depth and coverage are perspectively correct, and weights it with the
// Gaussian of splat-view's rasteriser (exp(-2 rho^2) - exp(-2 * 1.25^2)). A Sequential Point Tree
// (Dachsbacher, Vogelgsang and Stamminger 2003) is one vertex buffer; its vertex shader draws an
// entry only when its distance interval holds the eye's distance (r_min <= r k < r_max).

import { makeSptCells, sptRanges } from './spt_cells.js';

const VS = `#version 300 es
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aRadius;
layout(location = 3) in vec3 aColor;
layout(location = 4) in vec3 aAxis;
layout(location = 5) in float aMinor;
layout(location = 6) in vec2 aRange;
layout(location = 7) in uint aSurface;
uniform vec3 uEye, uRight, uDown, uForward;
uniform float uFocal, uCx, uCy, uW, uH, uNear;
uniform float uRadiusScale, uSptK, uMaxPoint;
uniform bool uSpt, uSrgbColor, uEllipse;
// Per splat, constant over its point sprite: flat (no interpolation to set up per point).
flat out vec3 vC, vN, vColor, vAxis;
flat out float vR, vMinor, vFront, vRing;
flat out uint vSurface;
float toLinear(float v) {
  return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}
void cull() { gl_Position = vec4(2.0, 2.0, 2.0, 1.0); gl_PointSize = 0.0; }
void main() {
  vec3 d = aPos - uEye;
  if (uSpt) {
    float r = length(d) * uSptK;
    if (!(aRange.x <= r && r < aRange.y)) { cull(); return; }
  }
  vec3 c = vec3(dot(d, uRight), dot(d, uDown), dot(d, uForward));
  float rad = aRadius * uRadiusScale;
  if (c.z - rad < uNear) { cull(); return; }
  vec2 px = vec2(uCx + uFocal * c.x / c.z, uCy + uFocal * c.y / c.z);
  // Splats of more than 3 pixels get a ring out to 1.25 r whose fragments join the normal only
  // (as splat-view's rasteriser: setup_splats.h); the visibility and id passes draw the discs
  // alone, on point sprites sized for them.
  vRing = rad * uFocal / c.z > 3.0 ? 1.5625 : 1.0;
#if defined(VISIBILITY_PASS) || defined(ID_PASS)
  float reach = rad;
#else
  float reach = rad * sqrt(vRing);
#endif
  // Bound on the distance, along x or y, from the projected centre to the projection of any
  // point within reach of the centre: reach sqrt(1 + (x/z)^2) / (z - reach) in units of f.
  float slope = max(abs(c.x), abs(c.y)) / c.z;
  float ext = uFocal * reach * sqrt(1.0 + slope * slope) / max(c.z - reach, 1e-6 * c.z);
  gl_PointSize = min(2.0 * ext + 1.0, uMaxPoint);
  gl_Position = vec4(2.0 * px.x / uW - 1.0, 1.0 - 2.0 * px.y / uH, 0.0, 1.0);
  vec3 n = normalize(aNormal);
  vC = c;
  vN = vec3(dot(n, uRight), dot(n, uDown), dot(n, uForward));
  vFront = dot(n, -d) > 0.0 ? 1.0 : 0.0;
  vR = rad;
#if defined(VISIBILITY_PASS) || defined(ID_PASS)
  vColor = vec3(0.0);
#else
  vColor = uSrgbColor ? vec3(toLinear(aColor.r), toLinear(aColor.g), toLinear(aColor.b)) : aColor;
#endif
  vAxis = uEllipse ? vec3(dot(aAxis, uRight), dot(aAxis, uDown), dot(aAxis, uForward)) : vec3(0.0);
  vMinor = aMinor * uRadiusScale;
  vSurface = aSurface;
}`;

const FS = `#version 300 es
precision highp float;
flat in vec3 vC, vN, vColor, vAxis;
flat in float vR, vMinor, vFront, vRing;
flat in uint vSurface;
uniform float uFocal, uCx, uCy, uH, uNear;
uniform float uDepthOffset, uDepthNear, uDepthFar, uBackWeight;
uniform bool uEllipse;
uniform vec3 uRight, uDown, uForward;
// One program per pass (SwiftShader runs both sides of a branch): VISIBILITY_PASS writes depth
// only, ID_PASS the surface id, neither the attributes.
#if defined(ID_PASS)
layout(location = 0) out uint oId;
#elif !defined(VISIBILITY_PASS)
uniform highp usampler2D uFrontId;
uniform bool uUseIds;
layout(location = 0) out vec4 oNormal;
layout(location = 1) out vec4 oColor;
#endif
void main() {
  vec2 pix = vec2(gl_FragCoord.x, uH - gl_FragCoord.y);
  vec3 ray = vec3((pix.x - uCx) / uFocal, (pix.y - uCy) / uFocal, 1.0);
  float den = dot(ray, vN);
  if (abs(den) < 1e-12) discard;
  float t = dot(vC, vN) / den;
  if (t < uNear) discard;
  vec3 q = ray * t - vC;
  float rho2;
  if (uEllipse) {
    float u = dot(q, vAxis) / vR;
    float v = dot(q, cross(vN, vAxis)) / vMinor;
    rho2 = u * u + v * v;
  } else {
    rho2 = dot(q, q) / (vR * vR);
  }
#if defined(ID_PASS) || defined(VISIBILITY_PASS)
  if (rho2 > 1.0) discard;
#else
  if (rho2 > vRing) discard;
#endif
  gl_FragDepth = clamp((t + uDepthOffset - uDepthNear) / (uDepthFar - uDepthNear), 0.0, 1.0);
#if defined(ID_PASS)
  oId = vSurface;
#elif !defined(VISIBILITY_PASS)
  // Fragments of other surfaces than the pixel's nearest are set aside (splat-view's rule).
  if (uUseIds && vSurface != texelFetch(uFrontId, ivec2(gl_FragCoord.xy), 0).r) discard;
  float w = exp(-2.0 * rho2) - exp(-3.125);
  w *= vFront > 0.5 ? 1.0 : uBackWeight;
  vec3 nw = vN.x * uRight + vN.y * uDown + vN.z * uForward;  // back to the scene frame
  float depth01 = (t - uDepthNear) / (uDepthFar - uDepthNear);
  if (rho2 > 1.0) {  // ring: the normal only
    oNormal = vec4(nw * w, 0.0);
    oColor = vec4(0.0);
    return;
  }
  oNormal = vec4(nw * w, w);
  oColor = vec4(vColor * w, depth01 * w);
#endif
}`;

// The fast path (blend=zbuffer, splat-view's --blend zbuffer): one pass, each splat a round
// point of its projected diameter at its centre's depth, shaded per vertex; no blending.
// One program per shading mode (#define MODE as SHADE_FS) and colour encoding (#define
// SRGB_COLOR: the colour attribute is sRGB); culled entries return before any shading. Back
// faces are culled when uBackCos <= 1 (see backFaceCosine).
const ZB_VS = `#version 300 es
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in float aRadius;
layout(location = 3) in vec3 aColor;
layout(location = 6) in vec2 aRange;
uniform vec3 uEye, uRight, uDown, uForward, uLight;
uniform float uFocal, uCx, uCy, uW, uH, uNear, uDepthNear, uDepthFar;
uniform float uRadiusScale, uSptK, uMaxPoint, uBackCos;
uniform bool uSpt;
flat out vec3 vColor;
float toLinear(float v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }
float toSrgb(float v) {
  v = clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? v * 12.92 : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}
void main() {
  vec3 d = aPos - uEye;
  if (uSpt) {
    float r = length(d) * uSptK;
    if (!(aRange.x <= r && r < aRange.y)) { gl_Position = vec4(2.0, 2.0, 2.0, 1.0); return; }
  }
  // (a zero normal gives NaN here, and the splat stays)
  if (dot(normalize(aNormal), d) > uBackCos * length(d)) { gl_Position = vec4(2.0, 2.0, 2.0, 1.0); return; }
  vec3 c = vec3(dot(d, uRight), dot(d, uDown), dot(d, uForward));
  float rad = aRadius * uRadiusScale;
  if (c.z - rad < uNear) { gl_Position = vec4(2.0, 2.0, 2.0, 1.0); return; }
  vec2 px = vec2(uCx + uFocal * c.x / c.z, uCy + uFocal * c.y / c.z);
  gl_PointSize = clamp(2.0 * rad * uFocal / c.z, 1.0, uMaxPoint);
  float z = clamp((c.z - uDepthNear) / (uDepthFar - uDepthNear), 0.0, 1.0) * 2.0 - 1.0;
  gl_Position = vec4(2.0 * px.x / uW - 1.0, 1.0 - 2.0 * px.y / uH, z, 1.0);
#if MODE == 1
  vColor = 0.5 * (normalize(aNormal) + 1.0);
#elif MODE == 2
  vColor = vec3(1.0 - (c.z - uDepthNear) / (uDepthFar - uDepthNear));
#else
#ifdef SRGB_COLOR
  vec3 albedo = vec3(toLinear(aColor.r), toLinear(aColor.g), toLinear(aColor.b));
#else
  vec3 albedo = aColor;
#endif
#if MODE == 3
  vec3 col = albedo;
#else
  vec3 n = normalize(aNormal);
  vec3 view = -normalize(d);
  float nv = dot(n, view);
  if (nv < 0.0) n = n - view * (2.0 * nv);
  float lambert = max(0.0, dot(n, uLight));
  float spec = max(0.0, dot(n, normalize(uLight + view)));
  spec *= spec; spec *= spec; spec *= spec; spec *= spec; spec *= spec;  // ^32
  if (!(lambert > 0.0)) spec = 0.0;
  vec3 col = albedo * (0.12 + 0.8 * lambert) + vec3(0.25 * spec);
#endif
  vColor = vec3(toSrgb(col.r), toSrgb(col.g), toSrgb(col.b));
#endif
}`;

const ZB_FS = `#version 300 es
precision mediump float;
flat in vec3 vColor;
out vec4 oColor;
void main() {
  vec2 q = gl_PointCoord - 0.5;
  if (dot(q, q) > 0.25) discard;
  oColor = vec4(vColor, 1.0);
}`;

const QUAD_VS = `#version 300 es
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}`;

// One program per shading mode (#define MODE 0 phong, 1 normals, 2 depth, 3 flat): SwiftShader
// runs every side of a branch for every pixel, and this pass covers the whole window.
const SHADE_FS = `#version 300 es
precision highp float;
uniform sampler2D uNormalSum, uColorSum, uSrgbTable;
uniform vec3 uRight, uDown, uForward, uLight, uBackground;  // uBackground: sRGB
uniform float uFocal, uCx, uCy, uH;
out vec4 oColor;
// Linear to sRGB by a table over sqrt(v) (SRGB_TABLE entries; within 0.05 of an 8-bit level of
// the formula, which SwiftShader's pow makes costly at 1280x720).
float toSrgb(float v) {
  float s = sqrt(clamp(v, 0.0, 1.0));
  return texelFetch(uSrgbTable, ivec2(int(s * float(SRGB_TABLE - 1) + 0.5), 0), 0).r;
}
vec3 srgb(vec3 c) { return vec3(toSrgb(c.r), toSrgb(c.g), toSrgb(c.b)); }
void main() {
  ivec2 ij = ivec2(gl_FragCoord.xy);
  vec4 ns = texelFetch(uNormalSum, ij, 0);
  if (!(ns.w > 0.0)) { oColor = vec4(uBackground, 1.0); return; }
  vec3 n = normalize(ns.xyz);
#if MODE == 1
  oColor = vec4(0.5 * (n + 1.0), 1.0);
#elif MODE == 2
  float d = clamp(1.0 - texelFetch(uColorSum, ij, 0).a / ns.w, 0.0, 1.0);
  oColor = vec4(d, d, d, 1.0);
#elif MODE == 3
  oColor = vec4(srgb(texelFetch(uColorSum, ij, 0).rgb / ns.w), 1.0);
#else
  vec3 albedo = texelFetch(uColorSum, ij, 0).rgb / ns.w;
  vec2 pix = vec2(gl_FragCoord.x, uH - gl_FragCoord.y);
  vec3 ray = uForward + uRight * ((pix.x - uCx) / uFocal) + uDown * ((pix.y - uCy) / uFocal);
  vec3 view = -normalize(ray);
  float nv = dot(n, view);
  if (nv < 0.0) n = n - view * (2.0 * nv);
  float lambert = max(0.0, dot(n, uLight));
  float spec = max(0.0, dot(n, normalize(uLight + view)));
  spec *= spec; spec *= spec; spec *= spec; spec *= spec; spec *= spec;  // ^32
  if (!(lambert > 0.0)) spec = 0.0;
  vec3 c = albedo * (0.12 + 0.8 * lambert) + vec3(0.25 * spec);
  oColor = vec4(srgb(c), 1.0);
#endif
}`;

const SRGB_TABLE = 4096;
const toSrgb = (v) => (v <= 0.0031308 ? v * 12.92 : 1.055 * v ** (1 / 2.4) - 0.055);
// splat-view's background colour (linear), as the page writes it.
const BACKGROUND = [0.0194, 0.0232, 0.0273].map(toSrgb);

// Back-face culling in the z-buffer pass, as [Dachsbacher03] culls back faces: a splat whose
// normal points away from the eye, more than 30 degrees past edge-on (n . (p - eye) / |p - eye|
// > 1/2), is not drawn. On a closed surface with outward normals every back face lies behind a
// front face, so the image is the same but for edge-on splats at the silhouette (measured: 5-57
// of ~300 000 pixels of the 5M-entry CAD part), and SwiftShader sets up about a third fewer
// points. A surface seen from behind (a facade from inside, a scan from the far side) would
// vanish, and so do back faces seen through a gap (a window of a building scanned from outside,
// vegetation whose normals are noise: CGAL's building scan at 35,25 keeps mask IoU 0.978). So
// 'auto' culls only while the camera moves (the frames of a drag, the wheel, the keys; a still
// frame follows, as QSplat refines when the user stops [Rusinkiewicz00]) with the eye outside the
// model's box (its sphere without one: not while walking through it); 'cull' always, 'show'
// never. Returns the cosine for uBackCos (2: none).
const BACK_FACE_COSINE = 0.5;
function backFaceCosine(mode, header, eye, moving) {
  if (mode === 'show') return 2;
  if (mode === 'cull') return BACK_FACE_COSINE;
  if (!moving) return 2;
  const b = header.box;
  const outside = b
    ? [0, 1, 2].some((i) => eye[i] < b[i] || eye[i] > b[i + 3])
    : Math.hypot(eye[0] - header.center[0], eye[1] - header.center[1],
                 eye[2] - header.center[2]) > header.radius;
  return outside ? BACK_FACE_COSINE : 2;
}

const define = (text, defines) => text.replace('#version 300 es\n', `#version 300 es\n${defines}\n`);

function compile(gl, vs, fs) {
  const program = gl.createProgram();
  for (const [type, text] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    gl.attachShader(program, s);
  }
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(program));
  const uniforms = {};
  const count = gl.getProgramParameter(program, gl.ACTIVE_UNIFORMS);
  for (let i = 0; i < count; ++i) {
    const name = gl.getActiveUniform(program, i).name;
    uniforms[name] = gl.getUniformLocation(program, name);
  }
  return { program, uniforms };
}

export class SplatRenderer {
  constructor(canvas) {
    // Opaque (alpha: false): every pixel is drawn with alpha 1, and the compositor need not blend.
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: false,
                                             alpha: false });
    if (!gl) throw new Error('this browser has no WebGL2');
    if (!gl.getExtension('EXT_color_buffer_float'))
      throw new Error('this browser cannot render into float targets (EXT_color_buffer_float)');
    this.gl = gl;
    this.canvas = canvas;
    this.splat = compile(gl, VS, FS);
    this.visibility = compile(gl, define(VS, '#define VISIBILITY_PASS'),
                              define(FS, '#define VISIBILITY_PASS'));
    // The nearest surface id per pixel, for files with surface ids.
    this.idPass = compile(gl, define(VS, '#define ID_PASS'), define(FS, '#define ID_PASS'));
    this.shade = [0, 1, 2, 3].map(
        (m) => compile(gl, QUAD_VS, define(SHADE_FS, `#define MODE ${m}\n#define SRGB_TABLE ${SRGB_TABLE}`)));
    // toSrgb(x^2) at x = i / (SRGB_TABLE - 1), for SHADE_FS.
    this.srgbTable = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, this.srgbTable);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.R32F, SRGB_TABLE, 1);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, SRGB_TABLE, 1, gl.RED, gl.FLOAT, Float32Array.from(
        { length: SRGB_TABLE }, (_, i) => toSrgb((i / (SRGB_TABLE - 1)) ** 2)));
    this.zbuffer = new Map();  // z-buffer programs by MODE and SRGB_COLOR, made when first used
    this.maxPoint = gl.getParameter(gl.ALIASED_POINT_SIZE_RANGE)[1];
    this.vao = gl.createVertexArray();
    this.width = this.height = 0;
  }

  // Uploads a view model (view_model.js). Splat files and .spt lists stay on the GPU; a QSplat
  // tree gets a stream buffer the traversal refills each frame.
  load(model) {
    const gl = this.gl;
    const { header, arrays } = model;
    this.kind = header.kind;
    gl.bindVertexArray(this.vao);
    for (let i = 0; i < 7; ++i) gl.disableVertexAttribArray(i);
    this.buffers?.forEach((b) => gl.deleteBuffer(b));
    this.buffers = [];
    const buffer = (data, usage = gl.STATIC_DRAW) => {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, data, usage);
      this.buffers.push(b);
      return b;
    };
    const attrib = (loc, b, size, type, normalized, stride, offset) => {
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, size, type, normalized, stride, offset);
    };
    gl.vertexAttrib3f(3, 0.6, 0.6, 0.6);  // splat-view's albedo for files without colours
    gl.vertexAttrib2f(6, 0, 3.4e38);
    gl.vertexAttribI4ui(7, 0, 0, 0, 0);
    this.hasIds = false;
    this.ellipse = false;
    this.radiusScale = 1;
    this.srgbColor = false;
    if (header.kind === 'spt') {
      // The list split into grid cells (spt_cells.js), each in list order.
      const split = makeSptCells(new Float32Array(arrays.entries.buffer, arrays.entries.byteOffset,
                                                  arrays.entries.byteLength / 4), header.count);
      this.entries = split.entries;
      this.split = split;
      // The model keeps the reordered list only (the file's order is 180 MB at 5M entries).
      arrays.entries = new Uint8Array(this.entries.buffer, this.entries.byteOffset,
                                      this.entries.byteLength);
      const b = buffer(this.entries);
      attrib(0, b, 3, gl.FLOAT, false, 36, 0);
      attrib(1, b, 3, gl.SHORT, true, 36, 12);
      attrib(2, b, 1, gl.FLOAT, false, 36, 20);
      attrib(6, b, 2, gl.FLOAT, false, 36, 24);
      attrib(3, b, 3, gl.UNSIGNED_BYTE, true, 36, 32);
      this.radiusScale = 0.5;  // entries store diameters
      this.srgbColor = header.has_color !== false;
      // Without colours, splat-view's albedo as a constant (the entries' 203 grey is 0.597).
      if (!this.srgbColor) gl.disableVertexAttribArray(3);
    } else if (header.kind === 'qsplat') {
      this.stream = new Float32Array(Math.min(header.count, 8 << 20) * 10);
      this.streamBuffer = buffer(this.stream.byteLength, gl.DYNAMIC_DRAW);
      attrib(0, this.streamBuffer, 3, gl.FLOAT, false, 40, 0);
      attrib(1, this.streamBuffer, 3, gl.FLOAT, false, 40, 12);
      attrib(2, this.streamBuffer, 1, gl.FLOAT, false, 40, 24);
      attrib(3, this.streamBuffer, 3, gl.FLOAT, false, 40, 28);
    } else {
      attrib(0, buffer(arrays.position), 3, gl.FLOAT, false, 0, 0);
      attrib(1, buffer(arrays.normal), 3, gl.FLOAT, false, 0, 0);
      attrib(2, buffer(arrays.radius), 1, gl.FLOAT, false, 0, 0);
      if (arrays.axis && arrays.minor) {
        attrib(4, buffer(arrays.axis), 3, gl.FLOAT, false, 0, 0);
        attrib(5, buffer(arrays.minor), 1, gl.FLOAT, false, 0, 0);
        this.ellipse = true;
      }
      this.colorBuffer = arrays.color ? buffer(arrays.color) : null;
      this.surfaceBuffer = arrays.surface_color ? buffer(arrays.surface_color) : null;
      if (arrays.surface) {
        gl.bindBuffer(gl.ARRAY_BUFFER, buffer(arrays.surface));
        gl.enableVertexAttribArray(7);
        gl.vertexAttribIPointer(7, 1, gl.UNSIGNED_INT, 0, 0);
        this.hasIds = true;
      }
      this.useColors(false);
    }
    gl.bindVertexArray(null);
    this.model = model;
  }

  // Splat files: the file's colours, or the surface palette when `surfaces` and the file has ids.
  useColors(surfaces) {
    const gl = this.gl;
    if (this.kind !== 'splats') return;
    const b = surfaces && this.surfaceBuffer ? this.surfaceBuffer : this.colorBuffer;
    gl.bindVertexArray(this.vao);
    if (b) {
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.enableVertexAttribArray(3);
      gl.vertexAttribPointer(3, 3, gl.FLOAT, false, 0, 0);
    } else {
      gl.disableVertexAttribArray(3);
    }
    gl.bindVertexArray(null);
  }

  resize(width, height) {
    if (width === this.width && height === this.height) return;
    const gl = this.gl;
    this.width = width;
    this.height = height;
    this.canvas.width = width;
    this.canvas.height = height;
    if (this.fbo) {
      gl.deleteFramebuffer(this.fbo);
      this.targets.forEach((t) => gl.deleteTexture(t));
      gl.deleteRenderbuffer(this.depth);
      gl.deleteFramebuffer(this.idFbo);
      gl.deleteTexture(this.idTarget);
    }
    this.fbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fbo);
    this.targets = [0, 1].map((i) => {
      const t = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, t);
      gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA16F, width, height);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0 + i, gl.TEXTURE_2D, t, 0);
      return t;
    });
    this.depth = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, this.depth);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT32F, width, height);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, this.depth);
    // The id pass's target, in a framebuffer of its own (the attribute pass samples it).
    this.idFbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.idFbo);
    this.idTarget = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, this.idTarget);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.R32UI, width, height);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, this.idTarget, 0);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, this.depth);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  }

  // How many entries of the ranges pass the interval test the vertex shader makes, and its
  // back-face test with backCos <= 1 (for the stats; the GPU does not report it).
  sptSelected(proj, k, ranges, backCos = 2) {
    const f = this.entries, e = proj.eye;
    const q = new Int16Array(f.buffer, f.byteOffset, f.length * 2);  // normals: shorts 6-8
    let n = 0;
    for (const { first, count } of ranges)
      for (let i = first; i < first + count; ++i) {
        const o = 9 * i;
        const dx = f[o] - e[0], dy = f[o + 1] - e[1], dz = f[o + 2] - e[2];
        const dist = Math.hypot(dx, dy, dz), r = dist * k;
        if (!(f[o + 6] <= r && r < f[o + 7])) continue;
        if (backCos <= 1) {
          const nx = q[2 * o + 6], ny = q[2 * o + 7], nz = q[2 * o + 8];
          if (nx * dx + ny * dy + nz * dz > backCos * dist * Math.hypot(nx, ny, nz)) continue;
        }
        ++n;
      }
    return n;
  }

  // Draws the frame's ranges of the vertex buffer as points (WEBGL_multi_draw measured slower
  // in SwiftShader than one drawArrays per range).
  drawPoints() {
    const gl = this.gl;
    for (const { first, count } of this.ranges) gl.drawArrays(gl.POINTS, first, count);
  }

  // Draws one frame. opts: {splatScale, sptError (px), qsplatThreshold (px), shade ('phong',
  // 'normals', 'depth', 'flat'), epsilon (scene units; default 3 x the mean radius), backFaces
  // (z-buffer blending: 'auto', 'cull' or 'show', backFaceCosine), moving (the camera moves)}.
  // Returns {submitted: the vertices drawn, drawn: the splats among them (.spt: those passing
  // the interval test, counted unless opts.countSpt is false)}.
  draw(proj, opts) {
    const gl = this.gl;
    const h = this.model.header;
    let count = h.count, submitted = h.count;
    let sptK = 0;
    this.ranges = [{ first: 0, count }];
    if (h.kind === 'spt') {
      sptK = opts.sptError / proj.focal / h.epsilon;
      this.ranges = sptRanges(this.split, proj, sptK, h, this.radiusScale * opts.splatScale);
      count = submitted = this.ranges.reduce((sum, r) => sum + r.count, 0);
    } else if (h.kind === 'qsplat') {
      const t = opts.traverse(proj, this.stream);
      count = submitted = t.drawn;
      this.ranges = [{ first: 0, count }];
      gl.bindBuffer(gl.ARRAY_BUFFER, this.streamBuffer);
      gl.bufferSubData(gl.ARRAY_BUFFER, 0, this.stream, 0, count * 10);
    }
    const centreDepth = (h.center[0] - proj.eye[0]) * proj.forward[0] +
                        (h.center[1] - proj.eye[1]) * proj.forward[1] +
                        (h.center[2] - proj.eye[2]) * proj.forward[2];
    // splat-view's Z-threshold is 2 x the mean radius, but it chains: a fragment joins within
    // epsilon of the previous joined one, so a pixel's surface reaches deeper than epsilon behind
    // the nearest fragment. One fixed offset of 3 x the mean radius matches it best (CGAL's
    // building at 35,25: PSNR .qs 27.9 -> 28.3 dB, .splk and .spt 28.5 -> 28.6; 2.5 and 3.5 do worse).
    const eps = opts.epsilon ?? 3 * h.mean_radius * opts.splatScale;
    const depthNear = Math.max(proj.near, centreDepth - h.radius);
    const depthFar = Math.max(depthNear + 1e-6, centreDepth + h.radius + eps);

    const light = [-0.4 * proj.right[0] - 0.6 * proj.down[0] - proj.forward[0],
                   -0.4 * proj.right[1] - 0.6 * proj.down[1] - proj.forward[1],
                   -0.4 * proj.right[2] - 0.6 * proj.down[2] - proj.forward[2]];
    const ln = Math.hypot(light[0], light[1], light[2]);
    this.light = light.map((v) => v / ln);
    const mode = { phong: 0, normals: 1, depth: 2, flat: 3, surface: 0 }[opts.shade] ?? 0;
    // The uniforms every splat program reads (a program ignores those it does not have).
    const setUniforms = (program) => {
      gl.useProgram(program.program);
      const u = program.uniforms;
      gl.uniform3fv(u.uEye, proj.eye);
      gl.uniform3fv(u.uRight, proj.right);
      gl.uniform3fv(u.uDown, proj.down);
      gl.uniform3fv(u.uForward, proj.forward);
      gl.uniform1f(u.uFocal, proj.focal);
      gl.uniform1f(u.uCx, proj.cx);
      gl.uniform1f(u.uCy, proj.cy);
      gl.uniform1f(u.uW, proj.width);
      gl.uniform1f(u.uH, proj.height);
      gl.uniform1f(u.uNear, proj.near);
      gl.uniform1f(u.uRadiusScale, this.radiusScale * opts.splatScale);
      gl.uniform1f(u.uSptK, sptK);
      gl.uniform1f(u.uMaxPoint, this.maxPoint);
      gl.uniform1i(u.uSpt, h.kind === 'spt' ? 1 : 0);
      gl.uniform1i(u.uSrgbColor, this.srgbColor ? 1 : 0);
      gl.uniform1i(u.uEllipse, this.ellipse ? 1 : 0);
      gl.uniform1f(u.uDepthNear, depthNear);
      gl.uniform1f(u.uDepthFar, depthFar);
      // Back faces within reach of a front face: splat-view sets them aside; here they weigh 1/4096
      // (not 0: a pixel with back faces alone must keep a weight; 1/256 cost the .qs 0.3 dB).
      gl.uniform1f(u.uBackWeight, 1 / 4096);
      return u;
    };
    if (opts.blend === 'zbuffer') {
      const key = `${mode} ${this.srgbColor}`;
      if (!this.zbuffer.has(key)) {
        this.zbuffer.set(key, compile(gl, define(ZB_VS, `#define MODE ${mode}` +
                                                     (this.srgbColor ? '\n#define SRGB_COLOR' : '')), ZB_FS));
      }
      return this.drawZBuffer(proj, setUniforms(this.zbuffer.get(key)), submitted, count, opts, sptK);
    }

    const useIds = this.hasIds && opts.surfaceIds !== false;
    gl.bindVertexArray(this.vao);
    if (useIds) {  // 0. the nearest splat's surface id per pixel
      const ui = setUniforms(this.idPass);
      gl.uniform1f(ui.uDepthOffset, 0);
      gl.bindFramebuffer(gl.FRAMEBUFFER, this.idFbo);
      gl.viewport(0, 0, proj.width, proj.height);
      gl.clearBufferuiv(gl.COLOR, 0, [0xFFFFFFFF, 0, 0, 0]);
      gl.clearBufferfi(gl.DEPTH_STENCIL, 0, 1, 0);
      gl.enable(gl.DEPTH_TEST);
      gl.depthFunc(gl.LESS);
      gl.depthMask(true);
      this.drawPoints();
    }

    gl.bindFramebuffer(gl.FRAMEBUFFER, this.fbo);
    gl.viewport(0, 0, proj.width, proj.height);
    gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
    gl.clearBufferfv(gl.COLOR, 0, [0, 0, 0, 0]);
    gl.clearBufferfv(gl.COLOR, 1, [0, 0, 0, 0]);
    gl.clearBufferfi(gl.DEPTH_STENCIL, 0, 1, 0);
    gl.bindVertexArray(this.vao);
    gl.enable(gl.DEPTH_TEST);

    // 1. visibility
    gl.depthFunc(gl.LESS);
    gl.depthMask(true);
    gl.colorMask(false, false, false, false);
    gl.drawBuffers([gl.NONE, gl.NONE]);
    const uv = setUniforms(this.visibility);
    gl.uniform1f(uv.uDepthOffset, eps);
    this.drawPoints();
    const times = [];
    if (opts.profile) { this.finish(); times.push(performance.now()); }
    // 2. attributes
    gl.depthFunc(gl.LEQUAL);
    gl.depthMask(false);
    gl.colorMask(true, true, true, true);
    gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE);
    const u = setUniforms(this.splat);
    gl.uniform1f(u.uDepthOffset, 0);
    gl.activeTexture(gl.TEXTURE2);
    gl.bindTexture(gl.TEXTURE_2D, this.idTarget);
    gl.uniform1i(u.uFrontId, 2);
    gl.uniform1i(u.uUseIds, useIds ? 1 : 0);
    this.drawPoints();
    if (opts.profile) { this.finish(); times.push(performance.now()); }
    gl.disable(gl.BLEND);
    gl.disable(gl.DEPTH_TEST);
    gl.depthMask(true);
    gl.bindVertexArray(null);

    // 3. normalisation and shading
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    const s = this.shade[mode];
    gl.useProgram(s.program);
    const su = s.uniforms;
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, this.targets[0]);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, this.targets[1]);
    gl.uniform1i(su.uNormalSum, 0);
    gl.uniform1i(su.uColorSum, 1);
    gl.uniform3fv(su.uRight, proj.right);
    gl.uniform3fv(su.uDown, proj.down);
    gl.uniform3fv(su.uForward, proj.forward);
    gl.uniform3fv(su.uLight, this.light);
    gl.uniform3fv(su.uBackground, BACKGROUND);
    gl.activeTexture(gl.TEXTURE3);
    gl.bindTexture(gl.TEXTURE_2D, this.srgbTable);
    gl.uniform1i(su.uSrgbTable, 3);
    gl.uniform1f(su.uFocal, proj.focal);
    gl.uniform1f(su.uCx, proj.cx);
    gl.uniform1f(su.uCy, proj.cy);
    gl.uniform1f(su.uH, proj.height);
    gl.viewport(0, 0, proj.width, proj.height);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    if (opts.profile) { this.finish(); times.push(performance.now()); }
    const drawn = h.kind === 'spt' && opts.countSpt !== false
        ? this.sptSelected(proj, sptK, this.ranges) : count;
    return { submitted, drawn, draws: this.ranges.length, times };
  }

  drawZBuffer(proj, u, submitted, count, opts, sptK) {
    const gl = this.gl;
    const backCos = backFaceCosine(opts.backFaces ?? 'auto', this.model.header, proj.eye,
                                   opts.moving);
    gl.uniform3fv(u.uLight, this.light);
    gl.uniform1f(u.uBackCos, backCos);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, proj.width, proj.height);
    const bg = BACKGROUND;
    gl.clearColor(bg[0], bg[1], bg[2], 1);
    gl.clearDepth(1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.depthFunc(gl.LESS);
    gl.depthMask(true);
    gl.bindVertexArray(this.vao);
    this.drawPoints();
    gl.bindVertexArray(null);
    gl.disable(gl.DEPTH_TEST);
    const drawn = this.model.header.kind === 'spt' && opts.countSpt !== false
        ? this.sptSelected(proj, sptK, this.ranges, backCos) : count;
    return { submitted, drawn, draws: this.ranges.length, times: [], back_faces: backCos <= 1 ? 'culled' : 'shown' };
  }

  // Waits for the GPU (for timing): a one-pixel read of the bound framebuffer (the float
  // targets are read as floats).
  finish() {
    const gl = this.gl;
    if (gl.getParameter(gl.FRAMEBUFFER_BINDING)) {
      gl.readBuffer(gl.COLOR_ATTACHMENT0);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.FLOAT, new Float32Array(4));
    } else {
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    }
  }
}
