#!/usr/bin/env python3
"""Writes the scan test set: scenes with known reference normals, for normal-orientation tests.
Run by scripts/make-scan-set.sh (which finds splat-synth and fetches the real scans); python3 +
numpy only. Deterministic: fixed seeds, the same bytes on every run.

Contract of every OUT_DIR/NAME.ply (binary_little_endian, one `vertex` element, in this order):
  float x y z          (double for city-utm)
  float nx ny nz       reference normal: unit, pointing out of the solid material (towards the
                       side the surface is seen from); (0, 0, 0) where unknown (class 5)
  uchar class          0 object surface, 1 ground/terrain, 2 wall, 3 roof,
                       4 slab/balcony/ceiling/other horizontal non-roof, 5 vegetation/clutter
  int segment          one id per planar face / smooth patch (ground included); -1 for class 5
No two points share their coordinates. OUT_DIR/scenes.json lists the scenes: name, file, kind
(synthetic | real), closed, points, source, and spacing (the nominal point spacing
sqrt(area / points) in metres; in plan view for the terrain; measured for the real scans).

Sampling, on every synthetic surface patch in its own isometric (a, b) parameter plane (the
terrain: in plan): stratified = one point per h x h cell, jittered over the cell's central half;
scan = parallel lines 2h apart at 25 degrees to the patch's first axis, points h/2 apart along
them (jittered by a quarter of that): the same density as stratified. -noisy: Gaussian offset
along the reference normal, sigma = 0.3 h. Vegetation is not scanned or noised.

Usage: make_scan_scenes.py OUT_DIR [--scale S] [--splat-synth BINARY]
                            [--cgal-dir DIR [--cgal-package "libcgal-demo VERSION"]]
"""
import argparse
import itertools
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

WALL, ROOF, SLAB, GROUND, OBJECT, VEGETATION = 2, 3, 4, 1, 0, 5
Z = np.array([0.0, 0.0, 1.0])
SCAN_ANGLE = math.radians(25)
SLAB_T = 0.3  # thickness of floor slabs and balconies, m
NOISE = 0.3  # sigma of the -noisy variants, in units of the spacing h
UTM_OFFSET = np.array([500000.0, 4100000.0, 300.0])


# ----------------------------------------------------------------------------------------------
# Regions in a patch's (a, b) plane: a convex polygon (counter-clockwise) or a disc, minus holes.

class Polygon:
    def __init__(self, vertices):
        v = np.asarray(vertices, dtype=float)
        a, b = v[:, 0], v[:, 1]
        signed = 0.5 * np.sum(a * np.roll(b, -1) - np.roll(a, -1) * b)
        self.v = v if signed > 0 else v[::-1]
        self.area = abs(signed)
        self.bbox = (a.min(), a.max(), b.min(), b.max())

    def contains(self, a, b):
        inside = np.ones(a.shape, dtype=bool)
        for p, q in zip(self.v, np.roll(self.v, -1, axis=0)):
            inside &= (q[0] - p[0]) * (b - p[1]) - (q[1] - p[1]) * (a - p[0]) >= 0
        return inside


class Disc:
    def __init__(self, centre, radius):
        self.c, self.r = np.asarray(centre, dtype=float), radius
        self.area = math.pi * radius * radius
        self.bbox = (self.c[0] - radius, self.c[0] + radius, self.c[1] - radius, self.c[1] + radius)

    def contains(self, a, b):
        return (a - self.c[0]) ** 2 + (b - self.c[1]) ** 2 <= self.r ** 2


def rect(a0, a1, b0, b1):
    return Polygon([(a0, b0), (a1, b0), (a1, b1), (a0, b1)])


class Region:
    """outer minus holes; the holes lie inside outer and do not overlap."""

    def __init__(self, outer, holes=()):
        self.outer, self.holes = outer, list(holes)
        self.area = outer.area - sum(h.area for h in self.holes)
        self.bbox = outer.bbox

    def contains(self, a, b):
        inside = self.outer.contains(a, b)
        for h in self.holes:
            inside &= ~h.contains(a, b)
        return inside


# ----------------------------------------------------------------------------------------------
# Patches: a region, a map (a, b) -> points and normals, a class and a segment id.

