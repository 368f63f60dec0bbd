// The CPU step of a Sequential Point Tree (Dachsbacher, Vogelgsang and Stamminger 2003) per cell
// of a grid: the list is split by entry position into the cells of a G x G x G grid over its
// box, each cell keeping the list's order (r_max descending), so that the CPU finds for each
// cell the prefix that can pass the interval test from that cell's nearest distance to the eye
// rather than the whole model's, and leaves out the cells outside the view frustum. The vertex
// shader then tests the interval only within those prefixes. Lists under CELL_MIN entries keep
// one cell (the whole model, as before).
//
// entries: Float32Array of 9 floats per entry, in the view model's layout (position xyz at 0..2,
// diameter at 5, r_min at 6, r_max at 7; encode_view_model.h).

const CELL_MIN = 1 << 20;

// Returns {entries (reordered, a new array unless one cell), cells: [{first, count, lo, hi,
// reach}]}: each cell's range in the list, the box of its entries' positions and the largest
// radius among them.
export function makeSptCells(entries, count, grid) {
  const g = grid ?? (count < CELL_MIN ? 1 : 8);
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < count; ++i)
    for (let a = 0; a < 3; ++a) {
      const v = entries[9 * i + a];
      if (v < lo[a]) lo[a] = v;
      if (v > hi[a]) hi[a] = v;
    }
  const scale = [0, 1, 2].map((a) => (hi[a] > lo[a] ? g / (hi[a] - lo[a]) : 0));
  const cellOf = new Uint32Array(g > 1 ? count : 0);
  const sizes = new Uint32Array(g * g * g);
  if (g > 1) {
    for (let i = 0; i < count; ++i) {
      let c = 0;
      for (let a = 2; a >= 0; --a)
        c = c * g + Math.min(g - 1, Math.floor((entries[9 * i + a] - lo[a]) * scale[a]));
      cellOf[i] = c;
      ++sizes[c];
    }
  } else {
    sizes[0] = count;
  }
  const firsts = new Uint32Array(sizes.length);
  for (let c = 1; c < sizes.length; ++c) firsts[c] = firsts[c - 1] + sizes[c - 1];
  let out = entries;
  if (g > 1) {  // a stable counting sort by cell, 9 words at a time
    const src = new Uint32Array(entries.buffer, entries.byteOffset, count * 9);
    const dst = new Uint32Array(count * 9);
    const next = firsts.slice();
    for (let i = 0; i < count; ++i) {
      const o = 9 * next[cellOf[i]]++;
      dst.set(src.subarray(9 * i, 9 * i + 9), o);
    }
    out = new Float32Array(dst.buffer);
  }
  const cells = [];
  for (let c = 0; c < sizes.length; ++c) {
    if (!sizes[c]) continue;
    const cell = { first: firsts[c], count: sizes[c], lo: [Infinity, Infinity, Infinity],
                   hi: [-Infinity, -Infinity, -Infinity], reach: 0 };
    for (let i = cell.first; i < cell.first + cell.count; ++i) {
      for (let a = 0; a < 3; ++a) {
        const v = out[9 * i + a];
        if (v < cell.lo[a]) cell.lo[a] = v;
        if (v > cell.hi[a]) cell.hi[a] = v;
      }
      cell.reach = Math.max(cell.reach, 0.5 * out[9 * i + 5]);
    }
    cells.push(cell);
  }
  return { entries: out, cells };
}

// The ranges [first, count] of the list to draw for one frame: per cell not wholly outside the
// view frustum (its box grown by its largest splat, times radiusScale), the entries with
// r_max > k x (a lower bound on the eye's distance to any of its entries: the larger of the
// distances to its box and to the model's bounding sphere), nearest cells first.
export function sptRanges(cells, entries, proj, k, sphere, radiusScale) {
  const { eye, right, down, forward, focal, near } = proj;
  const tx = proj.cx / focal, ty = proj.cy / focal;
  const ax = 1 / Math.hypot(1, tx), bx = tx / Math.hypot(1, tx);
  const ay = 1 / Math.hypot(1, ty), by = ty / Math.hypot(1, ty);
  const toSphere = Math.max(0, Math.hypot(eye[0] - sphere.center[0], eye[1] - sphere.center[1],
                                          eye[2] - sphere.center[2]) - sphere.radius);
  const ranges = [];
  for (const cell of cells) {
    let d2 = 0, r2 = 0;
    const p = [0, 0, 0];
    for (let a = 0; a < 3; ++a) {
      const e = eye[a] < cell.lo[a] ? cell.lo[a] - eye[a] : eye[a] > cell.hi[a] ? eye[a] - cell.hi[a] : 0;
      d2 += e * e;
      p[a] = 0.5 * (cell.lo[a] + cell.hi[a]) - eye[a];
      r2 += 0.25 * (cell.hi[a] - cell.lo[a]) ** 2;
    }
    if (cells.length > 1) {  // frustum culling of the cell's bounding sphere
      const r = Math.sqrt(r2) + cell.reach * radiusScale;
      const x = p[0] * right[0] + p[1] * right[1] + p[2] * right[2];
      const y = p[0] * down[0] + p[1] * down[1] + p[2] * down[2];
      const z = p[0] * forward[0] + p[1] * forward[1] + p[2] * forward[2];
      if (z + r < near || x * ax - z * bx > r || -x * ax - z * bx > r || y * ay - z * by > r ||
          -y * ay - z * by > r)
        continue;
    }
    const nearest = Math.max(Math.sqrt(d2), toSphere) * k;
    let lo = cell.first, hi = cell.first + cell.count;
    while (lo < hi) {
      const mid = (lo + hi) >>> 1;
      if (entries[9 * mid + 7] > nearest) lo = mid + 1; else hi = mid;
    }
    if (lo > cell.first) ranges.push({ first: cell.first, count: lo - cell.first, d2 });
  }
  ranges.sort((a, b) => a.d2 - b.d2);
  return ranges;
}
