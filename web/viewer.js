// The viewer page of splat-view --serve: loads a served file's view model, draws it with
// SplatRenderer, and keeps the camera in the URL:
//   #file=NAME&view=AZ,EL[,DIST]  the camera of `splat-view NAME OUT --view AZ,EL[,DIST]` at the
//                                 window's size (camera.js); optional shade=, size=, spt-error=,
//                                 qsplat-threshold=, backfaces= (auto, cull, show) as the controls.
// For tests and measurements, window.viewer offers ready (a promise of the first frame's
// stats), capture() (the canvas as a PNG data URL) and bench(ms) (frames per second drawing
// continuously with the camera turning). blend=zbuffer draws one pass without blending (fast),
// blend=botsch the three passes; without blend=, files of LARGE_MODEL entries or more open with
// the z-buffer (the only mode that keeps 20 frames/s on a 5M-entry .spt in software GL:
// docs/design/viewer.md), smaller ones blended.
import { DEFAULT_AZIMUTH, DEFAULT_ELEVATION, DEFAULT_FOV, add, cross, makeProjection, norm,
         normalized, orbitCamera, parseView, scale, sub } from './camera.js';
import { traverseQSplat } from './qsplat_traversal.js';
import { SplatRenderer } from './splat_gl.js';
import { parseViewModel } from './view_model.js';

const $ = (id) => document.getElementById(id);
const canvas = $('view');
const UP = [0, 0, 1];
const LARGE_MODEL = 1000000;

const state = {
  model: null, name: '',
  orbit: { az: DEFAULT_AZIMUTH, el: DEFAULT_ELEVATION, dist: undefined },
  walk: null,  // {eye, dir} in walk mode
  shade: 'phong', blend: 'botsch', blendAsked: null, size: 1, sptError: 1, qsThreshold: 1,
  backFaces: 'auto', moving: false, stillTimer: 0,
  lastMs: 0, lastStats: null,
};
let renderer = null;
let pending = false;