class Patch:
    def __init__(self, region, embed, cls, segment):
        self.region, self.embed, self.cls, self.segment = region, embed, cls, segment


def plane(origin, e1, normal, region, cls, segment):
    """p = origin + a e1 + b e2 with e2 = normal x e1 (so e1 x e2 = normal)."""
    o, e1, n = (np.asarray(v, dtype=float) for v in (origin, e1, normal))
    e1, n = e1 / np.linalg.norm(e1), n / np.linalg.norm(n)
    e2 = np.cross(n, e1)

    def embed(a, b):
        return o + a[:, None] * e1 + b[:, None] * e2, np.broadcast_to(n, (len(a), 3))
    return Patch(region, embed, cls, segment)


def cylinder(centre_xy, radius, z0, z1, outward, cls, segment):
    """Vertical cylinder side, (a, b) = (arc length, z); normals radial, out or towards the axis."""
    cx, cy = centre_xy
    sign = 1.0 if outward else -1.0

    def embed(a, b):
        t = a / radius
        radial = np.stack([np.cos(t), np.sin(t), np.zeros_like(t)], axis=1)
        return np.stack([cx + radius * radial[:, 0], cy + radius * radial[:, 1], b], axis=1), \
            sign * radial
    return Patch(Region(rect(0, 2 * math.pi * radius, z0, z1)), embed, cls, segment)


def heightfield(height, region, cls, segment):
    """z = height(x, y) over (a, b) = (x, y); height returns z and its two partial derivatives."""
    def embed(a, b):
        z, zx, zy = height(a, b)
        n = np.stack([-zx, -zy, np.ones_like(z)], axis=1)
        return np.stack([a, b, z], axis=1), n / np.linalg.norm(n, axis=1, keepdims=True)
    return Patch(region, embed, cls, segment)


