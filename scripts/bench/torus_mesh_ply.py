#!/usr/bin/env python3
"""Writes a closed torus triangle mesh, an N x M grid of vertices (2 N M triangles), as binary
big-endian PLY with only x, y, z per vertex and `list uchar int vertex_indices` per face: the
form the original QSplat 1.0 qsplat_make reads (it reads no other), for scripts/bench/qsplat.sh.
usage: torus_mesh_ply.py OUT.ply [N=2000] [M=2000]"""
import math
import struct
import sys
from array import array


def main():
    out = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 2000  # around the axis
    m = int(sys.argv[3]) if len(sys.argv) > 3 else 2000  # around the tube
    major, minor = 1.0, 0.35
    header = (f"ply\nformat binary_big_endian 1.0\ncomment torus {n}x{m}\n"
              f"element vertex {n * m}\nproperty float x\nproperty float y\nproperty float z\n"
              f"element face {2 * n * m}\nproperty list uchar int vertex_indices\nend_header\n")
    tube = [(math.cos(2 * math.pi * j / m), math.sin(2 * math.pi * j / m)) for j in range(m)]
    swap = sys.byteorder == "little"
    row_faces = struct.Struct(">" + "B3i" * (2 * m))
    with open(out, "wb") as f:
        f.write(header.encode("ascii"))
        for i in range(n):  # vertex (i, j) is number i * m + j
            cu, su = math.cos(2 * math.pi * i / n), math.sin(2 * math.pi * i / n)
            row = array("f")
            for cv, sv in tube:
                w = major + minor * cv
                row.extend((w * cu, w * su, minor * sv))
            if swap:
                row.byteswap()
            f.write(row.tobytes())
        for i in range(n):  # two triangles per grid cell, wrapping around both ways
            a0, b0 = i * m, (i + 1) % n * m
            values = []
            for j in range(m):
                j1 = (j + 1) % m
                values += (3, a0 + j, b0 + j, b0 + j1, 3, a0 + j, b0 + j1, a0 + j1)
            f.write(row_faces.pack(*values))


if __name__ == "__main__":
    main()