function params() {
  return new URLSearchParams(location.hash.replace(/^#/, ''));
}

function showError(text) {
  $('error').textContent = text;
  $('error').classList.remove('hidden');
  $('result').textContent = JSON.stringify({ error: text });
}

function viewportSize() {
  return [Math.max(1, Math.round(canvas.clientWidth * devicePixelRatio)),
          Math.max(1, Math.round(canvas.clientHeight * devicePixelRatio))];
}

function camera(width, height) {
  const h = state.model.header;
  if (state.walk) {
    return { eye: state.walk.eye, target: add(state.walk.eye, state.walk.dir), up: UP,
             fovY: DEFAULT_FOV };
  }
  const o = state.orbit;
  return orbitCamera({ center: h.center, radius: h.radius, box: h.box }, o.az, o.el, o.dist, UP,
                     DEFAULT_FOV, width, height);
}

function frame() {
  pending = false;
  if (!state.model) return null;
  const [w, h] = viewportSize();
  renderer.resize(w, h);
  const proj = makeProjection(camera(w, h), w, h);
  const t0 = performance.now();
  const r = renderer.draw(proj, {
    splatScale: state.size, sptError: state.sptError, shade: state.shade, blend: state.blend,
    backFaces: state.backFaces, moving: state.moving,
    profile: state.profile, countSpt: !state.benchmarking,
    traverse: (p, out) => traverseQSplat(state.model, p, state.qsThreshold, out),
  });
  if (!state.benchmarking) renderer.finish();  // (ms/frame: the GPU's work too)
  state.lastMs = performance.now() - t0;
  const hd = state.model.header;
  state.lastStats = { file: state.name, kind: hd.kind, entries: hd.count, splats: r.drawn,
                      submitted: r.submitted, draws: r.draws,
                      ...(r.back_faces ? { back_faces: r.back_faces } : {}),
                      ms: Math.round(state.lastMs * 100) / 100, width: w, height: h };
  if (state.profile && r.times.length === 3) {  // ms of: selection + visibility, attributes, shading
    const t = [t0, ...r.times];
    state.lastStats.pass_ms = [1, 2, 3].map((i) => Math.round((t[i] - t[i - 1]) * 10) / 10);
  }
  $('stats').textContent =
      `${state.name} (${hd.kind}, ${hd.count} ${hd.kind === 'splats' ? 'splats' : 'nodes'})\n` +
      `splats drawn: ${r.drawn}` +
      (hd.kind === 'spt' ? ` (of a prefix of ${r.submitted} entries)\n` : '\n') +
      `${state.lastMs.toFixed(1)} ms/frame  ${w}x${h}`;
  return state.lastStats;
}

// The camera moved (drag, wheel, keys): a frame now, drawn as moving, and one drawn still once
// the input has rested for STILL_MS (backfaces=auto culls back faces only while moving).
const STILL_MS = 200;
function moved() {
  state.moving = true;
  clearTimeout(state.stillTimer);
  state.stillTimer = setTimeout(() => { state.moving = false; redraw(); }, STILL_MS);
  redraw();
}

function redraw() {
  if (!pending) {
    pending = true;
    requestAnimationFrame(frame);
  }
}

function writeHash() {
  const p = params();
  p.set('file', state.name);
  if (!state.walk) {
    const o = state.orbit;
    const f = (v) => String(Math.round(v * 1000) / 1000);
    p.set('view', [f(o.az), f(o.el)].concat(o.dist ? [f(o.dist)] : []).join(','));
  }
  history.replaceState(null, '', '#' + p.toString().replace(/%2C/g, ','));
}

async function open(name) {
  const response = await fetch('model/' + encodeURIComponent(name));
  if (!response.ok) throw new Error(`${name}: ${(await response.text()).trim()}`);
  state.model = parseViewModel(await response.arrayBuffer());
  state.name = name;
  renderer.load(state.model);
  renderer.useColors?.(state.shade === 'surface');
  chooseBlend();
  $('spt-row').classList.toggle('hidden', state.model.header.kind !== 'spt');
  $('qs-row').classList.toggle('hidden', state.model.header.kind !== 'qsplat');
}

function readControlsFromHash() {
  const p = params();
  const v = p.get('view');
  if (v) {
    const parsed = parseView(v);
    if (!parsed) throw new Error(`view=${v}: needs AZ,EL or AZ,EL,DIST (numbers, DIST > 0)`);
    state.orbit = parsed;
    state.walk = null;
  }
  const num = (key, fallback) => (p.has(key) && Number.isFinite(+p.get(key)) ? +p.get(key) : fallback);
  state.shade = p.get('shade') ?? state.shade;
  state.blendAsked = ['zbuffer', 'botsch'].includes(p.get('blend')) ? p.get('blend') : null;
  chooseBlend();
  state.size = num('size', state.size);
  state.sptError = num('spt-error', state.sptError);
  state.qsThreshold = num('qsplat-threshold', state.qsThreshold);
  state.backFaces = ['auto', 'cull', 'show'].includes(p.get('backfaces')) ? p.get('backfaces')
                                                                          : state.backFaces;
  state.profile = p.get('profile') === '1';
  $('shade').value = state.shade;
  $('backfaces').value = state.backFaces;
  $('size').value = state.size;
  $('spt-error').value = state.sptError;
  $('qs-threshold').value = state.qsThreshold;
  $('spt-error-value').textContent = state.sptError;
  $('qs-threshold-value').textContent = state.qsThreshold;
}

// The blending asked for (URL or control), else the default for the file's size.
function chooseBlend() {
  const large = state.model && state.model.header.count >= LARGE_MODEL;
  state.defaultBlend = large ? 'zbuffer' : 'botsch';
  state.blend = state.blendAsked ?? state.defaultBlend;
  $('blend').value = state.blend;
  $('backfaces-row').classList.toggle('hidden', state.blend !== 'zbuffer');
}

function bindControls() {
  $('file').onchange = async () => {
    state.orbit = { az: DEFAULT_AZIMUTH, el: DEFAULT_ELEVATION, dist: undefined };
    state.walk = null;
    await open($('file').value);
    writeHash();
    redraw();
  };
  $('shade').onchange = () => {
    state.shade = $('shade').value;
    renderer.useColors?.(state.shade === 'surface');
    redraw();
  };
  $('blend').onchange = () => {
    state.blendAsked = $('blend').value;
    chooseBlend();
    redraw();
  };
  $('backfaces').onchange = () => { state.backFaces = $('backfaces').value; redraw(); };
  $('size').oninput = () => { state.size = +$('size').value; redraw(); };
  $('spt-error').oninput = () => {
    state.sptError = +$('spt-error').value;
    $('spt-error-value').textContent = state.sptError;
    redraw();
  };
  $('qs-threshold').oninput = () => {
    state.qsThreshold = +$('qs-threshold').value;
    $('qs-threshold-value').textContent = state.qsThreshold;
    redraw();
  };
  $('mode').onchange = () => {
    if ($('mode').value === 'walk') {
      const [w, h] = viewportSize();
      const c = camera(w, h);
      state.walk = { eye: c.eye, dir: normalized(sub(c.target, c.eye)) };
    } else {
      state.walk = null;
    }
    redraw();
  };
  let drag = null;
  canvas.onpointerdown = (e) => { drag = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId); };
  canvas.onpointerup = () => { drag = null; writeHash(); };
  canvas.onpointermove = (e) => {
    if (!drag || !state.model) return;
    const dx = e.clientX - drag[0], dy = e.clientY - drag[1];
    drag = [e.clientX, e.clientY];
    if (state.walk) {  // look around: yaw about up, pitch about the camera's right
      const yaw = -dx * 0.004, pitch = -dy * 0.004;
      let d = state.walk.dir;
      d = [d[0] * Math.cos(yaw) - d[1] * Math.sin(yaw), d[0] * Math.sin(yaw) + d[1] * Math.cos(yaw), d[2]];
      const el = Math.max(-1.5, Math.min(1.5, Math.asin(Math.max(-1, Math.min(1, d[2]))) + pitch));
      const horiz = normalized([d[0], d[1], 0]);
      state.walk.dir = [horiz[0] * Math.cos(el), horiz[1] * Math.cos(el), Math.sin(el)];
    } else {
      state.orbit.az -= dx * 0.3;
      state.orbit.el = Math.max(-89.9, Math.min(89.9, state.orbit.el + dy * 0.3));
    }
    moved();
  };
  canvas.onwheel = (e) => {
    if (!state.model || state.walk) return;
    e.preventDefault();
    const [w, h] = viewportSize();
    const c = camera(w, h);
    const d = norm(sub(c.eye, c.target));
    state.orbit.dist = d * Math.exp(e.deltaY * 0.001);
    writeHash();
    moved();
  };
  addEventListener('keydown', (e) => {
    if (!state.walk) return;
    const step = 0.02 * state.model.header.radius * (e.shiftKey ? 5 : 1);
    const right = normalized(cross(state.walk.dir, UP));
    const moves = { w: state.walk.dir, s: scale(state.walk.dir, -1), d: right,
                    a: scale(right, -1), e: UP, q: scale(UP, -1) };
    const m = moves[e.key.toLowerCase()];
    if (!m) return;
    state.walk.eye = add(state.walk.eye, scale(m, step));
    moved();
  });
  addEventListener('resize', redraw);
  addEventListener('hashchange', async () => {
    try {
      const name = params().get('file');
      if (name && name !== state.name) await open(name);
      readControlsFromHash();
      redraw();
    } catch (err) {
      showError(String(err.message ?? err));
    }
  });
}

async function start() {
  renderer = new SplatRenderer(canvas);
  const listing = await (await fetch('files.json')).json();
  for (const name of listing.files) $('file').add(new Option(name, name));
  bindControls();
  readControlsFromHash();
  const name = params().get('file') ?? listing.files[0];
  if (!name) throw new Error('no file is served');
  $('file').value = name;
  await open(name);
  if (!params().has('file')) writeHash();
  if (params().get('hud') === '0') {
    $('panel').classList.add('hidden');
    $('stats').classList.add('hidden');
  }
  const stats = frame();
  $('result').textContent = JSON.stringify(stats);
  return stats;
}

// Draws a frame per animation frame for `ms` milliseconds, turning the camera a little each
// frame (a moving camera), and returns {fps, frames, ms_per_frame, splats, ...}: the rate the page reaches, GPU
// work and the browser's compositing included (the GPU is waited for once, at the end).
async function bench(ms) {
  state.benchmarking = true;
  state.moving = true;
  const t0 = performance.now();
  let frames = 0, last = null;
  while (performance.now() - t0 < ms) {
    await new Promise((resolve) => requestAnimationFrame(resolve));
    state.orbit.az += 0.5;
    last = frame();
    ++frames;
  }
  renderer.finish();
  state.benchmarking = false;
  state.moving = false;
  const elapsed = performance.now() - t0;
  return { fps: frames / (elapsed / 1000), frames, ms_per_frame: elapsed / frames,
           pass_ms: last?.pass_ms, blend: state.blend, default_blend: state.defaultBlend,
           splats: last?.splats, entries: last?.entries, width: last?.width, height: last?.height,
           back_faces: last?.back_faces };
}

const ready = start().catch((err) => {
  showError(String(err.message ?? err));
  return { error: String(err.message ?? err) };
});
// capture() draws a frame and reads the canvas in the same task (the drawing buffer is not
// preserved across frames, which saves a copy per frame).
window.viewer = { ready, bench, capture: () => { frame(); return canvas.toDataURL('image/png'); }, state };