def vertical_face(p0, p1, z0, z1, cls, segment, holes=()):
    """The vertical rectangle over the segment p0 -> p1 (plan view); its normal points to the right
    of the direction of travel, so a counter-clockwise footprint gets outward faces."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    length = np.linalg.norm(p1 - p0)
    e1 = np.append((p1 - p0) / length, 0.0)
    return plane(np.append(p0, 0.0), e1, np.cross(e1, Z),
                 Region(rect(0, length, z0, z1), holes), cls, segment)


def horizontal_face(polygon_xy, z, up, cls, segment, holes_xy=()):
    """A horizontal face over a plan-view polygon (holes: polygons), normal up or down."""
    if up:
        return plane((0, 0, z), (1, 0, 0), Z, Region(Polygon(polygon_xy),
                                                     [Polygon(h) for h in holes_xy]), cls, segment)
    # Facing down, e2 = -y: the region is mirrored to (x, -y).
    flip = np.array([1.0, -1.0])
    return plane((0, 0, z), (1, 0, 0), -Z,
                 Region(Polygon(np.asarray(polygon_xy) * flip),
                        [Polygon(np.asarray(h) * flip) for h in holes_xy]), cls, segment)


# ----------------------------------------------------------------------------------------------
# Sampling

def total_area(patches):
    return sum(p.region.area for p in patches)


def stratified_params(region, h, rng):
    a0, a1, b0, b1 = region.bbox
    na, nb = max(1, round((a1 - a0) / h)), max(1, round((b1 - b0) / h))
    ca, cb = (a1 - a0) / na, (b1 - b0) / nb
    i, j = np.meshgrid(np.arange(na), np.arange(nb), indexing="ij")
    a = a0 + (i.ravel() + 0.5 + rng.uniform(-0.25, 0.25, i.size)) * ca
    b = b0 + (j.ravel() + 0.5 + rng.uniform(-0.25, 0.25, j.size)) * cb
    keep = region.contains(a, b)
    return a[keep], b[keep]


def scan_params(region, h, rng):
    """Lines 2h apart along direction (cos, sin) of SCAN_ANGLE, points h/2 apart along them."""
    spacing, step = 2 * h, h / 2
    t = np.array([math.cos(SCAN_ANGLE), math.sin(SCAN_ANGLE)])
    w = np.array([-t[1], t[0]])
    a0, a1, b0, b1 = region.bbox
    corners = np.array([(a0, b0), (a1, b0), (a1, b1), (a0, b1)])
    across, along = corners @ w, corners @ t
    lines = across.min() + rng.uniform(0, spacing) + spacing * np.arange(
        math.ceil((across.max() - across.min()) / spacing) + 1)
    n_along = math.ceil((along.max() - along.min()) / step) + 1
    s = along.min() + step * (np.arange(n_along)[None, :] + rng.uniform(0, 1, (len(lines), 1))
                              + rng.uniform(-0.25, 0.25, (len(lines), n_along)))
    c = np.broadcast_to(lines[:, None], s.shape)
    a, b = (c * w[0] + s * t[0]).ravel(), (c * w[1] + s * t[1]).ravel()
    keep = region.contains(a, b)
    return a[keep], b[keep]


def cloud(points, normals, cls, segment):
    n = len(points)
    return {"xyz": np.asarray(points, dtype=float).reshape(n, 3),
            "normal": np.asarray(normals, dtype=float).reshape(n, 3),
            "class": np.full(n, cls, dtype=np.uint8) if np.isscalar(cls) else cls.astype(np.uint8),
            "segment": np.full(n, segment, dtype=np.int32) if np.isscalar(segment)
            else segment.astype(np.int32)}


def concat(clouds):
    return {k: np.concatenate([c[k] for c in clouds]) for k in clouds[0]}


def sample(patches, h, scan, rng):
    params = scan_params if scan else stratified_params
    parts = []
    for p in patches:
        a, b = params(p.region, h, rng)
        xyz, n = p.embed(a, b)
        parts.append(cloud(xyz, n, p.cls, p.segment))
    return concat(parts)


def add_noise(c, sigma, rng):
    out = dict(c)
    out["xyz"] = c["xyz"] + c["normal"] * (sigma * rng.standard_normal(len(c["xyz"])))[:, None]
    return out


def to_world(xyz, angle, offset):
    """Turns points about z by angle, then moves them by offset (x, y)."""
    co, si = math.cos(angle), math.sin(angle)
    return xyz @ np.array([[co, si, 0], [-si, co, 0], [0, 0, 1]]) + np.array(
        [offset[0], offset[1], 0.0])


def transform(patch_list, angle, offset):
    """Patches turned about z by angle and moved by offset (x, y)."""
    def moved(embed):
        def f(a, b):
            xyz, n = embed(a, b)
            return to_world(xyz, angle, offset), to_world(n, angle, (0, 0))
        return f
    return [Patch(p.region, moved(p.embed), p.cls, p.segment) for p in patch_list]


# ----------------------------------------------------------------------------------------------
# Scenes

def building_with_rooms(length, width, floors, wall, balconies, ids):
    """A closed building in its own frame (corner at the origin, footprint [0, L] x [0, W]):
    thick walls sampled on both faces, a 0.3 m ground-floor slab (top face only: it lies on the
    ground), 0.3 m floor slabs between storeys (top and bottom), a 0.3 m flat roof (top = roof,
    underside = ceiling). Storeys are 3 m; balconies are (storey, x0) pairs: 3 m wide, 1.4 m deep
    0.3 m slabs on the y = 0 facade, level with that storey's floor slab."""
    L, W, t = length, width, wall
    height = 3.0 * floors + 0.3
    outer = [(0, 0), (L, 0), (L, W), (0, W)]
    inner_cw = [(t, t), (t, W - t), (L - t, W - t), (L - t, t)]
    inner_ccw = inner_cw[::-1]
    bw, depth = 3.0, 1.4
    patches = []
    front_holes = [rect(x0, x0 + bw, 3.0 * k, 3.0 * k + SLAB_T) for k, x0 in balconies]
    for i in range(4):
        patches.append(vertical_face(outer[i], outer[(i + 1) % 4], 0, height, WALL, ids(),
                                     front_holes if i == 0 else ()))
    for k in range(floors):
        floor_top = 3.0 * k + SLAB_T
        for i in range(4):
            patches.append(vertical_face(inner_cw[i], inner_cw[(i + 1) % 4], floor_top,
                                         3.0 * (k + 1), WALL, ids()))
        patches.append(horizontal_face(inner_ccw, floor_top, True, SLAB, ids()))
        patches.append(horizontal_face(inner_ccw, 3.0 * (k + 1), False, SLAB, ids()))
    patches.append(horizontal_face(outer, height, True, ROOF, ids()))
    for k, x0 in balconies:
        foot = [(x0, -depth), (x0 + bw, -depth), (x0 + bw, 0), (x0, 0)]
        z0 = 3.0 * k
        patches.append(horizontal_face(foot, z0 + SLAB_T, True, SLAB, ids()))
        patches.append(horizontal_face(foot, z0, False, SLAB, ids()))
        for i in (0, 1, 3):  # edge 2 is against the facade
            patches.append(vertical_face(foot[i], foot[(i + 1) % 4], z0, z0 + SLAB_T, SLAB, ids()))
    return patches, outer


