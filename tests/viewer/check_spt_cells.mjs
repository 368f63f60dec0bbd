// Checks web/spt_cells.js on a synthetic list large enough to be split (CELL_MIN entries): the
// reordering is a permutation of the entries, and for cameras inside, near and far from the box,
// every entry whose centre projects into the image and whose interval holds the eye's distance
// (what the vertex shader draws) lies in one of the frame's ranges, which are disjoint and in
// bounds. Seeded; prints one JSON line and exits 1 on a failure.
//   node check_spt_cells.mjs
import { makeSptCells, sptRanges } from '../../web/spt_cells.js';
import { makeProjection } from '../../web/camera.js';

let seed = 12345;
const rand = () => {  // mulberry32
  seed = (seed + 0x6d2b79f5) | 0;
  let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
  t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
  return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
};

const count = (1 << 20) + 4096;
const rows = [];
for (let i = 0; i < count; ++i) {
  const rMax = i < 8 ? 3.4e38 : 0.01 * 2 ** (16 * rand());
  const leaf = rand() < 0.3;
  rows.push([10 * rand(), 4 * rand(), 2 * rand(), 0, 0, 0.02 * rand(), leaf ? 0 : rMax / 2, rMax, i]);
}
rows.sort((a, b) => b[7] - a[7]);
const list = new Float32Array(count * 9);
rows.forEach((r, i) => list.set(r, 9 * i));  // float 8 (normally colour) keeps the entry's id
const ids = new Float32Array(list.filter((_, j) => j % 9 === 8)).sort().join();

const failures = [];
const split = makeSptCells(list, count);
const e = split.entries;
if (new Float32Array(e.filter((_, j) => j % 9 === 8)).sort().join() !== ids)
  failures.push('the reordered list is not a permutation');

const sphere = { center: [5, 2, 1], radius: Math.hypot(5, 2, 1) };
const cameras = [
  { eye: [5, 2, 1.5], target: [9, 3, 1] },  // inside the box
  { eye: [-3, -4, 3], target: [5, 2, 1] },
  { eye: [12, 1, 0.5], target: [0, 3, 1] },
  { eye: [5, 2, 40], target: [5, 2.01, 1] },
  { eye: [300, 200, 100], target: [5, 2, 1] },
];
let checked = 0, submitted = 0;
for (const c of cameras) {
  const proj = makeProjection({ ...c, up: [0, 0, 1], fovY: 40 }, 1280, 720);
  for (const err of [1, 4]) {
    const k = err / proj.focal / 0.001;
    const ranges = sptRanges(split, proj, k, sphere, 0.5);
    const inRange = new Uint8Array(count);
    let last = -1;
    for (const r of ranges) {
      if (r.first <= last || r.count <= 0 || r.first + r.count > count)
        failures.push(`bad range ${JSON.stringify(r)}`);
      last = r.first + r.count - 1;
      inRange.fill(1, r.first, r.first + r.count);
      submitted += r.count;
    }
    for (let i = 0; i < count; ++i) {
      const d = [e[9 * i] - proj.eye[0], e[9 * i + 1] - proj.eye[1], e[9 * i + 2] - proj.eye[2]];
      const dot = (a) => d[0] * a[0] + d[1] * a[1] + d[2] * a[2];
      const z = dot(proj.forward);
      if (!(z > proj.near)) continue;
      const x = proj.cx + proj.focal * dot(proj.right) / z, y = proj.cy + proj.focal * dot(proj.down) / z;
      if (x < 0 || x > proj.width || y < 0 || y > proj.height) continue;
      const r = Math.hypot(d[0], d[1], d[2]) * k;
      if (!(e[9 * i + 6] <= r && r < e[9 * i + 7])) continue;
      ++checked;
      if (!inRange[i]) {
        failures.push(`entry ${e[9 * i + 8]} is drawn but left out (camera ${JSON.stringify(c)})`);
        break;
      }
    }
  }
}
console.log(JSON.stringify({ entries: count, cells: split.cells.filter((c) => c.hi[0] >= c.lo[0]).length,
                             segments: split.segments.length, checked, submitted,
                             failures: failures.slice(0, 5) }));
process.exit(failures.length || checked === 0 ? 1 : 0);
