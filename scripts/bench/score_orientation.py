#!/usr/bin/python3
"""Scores estimated normals' orientation against a scene's reference normals (orientation.sh).

usage:
  score_orientation.py REF.ply EST.ply [EST.ply ...] [--kind synthetic|real]
      One JSON line per EST (a PLY with nx, ny, nz in REF's order; x, y, z, when present, are
      checked against REF's: a cloud written in another order is matched back by position).
      Scored: the points with class != 5 (vegetation) and a nonzero reference normal.
        agree             fraction with est . ref > 0
        walls_out         the same over class 2 (walls)
        ground_up         class 1 (ground): fraction with est_z > 0; roof_up: class 3, est_z > 0
        agree_consistent  (--kind real) agree over the points whose 16 nearest neighbours'
                          reference normals all agree with theirs (ref_i . ref_j > 0): real scans'
                          reference normals flip in places, and those places are left out
      An estimated normal that is NaN, zero or missing counts as wrong.
  score_orientation.py --scenes SCENE_DIR
      The scenes of a scan set, one line each: name, path, kind, and a JSON object of name, kind,
      closed, points and source (from SCENE_DIR/scenes.json; without one, every *.ply as an open
      synthetic scene).
  score_orientation.py --score REF.ply KIND SCENE_JSON RUNS.jsonl
      Scores the runs (JSON lines: tool, status, time_s, file, reason, note; those whose status
      is ok are scored) and prints each as a JSON line with the scene's fields and the scores.
  score_orientation.py --prepare SCENE.ply OUT.ply [K]
      Writes SCENE's x, y, z alone (binary PLY, for the peers that would otherwise read the
      reference normals) and prints the median distance to the K-th nearest neighbour (K = 16).
  score_orientation.py --report RESULTS.jsonl [--json OUT.json] [--cpu MODEL] [--threads T]
                       [--splatkit TEXT]
      Prints a table per scene, a summary per tool and splatkit's targets (ok / MISS); exits 3
      when a target is missed.

numpy only; scipy's cKDTree for the nearest neighbours when installed, else an exact grid search.
"""
import json
import math
import os
import sys

import numpy as np

try:
    from scipy.spatial import cKDTree
except ImportError:  # Debian's python3-scipy missing: the grid search below
    cKDTree = None

PLY_TYPES = {"char": "i1", "uchar": "u1", "int8": "i1", "uint8": "u1", "short": "i2",
             "ushort": "u2", "int16": "i2", "uint16": "u2", "int": "i4", "uint": "u4",
             "int32": "i4", "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8",
             "float64": "f8"}