def footprint_world(outer, angle, offset):
    plan = np.array([(x, y, 0.0) for x, y in outer])
    return to_world(plan, angle, offset)[:, :2]


def city_patches():
    """6 buildings on a 3 x 2 grid of 24 x 22 m blocks (streets between), two of them turned;
    the ground (z = 0, segment 0) has holes under the footprints. Walls and slabs are 0.3-0.4 m
    thick and the points about 0.12 m apart: each side of a wall is a surface of its own, as a
    scan that saw both sides would sample it."""
    rng = np.random.default_rng(20240611)
    ids = itertools.count().__next__
    ground_id = ids()
    patches, footprints = [], []
    for row in range(2):
        for col in range(3):
            length, width = rng.uniform(9, 14), rng.uniform(8, 11)
            floors, wall = int(rng.integers(2, 4)), rng.uniform(0.3, 0.4)
            angle = math.radians(rng.uniform(15, 35)) if (row * 3 + col) % 3 == 1 else 0.0
            balconies = []
            if (row * 3 + col) % 2 == 0:
                for k in range(1, floors):
                    x0 = rng.uniform(0.8, length - 3.8)
                    balconies.append((k, x0))
            centre = np.array([24.0 * col, 22.0 * row]) + rng.uniform(-2, 2, 2)
            # The footprint's centre goes to `centre` after the turn.
            offset = centre - to_world(np.array([length / 2, width / 2, 0]), angle, (0, 0))[:2]
            local, outer = building_with_rooms(length, width, floors, wall, balconies, ids)
            patches += transform(local, angle, offset)
            footprints.append(footprint_world(outer, angle, offset))
    ground = horizontal_face([(-16, -15), (64, -15), (64, 37), (-16, 37)], 0.0, True, GROUND,
                             ground_id, footprints)
    return [ground] + patches


def terrain_height(x, y):
    """Hills, a winding valley and a steep slope (up to 68 degrees) over [-250, 250]^2 m; returns
    z, dz/dx, dz/dy."""
    z, zx, zy = np.zeros_like(x), np.zeros_like(x), np.zeros_like(x)
    for cx, cy, amp, s in [(-140, 120, 45, 70), (90, 150, 30, 55), (150, -60, 38, 80),
                           (-60, -150, 25, 60), (20, 40, 18, 45), (-180, -40, 22, 50)]:
        g = amp * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2 * s * s))
        z += g
        zx += -g * (x - cx) / (s * s)
        zy += -g * (y - cy) / (s * s)
    # Valley: a Gaussian trough along y = 50 sin(x / 70) - 20, 18 m deep, 40 m wide.
    centre = 50 * np.sin(x / 70) - 20
    d = y - centre
    g = -18 * np.exp(-(d / 40) ** 2)
    z += g
    zx += g * (-2 * d / 1600) * (-50 / 70 * np.cos(x / 70))
    zy += g * (-2 * d / 1600)
    # Steep slope: a 20 m tanh step across the line 0.8 x + 0.6 y = 140, 4 m wide.
    u = (0.8 * x + 0.6 * y - 140) / 4
    z += 10 * (1 + np.tanh(u))
    slope = 10 / np.cosh(u) ** 2 / 4
    zx += slope * 0.8
    zy += slope * 0.6
    # Small undulations.
    z += 1.5 * np.sin(x / 17) * np.cos(y / 23)
    zx += 1.5 / 17 * np.cos(x / 17) * np.cos(y / 23)
    zy += -1.5 / 23 * np.sin(x / 17) * np.sin(y / 23)
    return z, zx, zy


def terrain_patches():
    return [heightfield(terrain_height, Region(rect(-250, 250, -250, 250)), GROUND, 0)]


