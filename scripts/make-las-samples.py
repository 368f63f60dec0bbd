#!/usr/bin/env python3
"""Writes the two LAS samples in data-samples/ from text samples, with a writer independent of
splatkit's reader (plain struct packing of the ASPRS LAS 1.2 / 1.4 layouts), so that reading them
back checks the reader against the specification rather than against itself.

  torus-las12.las  LAS 1.2, point format 3 (GPS time + 16-bit RGB), from torus-ascii.ply
  cad-utm-las14.las LAS 1.4, point format 7, from cad-noisy.xyz scaled to metres and moved to
                    UTM-like coordinates (offset 500000 E, 4100000 N, 1200 m), scale 1 mm

Usage: scripts/make-las-samples.py [DATA_SAMPLES_DIR]
"""
import math
import os
import struct
import sys


def read_ascii_ply(path):
    with open(path) as f:
        names = []
        for line in f:
            w = line.split()
            if w[:1] == ["property"]:
                names.append(w[-1])
            if w[:1] == ["end_header"]:
                break
        return [dict(zip(names, map(float, line.split()))) for line in f if line.strip()]


def read_xyz(path):
    with open(path) as f:
        names = f.readline().lstrip("#").split()
        return [dict(zip(names, map(float, line.split()))) for line in f if line.strip()]


def header(version_minor, fmt, rec_len, n, scale, offset, mins, maxs):
    size = 375 if version_minor == 4 else 227
    h = bytearray(size)
    struct.pack_into("<4sHHI2sB", h, 0, b"LASF", 0, 0, 0, b"\0\0", 0)  # signature..GUID start
    struct.pack_into("<BB", h, 24, 1, version_minor)
    struct.pack_into("<32s32s", h, 26, b"splatkit make-las-samples.py", b"splatkit data-samples")
    struct.pack_into("<HH", h, 90, 325, 2026)  # creation day of year, year
    struct.pack_into("<HIIBH", h, 94, size, size, 0, fmt, rec_len)
    legacy = n if fmt < 6 else 0
    struct.pack_into("<I", h, 107, legacy)
    struct.pack_into("<5I", h, 111, legacy, 0, 0, 0, 0)
    struct.pack_into("<3d3d", h, 131, *scale, *offset)
    struct.pack_into("<6d", h, 179, maxs[0], mins[0], maxs[1], mins[1], maxs[2], mins[2])
    if version_minor == 4:
        struct.pack_into("<QQIQ", h, 227, 0, 0, 0, n)  # waveform, EVLR start/count, 64-bit count
    return bytes(h)


def quantise(v, scale, offset):
    return int(round((v - offset) / scale))


def write(path, minor, fmt, points, scale, offset, pack):
    q = [[quantise(p[k], scale[i], offset[i]) for i, k in enumerate("xyz")] for p in points]
    mins = [min(c[i] for c in q) * scale[i] + offset[i] for i in range(3)]
    maxs = [max(c[i] for c in q) * scale[i] + offset[i] for i in range(3)]
    body = b"".join(pack(i, p, c) for i, (p, c) in enumerate(zip(points, q)))
    rec_len = len(body) // len(points)
    with open(path, "wb") as f:
        f.write(header(minor, fmt, rec_len, len(points), scale, offset, mins, maxs))
        f.write(body)


def main():
    d = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "data-samples")
    torus = read_ascii_ply(os.path.join(d, "torus-ascii.ply"))

    def pack3(i, p, c):  # format 3: 20 bytes core + GPS time + RGB = 34 bytes
        rgb = [int((p[k] * 0.5 + 0.5) * 65535) for k in ("nx", "ny", "nz")]
        ret = 0x09  # return 1 of 1
        return struct.pack("<3iHBBbBHd3H", *c, 100 + i % 50, ret, 2, 0, 0, 1, 1000.0 + i * 0.001, *rgb)

    write(os.path.join(d, "torus-las12.las"), 2, 3, torus, (1e-7,) * 3, (0.0,) * 3, pack3)

    cad = read_xyz(os.path.join(d, "cad-noisy.xyz"))
    offset = (500000.0, 4100000.0, 1200.0)
    for p in cad:  # metres, UTM-like
        p["x"], p["y"], p["z"] = p["x"] * 10 + offset[0] + 123.4, p["y"] * 10 + offset[1] + 56.7, p["z"] * 10 + offset[2]

    def pack7(i, p, c):  # format 7: 30 bytes core + GPS time... + RGB = 36 bytes
        cls = 6 if p["patch_id"] in (1, 7) else 2  # roofs and ground, for show
        returns = 0x11  # return 1 of 1 (4 bits each)
        flags = 0x00
        g = 60000 if cls == 2 else 20000
        return struct.pack("<3iHBBBBhHd3H", *c, 200, returns, flags, cls, 0, 0, 7, 2e8 + i, g, g, g)

    write(os.path.join(d, "cad-utm-las14.las"), 4, 7, cad, (0.001,) * 3, offset, pack7)


if __name__ == "__main__":
    main()