def read_ply(path):
    """The vertex element of a PLY file as {property: array} (binary either endian, or ascii)."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        fmt, elements = None, []
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no end_header")
            words = line.decode("ascii", "replace").split()
            if not words:
                continue
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                elements.append((words[1], int(words[2]), []))
            elif words[0] == "property":
                if words[1] == "list":
                    elements[-1][2].append((words[4], None))
                else:
                    elements[-1][2].append((words[2], PLY_TYPES[words[1]]))
            elif words[0] == "end_header":
                break
        data = f.read()
    order = {"binary_little_endian": "<", "binary_big_endian": ">", "ascii": None}[fmt]
    offset = 0
    for name, count, props in elements:
        if any(t is None for _, t in props):
            if name == "vertex":
                raise ValueError(f"{path}: list property in the vertex element")
            raise ValueError(f"{path}: element {name} with lists before the vertices")
        if order is None:  # ascii: the vertex lines come first or after fixed-size elements
            lines = data.split(b"\n")
            rows = [ln for ln in lines[offset:offset + count]]
            if name == "vertex":
                table = np.array([r.split() for r in rows], dtype=np.float64)
                table = table.reshape(count, len(props))
                return {p: table[:, i].astype(t) for i, (p, t) in enumerate(props)}
            offset += count
            continue
        dtype = np.dtype([(p, order + t) for p, t in props])
        if name == "vertex":
            table = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            return {p: table[p].astype(t) for p, t in props}
        offset += count * dtype.itemsize
    raise ValueError(f"{path}: no vertex element")


def write_ply(path, columns):
    """A binary little-endian PLY with the given {name: array} as vertex properties."""
    names = list(columns)
    types = {"f4": "float", "f8": "double", "u1": "uchar", "i4": "int"}
    dtype = np.dtype([(n, "<" + columns[n].dtype.str[1:]) for n in names])
    table = np.empty(len(columns[names[0]]), dtype=dtype)
    for n in names:
        table[n] = columns[n]
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(table)}"]
    header += [f"property {types[columns[n].dtype.str[1:]]} {n}" for n in names]
    with open(path, "wb") as f:
        f.write(("\n".join(header + ["end_header"]) + "\n").encode("ascii"))
        f.write(table.tobytes())


def grid_knn(points, k, qxyz, qself=None):
    """Exact k nearest points to each of qxyz (never qself[i] itself) by a uniform grid, its rings
    grown around each query's cell until the k-th distance lies within them."""
    lo = np.minimum(points.min(axis=0), qxyz.min(axis=0))
    hi = np.maximum(points.max(axis=0), qxyz.max(axis=0))
    diag = float(np.linalg.norm(hi - lo)) or 1.0
    h = 2.0 * diag / math.sqrt(len(points))  # ~4 points per cell on a surface
    dims = np.floor((hi - lo) / h).astype(np.int64) + 1
    flat = lambda c: (c[..., 0] * dims[1] + c[..., 1]) * dims[2] + c[..., 2]
    key = flat(np.floor((points - lo) / h).astype(np.int64))
    order = np.argsort(key, kind="stable")
    sorted_keys = key[order]
    qcells = np.floor((qxyz - lo) / h).astype(np.int64)
    qkey = flat(qcells)
    by_cell = np.argsort(qkey, kind="stable")
    result = np.empty((len(qxyz), k), dtype=np.int64)
    for group in np.split(by_cell, np.flatnonzero(np.diff(qkey[by_cell])) + 1):
        pending, ring = group, 1
        while len(pending):
            r = np.arange(-ring, ring + 1)
            cells = np.stack(np.meshgrid(r, r, r, indexing="ij"), -1).reshape(-1, 3)
            cells += qcells[group[0]]
            keys = flat(cells[np.all((cells >= 0) & (cells < dims), axis=1)])
            starts = np.searchsorted(sorted_keys, keys, "left")
            ends = np.searchsorted(sorted_keys, keys, "right")
            cand = np.concatenate([order[s:e] for s, e in zip(starts, ends)])
            d2 = ((qxyz[pending][:, None, :] - points[cand][None, :, :]) ** 2).sum(axis=2)
            if qself is not None:
                d2[cand[None, :] == qself[pending][:, None]] = np.inf
            whole = (ring - 1) * h > diag  # the rings hold every point
            if len(cand) - (qself is not None) >= k:
                part = np.argpartition(d2, k - 1, axis=1)[:, :k]
                dk = np.take_along_axis(d2, part, axis=1)
                done = (dk.max(axis=1) <= (ring * h) ** 2) | whole
                rank = np.argsort(dk[done], axis=1, kind="stable")
                result[pending[done]] = cand[np.take_along_axis(part[done], rank, axis=1)]
                pending = pending[~done]
            elif whole:
                raise ValueError("fewer points than k")
            ring += 1
    return result


def knn(points, k, queries=None):
    """Indices of the k nearest other points of each query index (all points by default)."""
    if queries is None:
        queries = np.arange(len(points))
    if cKDTree is None:
        return grid_knn(points, k, points[queries], queries)
    _, idx = cKDTree(points).query(points[queries], k=k + 1)
    self_hit = idx == queries[:, None]
    # itself first among equals, or a duplicate before it: put itself last and keep k
    idx = np.take_along_axis(idx, np.argsort(self_hit, axis=1, kind="stable"), axis=1)
    return idx[:, :k]


def positions(ply):
    return np.stack([ply["x"], ply["y"], ply["z"]], axis=1).astype(np.float64)