FACADE = {"length": 36.0, "width": 12.0, "eaves": 10.0, "ridge": 15.0, "angle": math.radians(12),
          "offset": (-18.0, -6.0)}


def facade_patches():
    """A closed box building 36 x 12 m with a gable roof (eaves 10 m, ridge 15 m along its
    length; walls one-sided) on a 60 x 40 m ground, all turned by 12 degrees."""
    L, W, He, Hr = (FACADE[k] for k in ("length", "width", "eaves", "ridge"))
    ids = itertools.count().__next__
    outer = [(0, 0), (L, 0), (L, W), (0, W)]
    local = [horizontal_face([(-12, -14), (48, -14), (48, 26), (-12, 26)], 0.0, True, GROUND,
                             ids(), [outer])]
    for i in range(4):
        face = vertical_face(outer[i], outer[(i + 1) % 4], 0, He, WALL, ids())
        if i % 2 == 1:  # gable ends: the wall runs up to the ridge
            face.region = Region(Polygon([(0, 0), (W, 0), (W, He), (W / 2, Hr), (0, He)]))
        local.append(face)
    slope = math.hypot(W / 2, Hr - He)
    for origin, e1, up in [((0, 0, He), (1, 0, 0), (0, W / 2, Hr - He)),
                           ((L, W, He), (-1, 0, 0), (0, -W / 2, Hr - He))]:
        e1, up = np.array(e1, dtype=float), np.array(up) / slope
        local.append(plane(origin, e1, np.cross(e1, up), Region(rect(0, L, 0, slope)), ROOF,
                           ids()))
    return transform(local, FACADE["angle"], FACADE["offset"])


def inside_facade_building(local):
    L, W, He, Hr = (FACADE[k] for k in ("length", "width", "eaves", "ridge"))
    lx, ly, z = local[:, 0], local[:, 1], local[:, 2]
    roof = He + (Hr - He) * (1 - np.abs(ly - W / 2) / (W / 2))
    return (lx > 0) & (lx < L) & (ly > 0) & (ly < W) & (z < roof)


def facade_vegetation(h):
    """Trees (trunk + crown) and shrubs as uniform random points in ellipsoids, 20-100x sparser
    than the surfaces (points = ellipsoid surface area / h^2 / ratio); some touch the facade
    (their points inside the building are dropped); plus a few stray single points."""
    rng = np.random.default_rng(77)
    W = FACADE["width"]
    # (centre in the building frame, radii, tree): trees have a trunk below the crown.
    blobs = [((6.0, -3.2, 7.0), (3.5, 3.5, 3.0), True),    # tree touching the front facade
             ((28.0, -9.0, 6.5), (3.0, 3.0, 2.8), True),
             ((-6.0, 19.0, 8.0), (4.0, 4.0, 3.5), True),
             ((42.0, 18.0, 5.5), (2.5, 2.5, 2.5), True),
             ((15.0, -0.9, 0.9), (1.2, 1.0, 0.9), False),  # shrubs against the facade
             ((22.0, W + 0.7, 0.7), (1.0, 0.8, 0.7), False),
             ((-6.0, 4.0, 0.6), (0.8, 0.8, 0.6), False),
             ((40.0, -6.0, 0.8), (1.1, 1.1, 0.8), False)]
    parts = []
    for centre, radii, tree in blobs:
        r = np.array(radii)
        p = 1.6  # Knud Thomsen's approximation of the ellipsoid surface area
        area = 4 * math.pi * (((r[0] * r[1]) ** p + (r[0] * r[2]) ** p + (r[1] * r[2]) ** p) / 3) \
            ** (1 / p)
        n = max(3, round(area / (h * h) / rng.uniform(20, 100)))
        u = rng.standard_normal((n, 3))
        u *= (rng.uniform(0, 1, n) ** (1 / 3) / np.linalg.norm(u, axis=1))[:, None]
        parts.append(np.array(centre) + u * r)
        if tree:
            trunk_top = centre[2] - r[2] * 0.8
            m = max(3, round(2 * math.pi * 0.2 * trunk_top / (h * h) / rng.uniform(20, 100)))
            t = rng.uniform(0, 2 * math.pi, m)
            parts.append(np.stack([centre[0] + 0.2 * np.cos(t), centre[1] + 0.2 * np.sin(t),
                                   rng.uniform(0, trunk_top, m)], axis=1))
    parts.append(np.stack([rng.uniform(-10, 46, 6), rng.uniform(-12, 24, 6),
                           rng.uniform(1, 20, 6)], axis=1))
    local = np.concatenate(parts)
    local = local[(local[:, 2] > 0.05) & ~inside_facade_building(local)]
    xyz = to_world(local, FACADE["angle"], FACADE["offset"])
    return cloud(xyz, np.zeros_like(xyz), VEGETATION, -1)


