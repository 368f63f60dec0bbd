#!/usr/bin/env python3
"""A single-band int16 GeoTIFF heightmap (uncompressed, stripped, little-endian, geographic
degrees) as an XYZ point cloud in metres, one point per valid texel: a real terrain surface
sampled on a grid, as an airborne scan would see it. usage: dem_to_xyz.py IN.tif OUT.xyz"""
import math
import struct
import sys


def main(src, dst):
    data = open(src, "rb").read()
    if data[:4] != b"II*\x00":
        sys.exit("dem_to_xyz: only little-endian classic TIFF")
    (ifd,) = struct.unpack_from("<I", data, 4)
    (count,) = struct.unpack_from("<H", data, ifd)
    sizes = {1: 1, 2: 1, 3: 2, 4: 4, 12: 8, 16: 8}
    fmt = {1: "B", 2: "c", 3: "H", 4: "I", 12: "d", 16: "Q"}
    tags = {}
    for i in range(count):
        tag, typ, n, value = struct.unpack_from("<HHII", data, ifd + 2 + 12 * i)
        size = sizes.get(typ, 1) * n
        off = ifd + 2 + 12 * i + 8 if size <= 4 else value
        if typ in fmt and typ != 2:
            tags[tag] = struct.unpack_from("<%d%s" % (n, fmt[typ]), data, off)
        else:
            tags[tag] = data[off:off + size]
    w, h = tags[256][0], tags[257][0]
    if tags[258][0] != 16 or tags.get(259, (1,))[0] != 1:
        sys.exit("dem_to_xyz: only uncompressed 16-bit samples")
    nodata = int(tags[42113].rstrip(b"\x00")) if 42113 in tags else None
    sx, sy = tags[33550][0], tags[33550][1]
    lat = tags[33922][4]
    mx = sx * 111320.0 * math.cos(math.radians(lat - sy * h / 2))
    my = sy * 110540.0
    rows = bytearray()
    for off, n in zip(tags[273], tags[279]):
        rows += data[off:off + n]
    values = struct.unpack("<%dh" % (w * h), bytes(rows[: 2 * w * h]))
    with open(dst, "w") as out:
        for y in range(h):
            for x in range(w):
                v = values[y * w + x]
                if v != nodata:
                    out.write("%.2f %.2f %d\n" % (x * mx, -y * my, v))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