def normals(ply):
    if not all(c in ply for c in ("nx", "ny", "nz")):
        raise ValueError("no nx, ny, nz")
    return np.stack([ply["nx"], ply["ny"], ply["nz"]], axis=1).astype(np.float64)


def align(ref_xyz, est, diag):
    """EST's normals in REF's order, and how the order was found."""
    n = normals(est)
    if not all(c in est for c in ("x", "y", "z")):
        if len(n) != len(ref_xyz):
            raise ValueError(f"{len(n)} normals for {len(ref_xyz)} points and no positions")
        return n, "as written (no positions)"
    xyz = positions(est)
    # 1e-5 of the diagonal, or 2 float ulps of the largest coordinate (float output of a double
    # scene far from the origin)
    tol = max(1e-5 * diag, 2.0 ** -22 * float(np.abs(ref_xyz).max()))
    if len(xyz) == len(ref_xyz):
        shift = np.median(xyz - ref_xyz, axis=0)
        if np.abs(xyz - ref_xyz - shift).max() <= tol:
            return n, "same" if np.abs(shift).max() <= tol else "same (shifted)"
    if cKDTree is not None:
        dist, idx = cKDTree(xyz).query(ref_xyz, k=1)
    else:
        idx = grid_knn(xyz, 1, ref_xyz)[:, 0]
        dist = np.linalg.norm(xyz[idx] - ref_xyz, axis=1)
    matched = np.where((dist <= tol)[:, None], n[idx], 0.0)
    return matched, f"realigned by position ({int((dist > tol).sum())} unmatched)"


def score(ref, ests, kind):
    ref_xyz, ref_n = positions(ref), normals(ref)
    diag = float(np.linalg.norm(ref_xyz.max(axis=0) - ref_xyz.min(axis=0))) or 1.0
    cls = ref["class"].astype(np.int64) if "class" in ref else np.zeros(len(ref_xyz), np.int64)
    known = np.linalg.norm(ref_n, axis=1) > 0
    scored = known & (cls != 5)
    consistent = None
    if kind == "real":
        nbr = knn(ref_xyz, 16)
        dots = np.einsum("ij,ikj->ik", ref_n, ref_n[nbr])
        consistent = scored & np.all(dots > 0, axis=1)
    out = []
    for path in ests:
        try:
            est_n, order = align(ref_xyz, read_ply(path), diag)
        except (OSError, ValueError, KeyError) as e:
            out.append({"file": path, "error": str(e)})
            continue
        length = np.linalg.norm(est_n, axis=1)
        valid = np.isfinite(length) & (length > 1e-6)
        dot = np.where(valid, np.einsum("ij,ij->i", np.nan_to_num(est_n), ref_n), 0.0)
        up = valid & (np.nan_to_num(est_n[:, 2]) > 0)

        def frac(good, where):
            count = int(where.sum())
            return (float((good & where).sum()) / count if count else None), count

        r = {"file": path, "order": order, "invalid": int((~valid & scored).sum())}
        r["agree"], r["scored"] = frac(dot > 0, scored)
        r["walls_out"], r["walls"] = frac(dot > 0, scored & (cls == 2))
        r["ground_up"], r["ground"] = frac(up, scored & (cls == 1))
        r["roof_up"], r["roof"] = frac(up, scored & (cls == 3))
        if consistent is not None:
            r["agree_consistent"], r["consistent"] = frac(dot > 0, consistent)
        out.append(r)
    return out


def list_scenes(scene_dir):
    index = os.path.join(scene_dir, "scenes.json")
    if os.path.exists(index):
        scenes = json.load(open(index))
    else:
        scenes = [{"name": f[:-4], "file": f, "kind": "synthetic", "closed": False}
                  for f in sorted(os.listdir(scene_dir)) if f.endswith(".ply")]
    for s in scenes:
        meta = {k: s.get(k) for k in ("name", "kind", "closed", "points", "source")}
        path = os.path.abspath(os.path.join(scene_dir, s["file"]))
        print(f"{s['name']}\t{path}\t{s.get('kind', 'synthetic')}\t{json.dumps(meta)}")