def cad_patches():
    """splat-synth's CAD-like part (lib/splatkit/synthetic_shapes.cpp, data-samples/README.md),
    patch ids 0-8 as there: a prism along y (|y| <= 1) with profile (-1.5, 0), (1.5, 0),
    (top_end, 1.2), (-1.5, 1.2), a boss (r 0.4, up to z 1.7) and a through hole (r 0.25)."""
    half_w, half_d, height = 1.5, 1.0, 1.2
    top_end = half_w - height / math.sqrt(3)
    boss, boss_r, boss_top, hole, hole_r = (-0.7, 0.0), 0.4, 1.7, (0.2, 0.0), 0.25
    bevel_n = np.array([math.sin(math.pi / 3), 0, math.cos(math.pi / 3)])
    profile = [(-half_w, 0), (half_w, 0), (top_end, height), (-half_w, height)]
    return [
        plane((0, 0, 0), (1, 0, 0), -Z,
              Region(rect(-half_w, half_w, -half_d, half_d), [Disc(hole, hole_r)]), OBJECT, 0),
        plane((0, 0, height), (1, 0, 0), Z,
              Region(rect(-half_w, top_end, -half_d, half_d),
                     [Disc(boss, boss_r), Disc(hole, hole_r)]), OBJECT, 1),
        plane((-half_w, half_d, 0), (0, -1, 0), (-1, 0, 0),
              Region(rect(0, 2 * half_d, 0, height)), OBJECT, 2),
        plane((half_w, -half_d, 0), (0, 1, 0), bevel_n,
              Region(rect(0, 2 * half_d, 0, height / math.sin(math.pi / 3))), OBJECT, 3),
        plane((0, -half_d, 0), (1, 0, 0), (0, -1, 0), Region(Polygon(profile)), OBJECT, 4),
        plane((0, half_d, 0), (-1, 0, 0), (0, 1, 0),
              Region(Polygon([(-x, z) for x, z in profile])), OBJECT, 5),
        cylinder(boss, boss_r, height, boss_top, True, OBJECT, 6),
        plane((0, 0, boss_top), (1, 0, 0), Z, Region(Disc(boss, boss_r)), OBJECT, 7),
        cylinder(hole, hole_r, 0, height, False, OBJECT, 8),
    ]


# ----------------------------------------------------------------------------------------------
# PLY in and out

PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4",
             "uint": "u4", "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1",
             "int16": "i2", "uint16": "u2", "int32": "i4", "uint32": "u4", "float32": "f4",
             "float64": "f8"}


