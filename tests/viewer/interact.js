// Evaluated in the viewer page by tests/e2e/viewer.sh (drive_chromium.mjs --eval): drags the orbit
// camera, zooms, switches to the walk camera and walks, changes the controls, and returns what
// each step did to the camera, the URL and the stats.
(async () => {
  const s = window.viewer.state;
  const canvas = document.getElementById('view');
  const frame = () => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
  const out = {};
  const az0 = s.orbit.az, el0 = s.orbit.el;
  canvas.dispatchEvent(new PointerEvent('pointerdown', { clientX: 100, clientY: 100, pointerId: 1 }));
  canvas.dispatchEvent(new PointerEvent('pointermove', { clientX: 140, clientY: 90, pointerId: 1 }));
  canvas.dispatchEvent(new PointerEvent('pointerup', { clientX: 140, clientY: 90, pointerId: 1 }));
  await frame();
  out.orbit_turned = s.orbit.az !== az0 && s.orbit.el !== el0;
  out.hash_after_drag = location.hash;
  canvas.dispatchEvent(new WheelEvent('wheel', { deltaY: 200, cancelable: true }));
  await frame();
  out.zoomed_out = s.orbit.dist > 0;
  const mode = document.getElementById('mode');
  mode.value = 'walk';
  mode.dispatchEvent(new Event('change'));
  const eye0 = s.walk.eye.slice();
  window.dispatchEvent(new KeyboardEvent('keydown', { key: 'w' }));
  await frame();
  out.walked = s.walk.eye.some((v, i) => v !== eye0[i]);
  const shade = document.getElementById('shade');
  shade.value = 'normals';
  shade.dispatchEvent(new Event('change'));
  await frame();
  out.shade = s.shade;
  out.stats = document.getElementById('stats').textContent;
  out.error = document.getElementById('error').textContent;
  return out;
})()
