// The QSplat traversal (Rusinkiewicz and Levoy 2000) run per frame, as splat-view runs it
// (lib/render/select_qsplat.h): from each root, depth first, a node whose sphere lies outside a
// side plane of the view frustum or wholly behind the near plane is culled with its subtree; a
// leaf, or a node below a root whose projected size 2 r f / z is at most `thresholdPx`, is drawn
// as a disc of its sphere's radius; any other node recurses into its children.
//
// Writes the drawn nodes into out (Float32Array, 10 floats each: centre xyz, normal xyz, radius,
// linear colour rgb) and returns {drawn, visited}; stops at out's capacity.
export function traverseQSplat(model, proj, thresholdPx, out) {
  const { centre, radius, normal, first_child: first, child_count: kids, roots, color } =
      model.arrays;
  const { eye, right, down, forward, focal, near } = proj;
  const tx = proj.cx / focal, ty = proj.cy / focal;
  const ax = 1 / Math.hypot(1, tx), bx = tx / Math.hypot(1, tx);
  const ay = 1 / Math.hypot(1, ty), by = ty / Math.hypot(1, ty);
  const capacity = Math.floor(out.length / 10);
  const stack = new Int32Array(4096 * 4);
  const depths = new Int32Array(stack.length);
  let drawn = 0, visited = 0;
  for (let ri = 0; ri < roots.length; ++ri) {
    let top = 0;
    stack[top] = roots[ri]; depths[top] = 0; ++top;
    while (top > 0) {
      --top;
      const n = stack[top], d = depths[top];
      ++visited;
      const px = centre[3 * n] - eye[0], py = centre[3 * n + 1] - eye[1],
            pz = centre[3 * n + 2] - eye[2];
      const x = px * right[0] + py * right[1] + pz * right[2];
      const y = px * down[0] + py * down[1] + pz * down[2];
      const z = px * forward[0] + py * forward[1] + pz * forward[2];
      const r = radius[n];
      const k = kids[n];
      if (!(k && d === 0)) {
        if (z + r < near) continue;
        if (x * ax - z * bx > r || -x * ax - z * bx > r || y * ay - z * by > r ||
            -y * ay - z * by > r)
          continue;
      }
      const small = z > near && 2 * r * focal / z <= thresholdPx;
      if (k === 0 || (small && d > 0)) {
        if (drawn >= capacity) continue;
        const o = drawn * 10;
        out[o] = centre[3 * n]; out[o + 1] = centre[3 * n + 1]; out[o + 2] = centre[3 * n + 2];
        out[o + 3] = normal[3 * n]; out[o + 4] = normal[3 * n + 1]; out[o + 5] = normal[3 * n + 2];
        out[o + 6] = r;
        if (color) {
          out[o + 7] = color[3 * n]; out[o + 8] = color[3 * n + 1]; out[o + 9] = color[3 * n + 2];
        } else {
          out[o + 7] = out[o + 8] = out[o + 9] = 0.6;
        }
        ++drawn;
        continue;
      }
      if (top + k > stack.length) continue;  // deeper than any tree the writer makes
      for (let c = k - 1; c >= 0; --c) {
        stack[top] = first[n] + c; depths[top] = d + 1; ++top;
      }
    }
  }
  return { drawn, visited };
}