def read_ply(path):
    """The vertex element of a PLY file with only scalar vertex properties, as a structured
    array; the layout comes from the header. Returns (array, header comments)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    header = data[:end].decode("ascii").splitlines()
    fmt, count, props, comments, element = None, 0, [], [], None
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "comment":
            comments.append(line[len("comment "):])
        elif w[0] == "element":
            element = w[1]
            if element == "vertex":
                count = int(w[2])
            elif int(w[2]) > 0 and props == []:
                raise ValueError(f"{path}: element '{element}' before the vertex element")
        elif w[0] == "property" and element == "vertex":
            if w[1] == "list":
                raise ValueError(f"{path}: list property in the vertex element")
            props.append((w[2], PLY_TYPES[w[1]]))
    if fmt == "ascii":
        rows = np.loadtxt(data[end:].decode("ascii").splitlines(), ndmin=2, max_rows=count)
        out = np.empty(count, dtype=[(n, t) for n, t in props])
        for i, (n, _) in enumerate(props):
            out[n] = rows[:, i]
        return out, comments
    order = {"binary_little_endian": "<", "binary_big_endian": ">"}[fmt]
    dtype = np.dtype([(n, order + t) for n, t in props])
    return np.frombuffer(data, dtype=dtype, count=count, offset=end), comments


def drop_duplicates(c, coord_type):
    """Keeps the first of any points with identical (written) coordinates."""
    xyz = c["xyz"].astype(coord_type)
    order = np.lexsort((xyz[:, 2], xyz[:, 1], xyz[:, 0]))
    same = np.all(xyz[order[1:]] == xyz[order[:-1]], axis=1)
    drop = np.zeros(len(xyz), dtype=bool)
    drop[np.maximum(order[1:][same], order[:-1][same])] = True
    return {k: v[~drop] for k, v in c.items()}, int(drop.sum())


def write_ply(path, c, comments, double=False):
    coord = "<f8" if double else "<f4"
    dtype = np.dtype([("x", coord), ("y", coord), ("z", coord), ("nx", "<f4"), ("ny", "<f4"),
                      ("nz", "<f4"), ("class", "u1"), ("segment", "<i4")])
    rows = np.empty(len(c["xyz"]), dtype=dtype)
    for i, k in enumerate("xyz"):
        rows[k] = c["xyz"][:, i]
        rows["n" + k] = c["normal"][:, i]
    rows["class"], rows["segment"] = c["class"], c["segment"]
    ctype = "double" if double else "float"
    header = ["ply", "format binary_little_endian 1.0"] + [f"comment {t}" for t in comments] + [
        f"element vertex {len(rows)}"] + [f"property {ctype} {k}" for k in "xyz"] + [
        f"property float {k}" for k in ("nx", "ny", "nz")] + [
        "property uchar class", "property int segment", "end_header"]
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        f.write(rows.tobytes())


# ----------------------------------------------------------------------------------------------
# Converted inputs

def from_splat_synth(binary, command):
    """Runs splat-synth (command: its arguments but OUT) and converts its PLY: class 0,
    segment = patch_id, its exact normals."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "synth.ply")
        subprocess.run([binary, "-q", command[0], path] + command[1:], check=True)
        v, _ = read_ply(path)
    xyz = np.stack([v["x"], v["y"], v["z"]], axis=1).astype(float)
    n = np.stack([v["nx"], v["ny"], v["nz"]], axis=1).astype(float)
    return cloud(xyz, n, OBJECT, v["patch_id"])


def from_cgal(path, building):
    """A CGAL demo scan (x y z nx ny nz segment_index): reference normals = the file's own,
    segment = segment_index. building: class 5 (normal zeroed) for segment_index < 0, else 2 wall
    for |nz| < 0.3, 3 roof for nz > 0.9, 0 otherwise; ball: class 0."""
    v, comments = read_ply(path)
    xyz = np.stack([v["x"], v["y"], v["z"]], axis=1).astype(float)
    n = np.stack([v["nx"], v["ny"], v["nz"]], axis=1).astype(float)
    seg = v["segment_index"].astype(np.int32)
    cls = np.zeros(len(v), dtype=np.uint8)
    if building:
        cls[np.abs(n[:, 2]) < 0.3] = WALL
        cls[n[:, 2] > 0.9] = ROOF
        cls[seg < 0] = VEGETATION
        n[seg < 0] = 0
        seg[seg < 0] = -1
    return cloud(xyz, n, cls, seg), comments


def measured_spacing(xyz, rng, samples=2000):
    """Mean distance to the nearest neighbour, over a fixed random subset (brute force)."""
    xyz = xyz - xyz.mean(axis=0)
    pick = rng.choice(len(xyz), size=min(samples, len(xyz)), replace=False)
    q = xyz[pick]
    best = np.full(len(pick), np.inf)
    for start in range(0, len(xyz), 10000):
        block = xyz[start:start + 10000]
        d = (q * q).sum(1)[:, None] + (block * block).sum(1)[None, :] - 2 * q @ block.T
        d[pick[:, None] == np.arange(start, start + len(block))[None, :]] = np.inf
        best = np.minimum(best, d.min(axis=1))
    return float(np.sqrt(np.maximum(best, 0)).mean())


