// The CPU step of a Sequential Point Tree (Dachsbacher, Vogelgsang and Stamminger 2003), per cell
// of a grid. The list is sorted by r_max descending so that the entries that can pass the interval
// test at a distance of at least d are a prefix (r_max > k d); here the entries are also split by
// position into the cells of a G x G x G grid over their box, so that each cell's prefix comes
// from that cell's nearest distance to the eye rather than the whole model's, and cells outside
// the view frustum are left out; and segments of the list whose entries all have r_min beyond k x
// the cell's farthest distance (too coarse anywhere in the cell) are left out as well. The vertex
// shader then tests the interval only within what is left.
//
// Draw calls are costly in SwiftShader (one range per cell of an 8^3 grid drew slower than one
// per cell of a 4^3 grid, with a fifth more entries), so the list is laid out band-major: r_max falls into bands of a factor 2, and the list is ordered by band, then by cell,
// then as in the file (r_max descending). Each cell needs all of the coarse bands, a part of one
// band and nothing finer: the ranges a frame draws are long runs of whole (band, cell) segments,
// and segments less than MERGE_GAP entries apart are drawn as one range. Lists under CELL_MIN
// entries keep one cell and one band (the file's order).
//
// entries: Float32Array of 9 floats per entry, in the view model's layout (position xyz at 0..2,
// diameter at 5, r_min at 6, r_max at 7; encode_view_model.h).

const CELL_MIN = 1 << 20;
const GRID = 8;
const BANDS = 24;  // band 0: r_max infinite; band b: r_max in (top / 2^b, top / 2^(b-1)]
const MERGE_GAP = 256;
const INFINITE = 3e38;

function bandOf(rMax, top) {
  if (rMax >= INFINITE) return 0;
  const b = 1 + Math.floor(Math.log2(top / rMax));
  return Math.min(BANDS - 1, Math.max(1, b));
}

// Returns {entries (reordered: a new array unless one cell), cells: [{lo, hi, reach}] (the box
// of each cell's entries' positions and its largest radius), segments: [{first, count, cell,
// minRMin}] in list order (minRMin: the segment's smallest r_min)}.
export function makeSptCells(entries, count) {
  const g = count < CELL_MIN ? 1 : GRID;
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  let top = 0;
  for (let i = 0; i < count; ++i) {
    for (let a = 0; a < 3; ++a) {
      const v = entries[9 * i + a];
      if (v < lo[a]) lo[a] = v;
      if (v > hi[a]) hi[a] = v;
    }
    const r = entries[9 * i + 7];
    if (r < INFINITE && r > top) top = r;
  }
  const cellCount = g * g * g, bands = g > 1 ? BANDS : 1;
  const scale = [0, 1, 2].map((a) => (hi[a] > lo[a] ? g / (hi[a] - lo[a]) : 0));
  const cellOf = (i) => {
    let c = 0;
    for (let a = 2; a >= 0; --a)
      c = c * g + Math.min(g - 1, Math.floor((entries[9 * i + a] - lo[a]) * scale[a]));
    return c;
  };
  const keys = new Uint32Array(g > 1 ? count : 0);
  const sizes = new Uint32Array(cellCount * bands);
  if (g > 1) {
    for (let i = 0; i < count; ++i) {
      keys[i] = bandOf(entries[9 * i + 7], top) * cellCount + cellOf(i);
      ++sizes[keys[i]];
    }
  } else {
    sizes[0] = count;
  }
  const firsts = new Uint32Array(sizes.length);
  for (let k = 1; k < sizes.length; ++k) firsts[k] = firsts[k - 1] + sizes[k - 1];
  let out = entries;
  if (g > 1) {  // a stable counting sort by (band, cell), 9 words at a time
    const src = new Uint32Array(entries.buffer, entries.byteOffset, count * 9);
    const dst = new Uint32Array(count * 9);
    const next = firsts.slice();
    for (let i = 0; i < count; ++i) dst.set(src.subarray(9 * i, 9 * i + 9), 9 * next[keys[i]]++);
    out = new Float32Array(dst.buffer);
  }
  const cells = Array.from({ length: cellCount }, () => (
    { lo: [Infinity, Infinity, Infinity], hi: [-Infinity, -Infinity, -Infinity], reach: 0 }));
  const segments = [];
  for (let k = 0; k < sizes.length; ++k) {
    if (!sizes[k]) continue;
    const cell = cells[k % cellCount];
    for (let i = firsts[k]; i < firsts[k] + sizes[k]; ++i) {
      for (let a = 0; a < 3; ++a) {
        const v = out[9 * i + a];
        if (v < cell.lo[a]) cell.lo[a] = v;
        if (v > cell.hi[a]) cell.hi[a] = v;
      }
      cell.reach = Math.max(cell.reach, 0.5 * out[9 * i + 5]);
    }
    let minRMin = Infinity;
    for (let i = firsts[k]; i < firsts[k] + sizes[k]; ++i) minRMin = Math.min(minRMin, out[9 * i + 6]);
    segments.push({ first: firsts[k], count: sizes[k], cell: k % cellCount, minRMin });
  }
  return { entries: out, cells, segments };
}