def score_runs(ref_path, kind, meta, runs_path):
    runs = [json.loads(line) for line in open(runs_path) if line.strip()]
    scored = score(read_ply(ref_path), [r["file"] for r in runs if r["status"] == "ok"], kind)
    scores = iter(scored)
    for run in runs:
        r = {**json.loads(meta), "scene": json.loads(meta)["name"], **run}
        r["time_s"] = float(r["time_s"])
        if run["status"] == "ok":
            r.update(next(scores))
            if "error" in r:
                r["status"], r["reason"] = "failed", "unreadable output: " + r.pop("error")
        r.pop("file", None)
        print(json.dumps(r))


def prepare(scene, out, k):
    ply = read_ply(scene)
    write_ply(out, {c: ply[c] for c in ("x", "y", "z")})
    xyz = positions(ply)
    sample = np.random.default_rng(1).permutation(len(xyz))[:20000]
    idx = knn(xyz, min(k, len(xyz) - 1), sample)
    print(f"{float(np.median(np.linalg.norm(xyz[idx[:, -1]] - xyz[sample], axis=1))):.6g}")


# --- report ---------------------------------------------------------------------------------

TARGETS = "synthetic: agree >= 99 % (closed: >= 99.99 %), ground up 100 %, walls out >= 99 %; " \
          "real: agree on consistent >= 97 % and above every peer (a tie at 100 % counts)"


def pct(v):
    """A fraction in %, cut (not rounded) to 2 decimals: 99.999 % shows as 99.99, not 100.00."""
    return "-" if v is None else f"{math.floor(v * 10000 + 1e-9) / 100:.2f}"


def missed_of(v, count):
    return "" if v is None or v == 1.0 else f" ({round((1 - v) * count)} of {count} not)"


