// Evaluated in the viewer page by tests/e2e/viewer.sh on a z-buffer page (backfaces=auto): a drag
// draws moving frames, which cull back faces from outside the model's box, and once the input has
// rested a still frame draws them again. Returns the stats' back_faces after each.
(async () => {
  const s = window.viewer.state;
  const canvas = document.getElementById('view');
  const frame = () => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
  canvas.dispatchEvent(new PointerEvent('pointerdown', { clientX: 100, clientY: 100, pointerId: 1 }));
  canvas.dispatchEvent(new PointerEvent('pointermove', { clientX: 120, clientY: 100, pointerId: 1 }));
  await frame();
  const moving = s.lastStats.back_faces;
  canvas.dispatchEvent(new PointerEvent('pointerup', { clientX: 120, clientY: 100, pointerId: 1 }));
  await new Promise((r) => setTimeout(r, 500));
  await frame();
  return { moving, still: s.lastStats.back_faces };
})()
