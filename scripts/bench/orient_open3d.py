#!/usr/bin/python3
"""Open3D's normal pipeline, a peer of estimate-normals' orientation (orientation.sh).

usage: /usr/bin/python3 orient_open3d.py SCENE.ply OUT.ply [K]
  Reads SCENE's x, y, z only (Open3D's own reader would take the scene's reference normals, and
  estimate_normals orients towards normals already there), then
  PointCloud.estimate_normals(KDTreeSearchParamKNN(K)) and
  PointCloud.orient_normals_consistent_tangent_plane(K), K = 16; writes nx, ny, nz (binary PLY)
  in the input's order and prints one JSON line: points, estimate_s, orient_s (the calls alone).
  Threads: OpenMP's (OMP_NUM_THREADS). Debian's python3-open3d: run it with /usr/bin/python3.
"""
import json
import os
import sys
import time

import numpy as np
import open3d as o3d

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from score_orientation import positions, read_ply, write_ply  # noqa: E402


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    k = int(argv[2]) if len(argv) > 2 else 16
    o3d.utility.set_verbosity_level(o3d.utility.VerbosityLevel.Error)
    cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(positions(read_ply(argv[0]))))
    t0 = time.perf_counter()
    cloud.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(k))
    t1 = time.perf_counter()
    cloud.orient_normals_consistent_tangent_plane(k)
    t2 = time.perf_counter()
    n = np.asarray(cloud.normals, dtype=np.float32)
    write_ply(argv[1], {"nx": n[:, 0], "ny": n[:, 1], "nz": n[:, 2]})
    print(json.dumps({"points": len(n), "estimate_s": round(t1 - t0, 4),
                      "orient_s": round(t2 - t1, 4)}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