// The ranges [first, count] of the list to draw for one frame: in each segment whose cell is not
// wholly outside the view frustum (its box grown by its largest splat, times radiusScale), the
// entries with r_max > k x (a lower bound on the eye's distance to any of the cell's entries: the
// larger of the distances to its box and to the model's bounding sphere), unless every entry of
// the segment has r_min > k x (an upper bound on that distance); in list order, ranges less than
// MERGE_GAP apart joined.
export function sptRanges(split, proj, k, sphere, radiusScale) {
  const { cells, segments, entries } = split;
  const { eye, right, down, forward, focal, near } = proj;
  const tx = proj.cx / focal, ty = proj.cy / focal;
  const ax = 1 / Math.hypot(1, tx), bx = tx / Math.hypot(1, tx);
  const ay = 1 / Math.hypot(1, ty), by = ty / Math.hypot(1, ty);
  const toSphere = Math.max(0, Math.hypot(eye[0] - sphere.center[0], eye[1] - sphere.center[1],
                                          eye[2] - sphere.center[2]) - sphere.radius);
  const farSphere = Math.hypot(eye[0] - sphere.center[0], eye[1] - sphere.center[1],
                              eye[2] - sphere.center[2]) + sphere.radius;
  // Per cell: k x the bounds on the distance [nearest, farthest], or null when outside the frustum.
  const bounds = cells.map((cell) => {
    if (!(cell.hi[0] >= cell.lo[0])) return null;  // empty
    let d2 = 0, r2 = 0, f2 = 0;
    const p = [0, 0, 0];
    for (let a = 0; a < 3; ++a) {
      const e = eye[a] < cell.lo[a] ? cell.lo[a] - eye[a] : eye[a] > cell.hi[a] ? eye[a] - cell.hi[a] : 0;
      d2 += e * e;
      f2 += Math.max(Math.abs(eye[a] - cell.lo[a]), Math.abs(eye[a] - cell.hi[a])) ** 2;
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
        return null;
    }
    return [Math.max(Math.sqrt(d2), toSphere) * k, Math.min(Math.sqrt(f2), farSphere) * k];
  });
  const ranges = [];
  for (const s of segments) {
    const b = bounds[s.cell];
    // Left out: cells outside the frustum, and segments too coarse for the cell's farthest point.
    if (!b || s.minRMin > b[1]) continue;
    const nearest = b[0];
    let lo = s.first, hi = s.first + s.count;
    if (entries[9 * (hi - 1) + 7] > nearest) {
      lo = hi;  // the whole segment
    } else {
      while (lo < hi) {
        const mid = (lo + hi) >>> 1;
        if (entries[9 * mid + 7] > nearest) lo = mid + 1; else hi = mid;
      }
    }
    if (lo === s.first) continue;
    const last = ranges[ranges.length - 1];
    if (last && s.first - (last.first + last.count) < MERGE_GAP) last.count = lo - last.first;
    else ranges.push({ first: s.first, count: lo - s.first });
  }
  return ranges;
}