def report(path, json_out, cpu, threads, splatkit):
    rows = [json.loads(line) for line in open(path) if line.strip()]
    scenes, tools = {}, []
    for r in rows:
        scenes.setdefault(r["scene"], {k: r.get(k) for k in ("kind", "closed", "points", "source")})
        scenes[r["scene"]].setdefault("tools", {})[r["tool"]] = r
        if r["tool"] not in tools:
            tools.append(r["tool"])
    for name, s in scenes.items():
        real = s["kind"] == "real"
        print(f"\n{name}: {s['kind']}, {'closed' if s['closed'] else 'open'}, {s['points']} points"
              + (f" ({s['source']})" if s.get("source") else ""))
        head = (f"  {'tool':22} {'agree %':>8} {'walls out %':>11} {'ground up %':>11}"
                f" {'roof up %':>9}")
        head += f" {'consistent %':>12}" if real else ""
        print(head + f" {'time s':>8}")
        for tool in tools:
            r = s["tools"].get(tool)
            if r is None:
                continue
            if r["status"] != "ok":
                why = f" ({r['reason']})" if r.get("reason") else ""
                print(f"  {tool:22} {r['status']}{why}")
                continue
            line = (f"  {tool:22} {pct(r['agree']):>8} {pct(r['walls_out']):>11}"
                    f" {pct(r['ground_up']):>11} {pct(r['roof_up']):>9}")
            line += f" {pct(r.get('agree_consistent')):>12}" if real else ""
            notes = []
            if r.get("invalid"):
                notes.append(f"{r['invalid']} without a normal")
            if r.get("order", "same") not in ("same", "as written (no positions)"):
                notes.append(f"order: {r['order']}")
            wrong = r["scored"] - r["invalid"] - round(r["agree"] * r["scored"])
            if r["agree"] < 0.5 and wrong > 0:
                notes.append(f"{pct(wrong / r['scored'])} % reversed")
            if r.get("note"):
                notes.append(r["note"])
            print(line + f" {r['time_s']:8.3f}" + ("  " + "; ".join(notes) if notes else ""))

    print("\nsummary (mean over the scenes each tool ran on; time: sum)")
    summary = {}
    for tool in tools:
        ok = [s["tools"][tool] for s in scenes.values()
              if tool in s["tools"] and s["tools"][tool]["status"] == "ok"]
        if not ok:
            print(f"  {tool:22} not run")
            summary[tool] = None
            continue
        mean = lambda key: (lambda v: sum(v) / len(v) if v else None)(
            [r[key] for r in ok if r.get(key) is not None])
        summary[tool] = {"scenes": len(ok), "agree": mean("agree"),
                         "agree_consistent": mean("agree_consistent"),
                         "ground_up": mean("ground_up"), "walls_out": mean("walls_out"),
                         "time_s": sum(r["time_s"] for r in ok)}
        m = summary[tool]
        parts = [f"{label} {pct(m[key])} %" for key, label in
                 (("agree", "agree"), ("walls_out", "walls out"), ("ground_up", "ground up"),
                  ("agree_consistent", "agree on consistent (real)")) if m[key] is not None]
        print(f"  {tool:22} {m['scenes']} scene(s): " + ", ".join(parts) +
              f", time {m['time_s']:.3f} s")

    print(f"\ntargets for splatkit ({TARGETS})")
    checks = []
    for name, s in scenes.items():
        ours = s["tools"].get("splatkit")
        if ours is None:
            continue
        if ours["status"] != "ok":
            checks.append((f"{name}: splatkit ran", False))
            continue
        if s["kind"] == "real":
            v = ours.get("agree_consistent")
            checks.append((f"{name}: agree on consistent {pct(v)} % >= 97 %"
                           + missed_of(v, ours["consistent"]),
                           v is not None and v >= 0.97))
            for tool, r in s["tools"].items():
                if tool.startswith("splatkit") or r["status"] != "ok":
                    continue
                p = r.get("agree_consistent")
                checks.append((f"{name}: agree on consistent above {tool} ({pct(p)} %)",
                               v is not None and (p is None or v > p or v == p == 1.0)))
        else:
            goal = 0.9999 if s["closed"] else 0.99
            checks.append((f"{name}: agree {pct(ours['agree'])} % >= {100 * goal:g} %"
                           + missed_of(ours["agree"], ours["scored"]),
                           ours["agree"] is not None and ours["agree"] >= goal))
            if ours["ground"]:
                checks.append((f"{name}: ground up {pct(ours['ground_up'])} % = 100 %"
                               + missed_of(ours["ground_up"], ours["ground"]),
                               ours["ground_up"] == 1.0))
            if ours["walls"]:
                checks.append((f"{name}: walls out {pct(ours['walls_out'])} % >= 99 %"
                               + missed_of(ours["walls_out"], ours["walls"]),
                               ours["walls_out"] >= 0.99))
    for text, ok in checks:
        print(f"  {'ok  ' if ok else 'MISS'} {text}")
    missed = sum(1 for _, ok in checks if not ok)
    print(f"  {len(checks) - missed} ok, {missed} missed")
    if json_out:
        with open(json_out, "w") as f:
            json.dump({"cpu": cpu, "threads": threads, "splatkit": splatkit, "targets": TARGETS,
                       "scenes": scenes,
                       "summary": summary,
                       "checks": [{"check": t, "ok": ok} for t, ok in checks]}, f, indent=1)
    return 3 if missed else 0


def main(argv):
    if argv[:1] == ["--prepare"]:
        prepare(argv[1], argv[2], int(argv[3]) if len(argv) > 3 else 16)
        return 0
    if argv[:1] == ["--scenes"]:
        list_scenes(argv[1])
        return 0
    if argv[:1] == ["--score"]:
        score_runs(*argv[1:5])
        return 0
    if argv[:1] == ["--report"]:
        opts = dict(zip(argv[2::2], argv[3::2]))
        return report(argv[1], opts.get("--json"), opts.get("--cpu", "?"),
                      opts.get("--threads", "?"), opts.get("--splatkit", "?"))
    kind = "synthetic"
    if "--kind" in argv:
        i = argv.index("--kind")
        kind = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    for r in score(read_ply(argv[0]), argv[1:], kind):
        print(json.dumps(r))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