# ----------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("--scale", type=float, default=1.0, help="multiplies every point count")
    ap.add_argument("--splat-synth", help="splat-synth binary: its cad part is the cad scene")
    ap.add_argument("--cgal-dir", help="directory with CGAL's building.ply and ball.ply")
    ap.add_argument("--cgal-package", default="libcgal-demo",
                    help="the Debian package (and version) they came from, for the record")
    args = ap.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    scenes = []

    def emit(name, c, kind, closed, spacing, source, started, double=False):
        """Writes the scene, lists it and prints its summary line."""
        c, dropped = drop_duplicates(c, np.float64 if double else np.float32)
        write_ply(os.path.join(args.out_dir, name + ".ply"), c,
                  [f"splatkit scan test set: {name} (scripts/make_scan_scenes.py)", source],
                  double)
        scenes.append({"name": name, "file": name + ".ply", "kind": kind, "closed": closed,
                       "points": len(c["xyz"]), "spacing": round(spacing, 6), "source": source})
        counts = " ".join(f"{k}:{v}" for k, v in enumerate(np.bincount(c["class"])) if v)
        extra = f", {dropped} duplicates dropped" if dropped else ""
        print(f"{name:18s} {len(c['xyz']):8d} points  classes {counts}{extra}  "
              f"{time.perf_counter() - started:.2f} s", flush=True)

    synthetic = [
        ("city", city_patches, 300000, False, None, 1,
         "6 closed buildings (thick walls sampled on both faces, floor slabs, flat roofs, "
         "balconies) on a ground plane with streets"),
        ("terrain", terrain_patches, 150000, False, None, 2,
         "500 x 500 m analytic heightfield with hills, a winding valley and a steep slope; "
         "sampled in plan view"),
        ("facade", facade_patches, 120000, False, facade_vegetation, 3,
         "a closed gable-roofed building on ground with sparse vegetation (trees, shrubs, "
         "stray points; class 5)"),
        ("cad", cad_patches, 100000, True, None, 4,
         "splat-synth's closed CAD-like part (prism with bevel, boss and through hole)"),
    ]
    for name, make, target, closed, vegetation, seed, what in synthetic:
        patches = make()
        h = math.sqrt(total_area(patches) / (target * args.scale))
        for variant, scan, noisy in [("", False, False), ("-scan", True, False),
                                     ("-noisy", False, True), ("-scan-noisy", True, True)]:
            started = time.perf_counter()
            rng = np.random.default_rng([seed, scan])
            how = "scan lines 2h apart at 25 deg, h/2 along" if scan else "stratified"
            if name == "cad" and not scan and args.splat_synth:
                command = ["cad", "-n", str(round(target * args.scale)), "--seed", "11",
                           "--no-color"]
                c = from_splat_synth(args.splat_synth, command)
                how = " ".join(["splat-synth"] + command)
            else:
                c = sample(patches, h, scan, rng)
            if vegetation:
                c = concat([c, vegetation(h)])
            if noisy:
                c = add_noise(c, NOISE * h, np.random.default_rng([seed, scan, 1]))
                how += f", noise sigma {NOISE} h along the normal"
            full = name + variant
            source = f"Synthetic: {what}; {how}, h = {h:.4g} m."
            emit(full, c, "synthetic", closed, h, source, started)
            if full == "city":
                started = time.perf_counter()
                utm = dict(c, xyz=c["xyz"].astype(np.float32).astype(np.float64) + UTM_OFFSET)
                emit("city-utm", utm, "synthetic", False, h,
                     "Synthetic: the city scene's float32 points moved by (+500000, +4100000, "
                     "+300) m to UTM-like coordinates, written as double.", started, double=True)

    if args.cgal_dir:
        for name, building, closed in [("building", True, False), ("ball", False, True)]:
            started = time.perf_counter()
            c, comments = from_cgal(os.path.join(args.cgal_dir, name + ".ply"), building)
            note = f" (header: '{comments[0]}')" if comments else ""
            source = (f"Real: data/points_3/{name}.ply of CGAL's demo data (Debian "
                      f"{args.cgal_package}){note}, with its own normals and segment_index.")
            spacing = measured_spacing(c["xyz"], np.random.default_rng(5))
            emit(name, c, "real", closed, spacing, source, started)

    with open(os.path.join(args.out_dir, "scenes.json"), "w") as f:
        json.dump(scenes, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    sys.exit(main())
