#!/usr/bin/python3
"""Mask IoU and PSNR of level-of-detail renders against the plain render (lod-masks.sh).

usage: mask_iou.py BACKGROUND_R,G,B REFERENCE.png OTHER.png...

The images are splat-view's PNGs (8-bit RGB) rendered over a background colour that the model
never shows (BACKGROUND as 0..255 integers): a pixel is in a render's mask when it differs from
that colour. Prints one line per OTHER: the mask IoU against REFERENCE's mask, the pixels only
REFERENCE covers (lost) and only OTHER covers (grown), the PSNR (dB, 8-bit RGB) over the
pixels both cover, and the regions of at least 20 of those pixels (4-connected) where a channel
differs by more than 40 levels. Reads any 8-bit RGB or RGBA PNG without interlacing (every filter
type).
"""
import collections
import struct
import sys
import zlib

import numpy as np


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"mask_iou.py: {path}: not a PNG")
    pos, idat, header = 8, [], None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        sys.exit(f"mask_iou.py: {path}: only 8-bit RGB or RGBA PNGs without interlacing")
    bpp = 3 if colour == 2 else 4
    raw = np.frombuffer(zlib.decompress(b"".join(idat)), np.uint8).reshape(height, 1 + width * bpp)
    out = np.zeros((height, width * bpp), np.uint8)
    prev = np.zeros(width * bpp, np.int32)
    for y in range(height):
        kind, row = raw[y, 0], raw[y, 1:].astype(np.int32)
        if kind == 0:
            cur = row
        elif kind == 2:
            cur = (row + prev) & 255
        elif kind in (1, 3, 4):  # these depend on the bytes to the left: byte by byte
            cur = np.zeros_like(row)
            for x in range(len(row)):
                a = cur[x - bpp] if x >= bpp else 0
                b, c = prev[x], (prev[x - bpp] if x >= bpp else 0)
                if kind == 1:
                    p = a
                elif kind == 3:
                    p = (a + b) // 2
                else:
                    pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                    p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (row[x] + p) & 255
        else:
            sys.exit(f"mask_iou.py: {path}: bad filter type {kind} in row {y}")
        out[y] = cur
        prev = cur
    return out.reshape(height, width, bpp)[:, :, :3]


def large_regions(bad, least=20):
    """The 4-connected regions of at least `least` pixels in the boolean image `bad`."""
    height, width = bad.shape
    seen = np.zeros_like(bad)
    count = 0
    for y0, x0 in zip(*np.nonzero(bad)):
        if seen[y0, x0]:
            continue
        seen[y0, x0] = True
        queue, size = collections.deque([(y0, x0)]), 0
        while queue:
            y, x = queue.popleft()
            size += 1
            for yy, xx in ((y + 1, x), (y - 1, x), (y, x + 1), (y, x - 1)):
                if 0 <= yy < height and 0 <= xx < width and bad[yy, xx] and not seen[yy, xx]:
                    seen[yy, xx] = True
                    queue.append((yy, xx))
        count += size >= least
    return count


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    background = np.array([int(v) for v in sys.argv[1].split(",")], np.uint8)
    ref = read_png(sys.argv[2])
    ref_mask = np.any(ref != background, axis=2)
    for path in sys.argv[3:]:
        img = read_png(path)
        if img.shape != ref.shape:
            sys.exit(f"mask_iou.py: {path}: size differs from {sys.argv[2]}")
        mask = np.any(img != background, axis=2)
        union = np.count_nonzero(ref_mask | mask)
        both = ref_mask & mask
        iou = np.count_nonzero(both) / union if union else 1.0
        diff = ref[both].astype(np.float64) - img[both].astype(np.float64)
        mse = np.mean(diff * diff) if diff.size else 0.0
        psnr = 10 * np.log10(255.0 ** 2 / mse) if mse > 0 else 99.0
        lost = np.count_nonzero(ref_mask & ~mask)
        grown = np.count_nonzero(mask & ~ref_mask)
        levels = np.abs(ref.astype(np.int16) - img.astype(np.int16)).max(axis=2)
        regions = large_regions(both & (levels > 40))
        print(f"{path}: iou {iou:.4f} lost {lost} grown {grown} ref {np.count_nonzero(ref_mask)} "
              f"psnr {psnr:.2f} regions {regions}")


main()
