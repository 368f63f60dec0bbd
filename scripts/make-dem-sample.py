#!/usr/bin/env python3
"""Crops a GeoTIFF elevation model (uncompressed int16, tiled or stripped, one band: the SRTM
tiles under ../shared/data/dem) to a small uncompressed stripped GeoTIFF, keeping the no-data tag
(GDAL_NODATA) and the georeferencing (ModelPixelScale, ModelTiepoint moved to the crop's corner,
GeoKeyDirectory). Standard library only.

usage: make-dem-sample.py IN.tif OUT.tif X0 Y0 WIDTH HEIGHT
"""
import struct
import sys

TYPES = {1: 'B', 2: 's', 3: 'H', 4: 'I', 12: 'd', 16: 'Q'}
SIZES = {1: 1, 2: 1, 3: 2, 4: 4, 12: 8, 16: 8}


def read_tags(data):
    order = '<' if data[:2] == b'II' else '>'
    assert struct.unpack(order + 'H', data[2:4])[0] == 42, 'classic TIFF only'
    ifd = struct.unpack(order + 'I', data[4:8])[0]
    n = struct.unpack(order + 'H', data[ifd:ifd + 2])[0]
    tags = {}
    for i in range(n):
        tag, typ, count, value = struct.unpack(order + 'HHI4s', data[ifd + 2 + 12 * i: ifd + 14 + 12 * i])
        size = SIZES[typ] * count
        raw = value[:size] if size <= 4 else data[struct.unpack(order + 'I', value)[0]:][:size]
        if typ == 2:
            tags[tag] = (typ, raw)
        else:
            tags[tag] = (typ, list(struct.unpack(order + TYPES[typ] * count, raw)))
    return order, tags


def sample_reader(data, order, tags):
    width, height = tags[256][1][0], tags[257][1][0]
    assert tags[258][1][0] == 16 and tags.get(259, (0, [1]))[1][0] == 1, 'uncompressed 16-bit only'
    if 322 in tags:
        tw, th = tags[322][1][0], tags[323][1][0]
        offsets = tags[324][1]
        across = (width + tw - 1) // tw

        def at(x, y):
            t = (y // th) * across + x // tw
            o = offsets[t] + 2 * ((y % th) * tw + x % tw)
            return struct.unpack(order + 'h', data[o:o + 2])[0]
    else:
        rps = tags.get(278, (0, [height]))[1][0]
        offsets = tags[273][1]

        def at(x, y):
            o = offsets[y // rps] + 2 * ((y % rps) * width + x)
            return struct.unpack(order + 'h', data[o:o + 2])[0]
    return width, height, at


def main():
    src, dst = sys.argv[1], sys.argv[2]
    x0, y0, w, h = map(int, sys.argv[3:7])
    data = open(src, 'rb').read()
    order, tags = read_tags(data)
    width, height, at = sample_reader(data, order, tags)
    assert x0 + w <= width and y0 + h <= height
    pixels = b''.join(struct.pack('<%dh' % w, *[at(x, y) for x in range(x0, x0 + w)])
                      for y in range(y0, y0 + h))
    scale = tags[33550][1]
    tie = list(tags[33922][1])
    tie[3] += x0 * scale[0]
    tie[4] -= y0 * scale[1]
    out = [(256, 3, [w]), (257, 3, [h]), (258, 3, [16]), (259, 3, [1]), (262, 3, [1]),
           (273, 4, [0]), (277, 3, [1]), (278, 3, [h]), (279, 4, [len(pixels)]), (284, 3, [1]),
           (339, 3, [2]), (33550, 12, scale), (33922, 12, tie), (34735, 3, tags[34735][1])]
    if 34736 in tags:
        out.append((34736, 12, tags[34736][1]))
    if 34737 in tags:
        out.append((34737, 2, tags[34737][1]))
    out.append((42113, 2, tags[42113][1]))
    # Layout: header, pixels, then the values that do not fit in 4 bytes, then the directory.
    blob = bytearray(b'II' + struct.pack('<HI', 42, 0))
    pixel_offset = len(blob)
    blob += pixels
    entries = []
    for tag, typ, values in out:
        raw = values if typ == 2 else struct.pack('<' + TYPES[typ] * len(values), *values)
        count = len(raw) if typ == 2 else len(values)
        if tag == 273:
            raw = struct.pack('<I', pixel_offset)
        if len(raw) <= 4:
            entries.append(struct.pack('<HHI', tag, typ, count) + raw.ljust(4, b'\0'))
        else:
            if len(blob) % 2:
                blob += b'\0'
            entries.append(struct.pack('<HHII', tag, typ, count, len(blob)))
            blob += raw
    if len(blob) % 2:
        blob += b'\0'
    ifd = len(blob)
    blob += struct.pack('<H', len(entries)) + b''.join(entries) + struct.pack('<I', 0)
    blob[4:8] = struct.pack('<I', ifd)
    open(dst, 'wb').write(bytes(blob))


if __name__ == '__main__':
    main()
