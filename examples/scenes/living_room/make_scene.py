#!/usr/bin/env python3
"""Writes crex's textured example scene: a furnished living room as glTF 2.0.

    python3 examples/scenes/living_room/make_scene.py OUT_DIR [--untextured] [--glb]

OUT_DIR receives scene.gltf, scene.bin and textures/*.png (or one scene.glb with --glb, every
image inside it). Everything is made here, textures included (wood, ceramic tiles and their
normal map, two fabrics, a poster with text, a TV screen, leaves with an alpha cut-out, book
spines, a floor roughness map), so the repository carries no binaries; the build runs this
once (CMake target `living_room_scene`, into build/<type>/examples/scenes/living_room/).
--untextured writes the same room with every texture replaced by its mean colour (the
timing comparison in docs/textures.md).

The room: 6 x 4 x 2.8 m, metres, +y up (glTF's units). A ceiling panel (a sampled area
light) and a floor lamp (a KHR_lights_punctual point light); a sofa, a coffee table with a
mug (tagged task object, extras {"task": 3}), a glass vase and a bowl of oranges, a TV whose
screen glows with an emission texture (tagged distractor), a poster, a bookshelf, a plant
whose leaves are alpha cut-outs, a rug, a tiled feature wall. About 150k triangles.
Pure Python (no numpy), deterministic: the same bytes on every run.
"""
import argparse
import json
import math
import os
import struct
import zlib

# ---------------------------------------------------------------- images


def write_png(path, width, height, channels, pixels):
    """8-bit PNG of `pixels` (bytes, row-major, top row first)."""
    stride = width * channels
    raw = b"".join(b"\x00" + pixels[y * stride:(y + 1) * stride] for y in range(height))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    colour_type = {1: 0, 3: 2, 4: 6}[channels]
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(data)
    return data


def hash01(x, y, seed):
    """A fixed pseudo-random number in [0, 1) for integer lattice point (x, y)."""
    h = (x * 374761393 + y * 668265263 + seed * 2147483647) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return ((h ^ (h >> 16)) & 0xFFFFFF) / float(0x1000000)


# Lattice cells' corner values, memoised per image (image() clears it): most lookups of a
# texture land in a cell already seen, and hashing dominated the script's time (3x faster).
_CELLS = {}


def value_noise(x, y, seed):
    """Smooth noise in [0, 1): the lattice's values, interpolated."""
    ix, iy = math.floor(x), math.floor(y)
    fx, fy = x - ix, y - iy
    fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
    key = (ix, iy, seed)
    corners = _CELLS.get(key)
    if corners is None:
        corners = _CELLS[key] = (hash01(ix, iy, seed), hash01(ix + 1, iy, seed),
                                 hash01(ix, iy + 1, seed), hash01(ix + 1, iy + 1, seed))
    a, b, c, d = corners
    return (a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy


def fbm(x, y, seed, octaves=4):
    total, amplitude, norm = 0.0, 1.0, 0.0
    for o in range(octaves):
        total += amplitude * value_noise(x, y, seed + o)
        norm += amplitude
        x, y, amplitude = x * 2.03, y * 2.03, amplitude * 0.5
    return total / norm


def to_byte(v):
    return 0 if v <= 0 else 255 if v >= 1 else int(v * 255 + 0.5)


def image(width, height, channels, texel):
    """Pixels from texel(x, y) -> tuple of `channels` values in [0, 1] (display-encoded)."""
    _CELLS.clear()
    out = bytearray(width * height * channels)
    i = 0
    for y in range(height):
        for x in range(width):
            for v in texel(x, y):
                out[i] = to_byte(v)
                i += 1
    return bytes(out)


def wood_floor(size):
    planks = 6  # across the texture; the floor repeats it
    def texel(x, y):
        u, v = x / size, y / size
        p = int(u * planks)
        offset = hash01(p, 7, 11)  # planks' ends staggered
        seg = int(v * 2 + offset * 2)
        tone = 0.75 + 0.5 * hash01(p, seg, 3)
        grain = fbm(u * 40, v * 3 + p * 5.1, 21)
        rings = 0.5 + 0.5 * math.sin((u * planks - p) * 35 + grain * 9)
        r, g, b = 0.55 * tone, 0.36 * tone, 0.21 * tone
        k = 0.82 + 0.18 * rings
        edge = min(u * planks - p, 1 - (u * planks - p))
        end = abs(((v * 2 + offset * 2) % 1) - 0.5) > 0.497
        if edge < 0.012 or end:
            k *= 0.35
        return (r * k, g * k, b * k)
    return texel


def floor_roughness(size):
    """glTF metallicRoughness: G roughness, B metallic (0): worn planks, some waxed."""
    def texel(x, y):
        u, v = x / size, y / size
        p = int(u * 6)
        wax = hash01(p, int(v * 2 + hash01(p, 7, 11) * 2), 5)
        rough = 0.35 + 0.45 * wax + 0.15 * fbm(u * 20, v * 20, 9)
        return (0, rough, 0)
    return texel


def tiles(size):
    n = 8
    def texel(x, y):
        u, v = x * n / size, y * n / size
        i, j = int(u), int(v)
        fu, fv = u - i, v - j
        if min(fu, fv, 1 - fu, 1 - fv) < 0.035:
            return (0.55, 0.55, 0.52)  # grout
        tone = 0.92 + 0.08 * hash01(i, j, 31)
        glaze = 0.96 + 0.04 * fbm(u * 3, v * 3, 41)
        return (0.20 * tone * glaze, 0.48 * tone * glaze, 0.50 * tone * glaze)
    return texel


def tiles_normal(size):
    """Tangent-space normals (+y up in the image): grout grooves and bevelled tile edges."""
    n = 8
    def texel(x, y):
        u, v = x * n / size, y * n / size
        fu, fv = u - int(u), v - int(v)
        nx = ny = 0.0
        bevel = 0.09
        if fu < bevel:
            nx = -0.6 * (1 - fu / bevel)
        elif fu > 1 - bevel:
            nx = 0.6 * (1 - (1 - fu) / bevel)
        if fv < bevel:
            ny = 0.6 * (1 - fv / bevel)  # t grows downwards: the image's up is -t
        elif fv > 1 - bevel:
            ny = -0.6 * (1 - (1 - fv) / bevel)
        nz = math.sqrt(max(0.0, 1 - nx * nx - ny * ny))
        return (0.5 + 0.5 * nx, 0.5 + 0.5 * ny, 0.5 + 0.5 * nz)
    return texel


def woven(size, warp, weft, threads, seed):
    def texel(x, y):
        u, v = x * threads / size, y * threads / size
        iu, iv = int(u), int(v)
        over = (iu + iv) % 4 < 2  # twill
        t = (u - iu) if over else (v - iv)
        shade = 0.75 + 0.25 * math.sin(t * math.pi)
        c = warp if over else weft
        n = 0.9 + 0.2 * fbm(u * 0.7, v * 0.7, seed)
        return (c[0] * shade * n, c[1] * shade * n, c[2] * shade * n)
    return texel


def rug(size):
    def texel(x, y):
        u, v = x / size - 0.5, y / size - 0.5
        border = max(abs(u), abs(v)) > 0.42
        band = 0.38 < max(abs(u), abs(v)) <= 0.42
        d = (abs(u) + abs(v)) * 8
        diamond = int(d) % 2 == 0
        n = 0.85 + 0.3 * fbm(x * 0.15, y * 0.15, 77)
        if band:
            c = (0.85, 0.78, 0.6)
        elif border:
            c = (0.45, 0.08, 0.07)
        else:
            c = (0.62, 0.12, 0.1) if diamond else (0.85, 0.76, 0.58)
        return (c[0] * n, c[1] * n, c[2] * n)
    return texel


# A 5x7 bitmap font for the poster and the screen (capitals, digits, a few signs).
FONT = {
    "A": "01110100011000111111100011000110001", "B": "11110100011000111110100011000111110",
    "C": "01110100011000010000100001000101110", "D": "11110100011000110001100011000111110",
    "E": "11111100001000011110100001000011111", "F": "11111100001000011110100001000010000",
    "G": "01110100011000010111100011000101111", "H": "10001100011000111111100011000110001",
    "I": "01110001000010000100001000010001110", "J": "00111000100001000010000101001001100",
    "K": "10001100101010011000101001001010001", "L": "10000100001000010000100001000011111",
    "M": "10001110111010110101100011000110001", "N": "10001110011010110011100011000110001",
    "O": "01110100011000110001100011000101110", "P": "11110100011000111110100001000010000",
    "Q": "01110100011000110001101011001001101", "R": "11110100011000111110101001001010001",
    "S": "01111100001000001110000010000111110", "T": "11111001000010000100001000010000100",
    "U": "10001100011000110001100011000101110", "V": "10001100011000110001100010101000100",
    "W": "10001100011000110101101011010101010", "X": "10001100010101000100010101000110001",
    "Y": "10001100010101000100001000010000100", "Z": "11111000010001000100010001000011111",
    "0": "01110100011001110101110011000101110", "1": "00100011000010000100001000010001110",
    "2": "01110100010000100010001000100011111", "3": "11111000100010000010000011000101110",
    "4": "00010001100101010010111110001000010", "5": "11111100001111000001000011000101110",
    "6": "00110010001000011110100011000101110", "7": "11111000010001000100010000100001000",
    "8": "01110100011000101110100011000101110", "9": "01110100011000101111000010001001100",
    ".": "00000000000000000000000000110001100", "-": "00000000000000011111000000000000000",
    " ": "0" * 35, ":": "00000011000110000000011000110000000",
}


def text_mask(lines):
    """[(text, x, y, scale)] -> function (x, y) -> True on a glyph's pixel."""
    def inside(px, py):
        for text, x0, y0, s in lines:
            if py < y0 or py >= y0 + 7 * s:
                continue
            col = (px - x0) // s
            if col < 0 or col >= 6 * len(text):
                continue
            glyph = FONT.get(text[col // 6], FONT[" "])
            cx, cy = col % 6, (py - y0) // s
            if cx < 5 and glyph[cy * 5 + cx] == "1":
                return True
        return False
    return inside


def poster(width, height):
    title = text_mask([("CREX", 72, 90, 16), ("SELECTIVE", 70, 250, 7), ("RENDERING", 70, 320, 7),
                       ("WHERE THE EYE GOES", 42, 640, 4), ("THE RAYS GO", 126, 690, 4)])
    def texel(x, y):
        u, v = x / width, y / height
        if title(x, y):
            return (0.98, 0.94, 0.82)
        # Concentric rings, like an eye, behind the text.
        d = math.hypot(u - 0.5, (v - 0.62) * height / width)
        ring = int(d * 14) % 2 == 0 and d < 0.36
        base = (0.08 + 0.1 * v, 0.16 + 0.05 * v, 0.32 - 0.1 * v)
        if ring:
            base = (0.85, 0.32 + 0.3 * d, 0.12)
        if max(abs(u - 0.5), abs(v - 0.5)) > 0.47:
            base = (0.95, 0.93, 0.88)  # white margin
        return base
    return texel


def screen(width, height):
    caption = text_mask([("NOW SHOWING", 20, 16, 3), ("ALPS 4K", 20, 246, 3)])
    def texel(x, y):
        u, v = x / width, y / height
        if caption(x, y):
            return (1, 1, 1)
        horizon = 0.62 + 0.12 * fbm(u * 6, 0.5, 5) - 0.1 * abs(math.sin(u * 7))
        if v < horizon:
            sun = math.hypot((u - 0.72) * width / height, v - 0.28) < 0.09
            if sun:
                return (1.0, 0.93, 0.6)
            t = v / horizon
            return (0.25 + 0.6 * t, 0.45 + 0.35 * t, 0.9 - 0.2 * t)
        snow = v < horizon + 0.04
        g = 0.6 + 0.4 * fbm(u * 30, v * 30, 13)
        return (0.95, 0.95, 0.97) if snow else (0.12 * g, 0.45 * g, 0.15 * g)
    return texel


def leaf(size):
    """RGBA: a leaf (alpha 1) on nothing (alpha 0)."""
    def texel(x, y):
        u, v = x / size, y / size
        half = 0.45 * math.sin(math.pi * v) ** 0.8 * (1 - 0.3 * v)
        inside = abs(u - 0.5) < half and 0.02 < v < 0.98
        vein = abs(u - 0.5) < 0.012 or (abs(abs(u - 0.5) - (v % 0.12) * 1.5) < 0.01 and abs(u - 0.5) < half * 0.9)
        g = 0.7 + 0.3 * fbm(u * 8, v * 8, 3)
        c = (0.35, 0.6, 0.25) if vein else (0.08 * g, 0.32 * g, 0.07 * g)
        return (c[0], c[1], c[2], 1.0 if inside else 0.0)
    return texel


def books(width, height):
    """Spines side by side across the texture."""
    def texel(x, y):
        u, v = x / width, y / height
        k = int(u * 16)
        r, g, b = hash01(k, 1, 5), hash01(k, 2, 5), hash01(k, 3, 5)
        c = (0.15 + 0.6 * r, 0.1 + 0.45 * g, 0.1 + 0.5 * b)
        f = u * 16 - k
        if f < 0.06 or f > 0.94:
            c = (c[0] * 0.4, c[1] * 0.4, c[2] * 0.4)
        if 0.15 < v < 0.18 or 0.82 < v < 0.85:
            c = (0.85, 0.72, 0.3)  # gilt bands
        return c
    return texel


TEXTURES = [
    # name, width, height, channels, maker
    ("wood_floor", 512, 512, 3, lambda: wood_floor(512)),
    ("floor_roughness", 256, 256, 3, lambda: floor_roughness(256)),
    ("tiles", 512, 512, 3, lambda: tiles(512)),
    ("tiles_normal", 256, 256, 3, lambda: tiles_normal(256)),
    ("sofa_fabric", 256, 256, 3, lambda: woven(256, (0.18, 0.26, 0.36), (0.24, 0.32, 0.42), 48, 7)),
    ("rug", 512, 512, 3, lambda: rug(512)),
    ("poster", 512, 768, 3, lambda: poster(512, 768)),
    ("screen", 512, 288, 3, lambda: screen(512, 288)),
    ("leaf", 256, 256, 4, lambda: leaf(256)),
    ("books", 512, 128, 3, lambda: books(512, 128)),
]

# ---------------------------------------------------------------- geometry


class Mesh:
    def __init__(self):
        self.p, self.n, self.t, self.i = [], [], [], []

    def vertex(self, p, n, t):
        self.p.append(p)
        self.n.append(n)
        self.t.append(t)
        return len(self.p) - 1

    def tri(self, a, b, c):
        self.i += [a, b, c]

    def quad(self, a, b, c, d):
        self.i += [a, b, c, a, c, d]


def norm(v):
    l = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2) or 1.0
    return (v[0] / l, v[1] / l, v[2] / l)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def quad_mesh(origin, edge_u, edge_v, uv_scale=(1, 1), mesh=None):
    """A rectangle origin + s edge_u + t edge_v, facing cross(edge_u, edge_v); uv (s, 1 - t)
    scaled (so the image's top is at origin + edge_v)."""
    m = mesh or Mesh()
    n = norm(cross(edge_u, edge_v))
    idx = []
    for s, t in ((0, 0), (1, 0), (1, 1), (0, 1)):
        p = tuple(origin[k] + s * edge_u[k] + t * edge_v[k] for k in range(3))
        idx.append(m.vertex(p, n, (s * uv_scale[0], (1 - t) * uv_scale[1])))
    m.quad(*idx)
    return m


def box_mesh(lo, hi, uv_per_metre=1.0, mesh=None):
    m = mesh or Mesh()
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    sx, sy, sz = (x1 - x0) * uv_per_metre, (y1 - y0) * uv_per_metre, (z1 - z0) * uv_per_metre
    quad_mesh((x0, y0, z1), (x1 - x0, 0, 0), (0, y1 - y0, 0), (sx, sy), m)  # +z
    quad_mesh((x1, y0, z0), (x0 - x1, 0, 0), (0, y1 - y0, 0), (sx, sy), m)  # -z
    quad_mesh((x1, y0, z1), (0, 0, z0 - z1), (0, y1 - y0, 0), (sz, sy), m)  # +x
    quad_mesh((x0, y0, z0), (0, 0, z1 - z0), (0, y1 - y0, 0), (sz, sy), m)  # -x
    quad_mesh((x0, y1, z1), (x1 - x0, 0, 0), (0, 0, z0 - z1), (sx, sz), m)  # +y
    quad_mesh((x0, y0, z0), (x1 - x0, 0, 0), (0, 0, z1 - z0), (sx, sz), m)  # -y
    return m


def lathe_mesh(profile, segments, centre=(0, 0, 0), mesh=None):
    """A surface of revolution about +y: profile [(radius, height)], smooth normals."""
    m = mesh or Mesh()
    cx, cy, cz = centre
    rows = len(profile)
    base = len(m.p)
    for j, (r, h) in enumerate(profile):
        # The profile's tangent, for the normal.
        a = profile[max(j - 1, 0)]
        b = profile[min(j + 1, rows - 1)]
        dr, dh = b[0] - a[0], b[1] - a[1]
        for i in range(segments + 1):
            phi = 2 * math.pi * i / segments
            c, s = math.cos(phi), math.sin(phi)
            n = norm((dh * c, -dr, dh * s))
            m.vertex((cx + r * c, cy + h, cz + r * s), n, (i / segments, j / (rows - 1)))
    for j in range(rows - 1):
        for i in range(segments):
            a = base + j * (segments + 1) + i
            b = a + segments + 1
            # A row on the axis (radius 0) makes its quads triangles: leave out the empty half.
            if profile[j][0] > 1e-9:
                m.tri(a, b + 1, a + 1)
            if profile[j + 1][0] > 1e-9:
                m.tri(a, b, b + 1)
    return m


def sphere_mesh(centre, radius, segments, rings, mesh=None):
    profile = [(radius * math.sin(math.pi * k / rings), -radius * math.cos(math.pi * k / rings)) for k in range(rings + 1)]
    return lathe_mesh(profile, segments, centre, mesh)


def torus_arc_mesh(centre, major, minor, segments, sides, mesh=None):
    """Half a torus in the xy plane on the +x side of `centre` (a mug's handle)."""
    m = mesh or Mesh()
    base = len(m.p)
    for i in range(segments + 1):
        a = -math.pi / 2 + math.pi * i / segments
        ring = (centre[0] + major * math.cos(a), centre[1] + major * math.sin(a), centre[2])
        for j in range(sides + 1):
            b = 2 * math.pi * j / sides
            n = (math.cos(a) * math.cos(b), math.sin(a) * math.cos(b), math.sin(b))
            m.vertex((ring[0] + minor * n[0], ring[1] + minor * n[1], ring[2] + minor * n[2]), n, (i / segments, j / sides))
    for i in range(segments):
        for j in range(sides):
            a = base + i * (sides + 1) + j
            b = a + sides + 1
            m.quad(a, a + 1, b + 1, b)
    return m


def cushion_mesh(centre, half, segments, mesh=None, uv_scale=1.0):
    """A rounded box (a superellipsoid with exponent 0.25): sofa cushions."""
    m = mesh or Mesh()
    e = 0.25
    base = len(m.p)

    def sgnpow(x, p):
        return math.copysign(abs(x) ** p, x)

    rows = segments
    cols = 2 * segments
    for j in range(rows + 1):
        th = -math.pi / 2 + math.pi * j / rows
        for i in range(cols + 1):
            ph = -math.pi + 2 * math.pi * i / cols
            ct, st, cp, sp = math.cos(th), math.sin(th), math.cos(ph), math.sin(ph)
            x = half[0] * sgnpow(ct, e) * sgnpow(cp, e)
            y = half[1] * sgnpow(st, e)
            z = half[2] * sgnpow(ct, e) * sgnpow(sp, e)
            n = norm((sgnpow(ct, 2 - e) * sgnpow(cp, 2 - e) / half[0], sgnpow(st, 2 - e) / half[1],
                      sgnpow(ct, 2 - e) * sgnpow(sp, 2 - e) / half[2]))
            m.vertex((centre[0] + x, centre[1] + y, centre[2] + z), n, (uv_scale * i / cols * 2, uv_scale * j / rows))
    for j in range(rows):
        for i in range(cols):
            a = base + j * (cols + 1) + i
            b = a + cols + 1
            m.quad(a, b, b + 1, a + 1)
    return m


# ---------------------------------------------------------------- the room


def build(untextured):
    objects = []  # (name, mesh, material name, extras)
    mats = {}

    def material(name, base=(0.8, 0.8, 0.8), rough=0.8, metal=0.0, tex=None, mr=None, normal=None, emissive=None,
                 emissive_tex=None, strength=None, alpha=None, transmission=None, transform=None):
        mats[name] = dict(base=base, rough=rough, metal=metal, tex=tex, mr=mr, normal=normal, emissive=emissive,
                          emissive_tex=emissive_tex, strength=strength, alpha=alpha, transmission=transmission, transform=transform)

    material("plaster", base=(0.82, 0.8, 0.75), rough=0.95)
    material("ceiling", base=(0.9, 0.9, 0.88), rough=1.0)
    material("floor", base=(1, 1, 1), rough=1.0, tex="wood_floor", mr="floor_roughness")
    material("tiles", base=(1, 1, 1), rough=0.25, tex="tiles", normal="tiles_normal")
    material("sofa", base=(1, 1, 1), rough=0.9, tex="sofa_fabric")
    material("sofa_frame", base=(0.12, 0.1, 0.09), rough=0.6)
    material("rug", base=(1, 1, 1), rough=1.0, tex="rug")
    # A quarter turn clockwise as glTF viewers turn it: the table's grain as it was rendered
    # (and its committed reference made) while crex turned KHR_texture_transform the other way.
    material("table_wood", base=(0.7, 0.55, 0.45), rough=0.35, tex="wood_floor", transform={"rotation": -1.5707963, "scale": [2.0, 1.0]})
    material("ceramic", base=(0.92, 0.9, 0.85), rough=0.12)
    material("glass", base=(0.95, 0.98, 0.96), rough=0.0, transmission=1.0)
    material("orange", base=(0.85, 0.35, 0.05), rough=0.45)
    material("tv_black", base=(0.02, 0.02, 0.02), rough=0.2)
    material("screen", base=(0.01, 0.01, 0.01), rough=0.05, emissive=(1, 1, 1), emissive_tex="screen", strength=3.0)
    material("poster", base=(1, 1, 1), rough=0.7, tex="poster")
    material("cabinet", base=(0.32, 0.24, 0.17), rough=0.5)
    material("leaves", base=(1, 1, 1), rough=0.6, tex="leaf", alpha="MASK")
    material("pot", base=(0.62, 0.3, 0.18), rough=0.8)
    material("books", base=(1, 1, 1), rough=0.7, tex="books")
    material("lamp_metal", base=(0.75, 0.74, 0.72), rough=0.25, metal=1.0)
    material("lamp_shade", base=(0.92, 0.86, 0.72), rough=1.0)
    material("panel", base=(0, 0, 0), emissive=(1.0, 0.96, 0.88), strength=8.0)

    W, D, H = 3.0, 2.0, 2.8  # half width (x), half depth (z), height
    objects.append(("floor", quad_mesh((-W, 0, D), (2 * W, 0, 0), (0, 0, -2 * D), (2 * W / 1.5, 2 * D / 1.5)), "floor", None))
    objects.append(("ceiling", quad_mesh((-W, H, -D), (2 * W, 0, 0), (0, 0, 2 * D)), "ceiling", None))
    objects.append(("back_wall", quad_mesh((-W, 0, -D), (2 * W, 0, 0), (0, H, 0)), "plaster", None))
    objects.append(("right_wall", quad_mesh((W, 0, -D), (0, 0, 2 * D), (0, H, 0)), "plaster", None))
    objects.append(("front_wall", quad_mesh((W, 0, D), (-2 * W, 0, 0), (0, H, 0)), "plaster", None))
    objects.append(("tiled_wall", quad_mesh((-W, 0, D), (0, 0, -2 * D), (0, H, 0), (2 * D / 0.8, H / 0.8)), "tiles", None))
    objects.append(("ceiling_panel", quad_mesh((-0.6, H - 0.005, -0.3), (1.2, 0, 0), (0, 0, 0.6)), "panel", None))

    # Sofa along the tiled wall, facing +x.
    frame = box_mesh((-2.95, 0.0, -1.05), (-2.25, 0.38, 1.05))
    box_mesh((-2.98, 0.0, -1.05), (-2.78, 0.95, 1.05), mesh=frame)
    box_mesh((-2.95, 0.0, -1.15), (-2.3, 0.62, -1.0), mesh=frame)
    box_mesh((-2.95, 0.0, 1.0), (-2.3, 0.62, 1.15), mesh=frame)
    objects.append(("sofa_frame", frame, "sofa_frame", None))
    cushions = Mesh()
    for z in (-0.66, 0.0, 0.66):
        cushion_mesh((-2.55, 0.47, z), (0.3, 0.1, 0.31), 56, cushions, uv_scale=3)
        cushion_mesh((-2.71, 0.78, z), (0.08, 0.24, 0.3), 56, cushions, uv_scale=3)
    objects.append(("sofa_cushions", cushions, "sofa", None))

    objects.append(("rug", quad_mesh((-2.1, 0.004, 1.2), (1.9, 0, 0), (0, 0, -2.4)), "rug", None))

    # Coffee table with a mug (the task object), a glass vase and a bowl of oranges.
    table = box_mesh((-1.75, 0.4, -0.55), (-0.75, 0.45, 0.55), uv_per_metre=1.2)
    for x in (-1.7, -0.85):
        for z in (-0.5, 0.45):
            box_mesh((x, 0.0, z), (x + 0.05, 0.4, z + 0.05), mesh=table)
    objects.append(("coffee_table", table, "table_wood", None))
    mug_profile = [(0.0, 0.0), (0.038, 0.0), (0.04, 0.004)] + [(0.04 + 0.002 * math.sin(k / 10 * math.pi), 0.004 + 0.09 * k / 40) for k in range(1, 41)]
    mug_profile += [(0.036, 0.094), (0.034, 0.02), (0.0, 0.02)]
    mug = lathe_mesh(mug_profile, 160, (-1.05, 0.45, 0.22))
    torus_arc_mesh((-1.05 + 0.04, 0.45 + 0.05, 0.22), 0.03, 0.008, 48, 24, mug)
    objects.append(("mug", mug, "ceramic", {"task": 3, "tag": "mug"}))
    vase_profile = [(0.0, 0.0), (0.05, 0.0)] + [(0.05 + 0.035 * math.sin(k / 30 * math.pi * 1.3), 0.3 * k / 30) for k in range(1, 31)]
    objects.append(("vase", lathe_mesh(vase_profile, 128, (-1.45, 0.45, -0.25)), "glass", None))
    bowl = lathe_mesh([(0.0, 0.0), (0.06, 0.0)] + [(0.06 + 0.1 * math.sin(k / 20 * math.pi / 2), 0.07 * (k / 20) ** 1.5) for k in range(1, 21)],
                      96, (-1.25, 0.45, 0.05))
    objects.append(("bowl", bowl, "ceramic", None))
    oranges = Mesh()
    for k, (dx, dz) in enumerate(((0.0, 0.0), (0.07, 0.03), (-0.05, 0.06), (0.02, -0.07), (-0.06, -0.04))):
        sphere_mesh((-1.25 + dx, 0.49 + 0.02 * (k % 2), 0.05 + dz), 0.04, 48, 24, oranges)
    objects.append(("oranges", oranges, "orange", None))

    # TV on a cabinet against the back wall: the screen is the distractor.
    objects.append(("tv_cabinet", box_mesh((0.2, 0.0, -1.98), (2.0, 0.5, -1.55)), "cabinet", None))
    objects.append(("tv_body", box_mesh((0.45, 0.6, -1.9), (1.75, 1.36, -1.84)), "tv_black", None))
    objects.append(("tv_stand", box_mesh((1.0, 0.5, -1.85), (1.2, 0.6, -1.7)), "tv_black", None))
    objects.append(("tv_screen", quad_mesh((0.49, 0.64, -1.8395), (1.22, 0, 0), (0, 0.686, 0)), "screen", {"distractor": True, "tag": "tv"}))

    objects.append(("poster", quad_mesh((-1.55, 1.0, -1.995), (0.7, 0, 0), (0, 1.05, 0)), "poster", None))

    # Bookshelf (the back wall's left corner) with books on two shelves.
    shelf = box_mesh((-2.95, 0.0, -1.98), (-2.91, 1.8, -1.6))
    box_mesh((-1.99, 0.0, -1.98), (-1.95, 1.8, -1.6), mesh=shelf)
    for y in (0.0, 0.6, 1.2, 1.76):
        box_mesh((-2.95, y, -1.98), (-1.95, y + 0.04, -1.6), mesh=shelf)
    objects.append(("bookshelf", shelf, "cabinet", None))
    book_mesh = Mesh()
    for row, y in enumerate((0.64, 1.24)):
        x = -2.9
        k = 0
        while x < -2.05:
            w = 0.025 + 0.03 * hash01(k, row, 2)
            h = 0.3 + 0.18 * hash01(k, row, 4)
            u0 = hash01(k, row, 6) * 0.9
            start = len(book_mesh.p)
            box_mesh((x, y, -1.95), (x + w, y + h, -1.72), mesh=book_mesh)
            for v in range(start, len(book_mesh.p)):  # a spine's slice of the texture
                s, t = book_mesh.t[v]
                book_mesh.t[v] = (u0 + 0.06 * min(max(s / max(w, 1e-6), 0), 1), t / max(h, 1e-6))
            x += w + 0.004
            k += 1
    objects.append(("books", book_mesh, "books", None))

    # Plant in a pot, leaves cut out by their texture's alpha.
    objects.append(("pot", lathe_mesh([(0.0, 0.0), (0.14, 0.0), (0.18, 0.38), (0.19, 0.4), (0.16, 0.4), (0.15, 0.36), (0.0, 0.36)], 96,
                                      (-0.45, 0.0, -1.62)), "pot", None))
    leaves = Mesh()
    for k in range(90):
        a = 2 * math.pi * hash01(k, 0, 17)
        tilt = 0.4 + 0.9 * hash01(k, 1, 17)
        height = 0.45 + 0.75 * hash01(k, 2, 17)
        length_ = 0.28 + 0.14 * hash01(k, 3, 17)
        base = (-0.45 + 0.05 * math.cos(a), height, -1.62 + 0.05 * math.sin(a))
        along = (math.cos(a) * math.sin(tilt) * length_, math.cos(tilt) * length_, math.sin(a) * math.sin(tilt) * length_)
        side = (-math.sin(a) * 0.16, 0.0, math.cos(a) * 0.16)
        origin = tuple(base[i] - 0.5 * side[i] for i in range(3))
        quad_mesh(origin, side, along, (1, 1), leaves)
    objects.append(("plant_leaves", leaves, "leaves", None))

    # Floor lamp by the sofa: a pole, a shade, and the point light in the shade, above the pole's
    # top (a light inside the pole would light nothing).
    lamp = lathe_mesh([(0.0, 0.0), (0.16, 0.0), (0.16, 0.03), (0.015, 0.04), (0.015, 1.42), (0.0, 1.42)], 64, (-2.45, 0.0, 1.55))
    objects.append(("lamp_pole", lamp, "lamp_metal", None))
    objects.append(("lamp_shade", lathe_mesh([(0.22, 1.35), (0.2, 1.45), (0.14, 1.62)], 96, (-2.45, 0.0, 1.55)), "lamp_shade", None))
    lights = [("floor_lamp", (-2.45, 1.5, 1.55), (1.0, 0.8, 0.55), 6.0)]

    camera = {"position": (2.75, 1.6, 1.9), "target": (-0.7, 0.85, -0.8), "yfov": 1.0}
    return objects, mats, lights, camera


# ---------------------------------------------------------------- glTF


def mean_colour(pixels, channels):
    n = len(pixels) // channels
    return tuple(sum(pixels[c::channels]) / (255.0 * n) for c in range(3))


def srgb_to_linear(c):
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def look_at_matrix(position, target):
    f = norm(tuple(target[i] - position[i] for i in range(3)))
    r = norm(cross(f, (0, 1, 0)))
    u = cross(r, f)
    # Columns: right, up, back (the camera looks down its -z), position.
    return [r[0], r[1], r[2], 0, u[0], u[1], u[2], 0, -f[0], -f[1], -f[2], 0, position[0], position[1], position[2], 1]


def write_scene(out_dir, untextured, glb):
    os.makedirs(out_dir, exist_ok=True)
    objects, mats, lights, camera = build(untextured)
    blob = bytearray()
    gltf = {"asset": {"version": "2.0", "generator": "crex examples/scenes/living_room/make_scene.py"},
            "scene": 0, "scenes": [{"name": "living_room", "nodes": []}], "nodes": [], "meshes": [], "accessors": [],
            "bufferViews": [], "materials": [], "textures": [], "images": [], "samplers": [{"magFilter": 9729, "minFilter": 9987}],
            "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform",
                               "KHR_materials_transmission"]}

    def view(data, target=None):
        while len(blob) % 4:
            blob.append(0)
        entry = {"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)}
        if target:
            entry["target"] = target
        blob.extend(data)
        gltf["bufferViews"].append(entry)
        return len(gltf["bufferViews"]) - 1

    def accessor(values, kind, component=5126, target=34962):
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3}[kind]
        fmt = {5126: "f", 5125: "I", 5123: "H"}[component]
        data = struct.pack("<%d%s" % (len(values), fmt), *values)
        entry = {"bufferView": view(data, target), "componentType": component, "count": len(values) // width, "type": kind}
        if kind == "VEC3" and component == 5126:
            entry["min"] = [min(values[i::3]) for i in range(3)]
            entry["max"] = [max(values[i::3]) for i in range(3)]
        gltf["accessors"].append(entry)
        return len(gltf["accessors"]) - 1

    # Textures: made once, written as files or into the GLB.
    tex_index, means = {}, {}
    for name, width, height, channels, maker in TEXTURES:
        pixels = image(width, height, channels, maker())
        means[name] = tuple(srgb_to_linear(c) for c in mean_colour(pixels, channels))
        if untextured:
            continue
        if glb:
            path = os.path.join(out_dir, ".tmp.png")
            data = write_png(path, width, height, channels, pixels)
            os.remove(path)
            gltf["images"].append({"name": name, "mimeType": "image/png", "bufferView": view(data)})
        else:
            os.makedirs(os.path.join(out_dir, "textures"), exist_ok=True)
            write_png(os.path.join(out_dir, "textures", name + ".png"), width, height, channels, pixels)
            gltf["images"].append({"name": name, "uri": "textures/%s.png" % name})
        gltf["textures"].append({"sampler": 0, "source": len(gltf["images"]) - 1})
        tex_index[name] = len(gltf["textures"]) - 1

    def texture_info(name, transform=None):
        info = {"index": tex_index[name]}
        if transform:
            info["extensions"] = {"KHR_texture_transform": transform}
        return info

    mat_index = {}
    for name, m in mats.items():
        base = list(m["base"])
        pbr = {"baseColorFactor": base + [1.0], "metallicFactor": m["metal"], "roughnessFactor": m["rough"]}
        entry = {"name": name, "pbrMetallicRoughness": pbr}
        if m["tex"]:
            if untextured:
                mean = means[m["tex"]]
                pbr["baseColorFactor"] = [base[i] * mean[i] for i in range(3)] + [1.0]
            else:
                pbr["baseColorTexture"] = texture_info(m["tex"], m["transform"])
        if m["mr"] and not untextured:
            pbr["metallicRoughnessTexture"] = texture_info(m["mr"])
        if m["normal"] and not untextured:
            entry["normalTexture"] = texture_info(m["normal"])
        if m["emissive"]:
            entry["emissiveFactor"] = list(m["emissive"])
            if m["emissive_tex"]:
                if untextured:
                    entry["emissiveFactor"] = list(means[m["emissive_tex"]])
                    # A constant emission would make crex sample it as a lamp: keep it a glowing surface.
                    entry["extras"] = {"crex_light": False}
                else:
                    entry["emissiveTexture"] = texture_info(m["emissive_tex"])
            if m["strength"]:
                entry.setdefault("extensions", {})["KHR_materials_emissive_strength"] = {"emissiveStrength": m["strength"]}
        if m["alpha"] and not untextured:
            entry["alphaMode"] = m["alpha"]
            entry["doubleSided"] = True
        if m["transmission"]:
            entry.setdefault("extensions", {})["KHR_materials_transmission"] = {"transmissionFactor": m["transmission"]}
        gltf["materials"].append(entry)
        mat_index[name] = len(gltf["materials"]) - 1

    triangles = 0
    for name, mesh, mat, extras in objects:
        positions = [c for p in mesh.p for c in p]
        normals = [c for n in mesh.n for c in n]
        uvs = [c for t in mesh.t for c in t]
        big = len(mesh.p) > 65535
        prim = {"attributes": {"POSITION": accessor(positions, "VEC3"), "NORMAL": accessor(normals, "VEC3"),
                               "TEXCOORD_0": accessor(uvs, "VEC2")},
                "indices": accessor(mesh.i, "SCALAR", 5125 if big else 5123, 34963), "material": mat_index[mat]}
        triangles += len(mesh.i) // 3
        gltf["meshes"].append({"name": name, "primitives": [prim]})
        node = {"name": name, "mesh": len(gltf["meshes"]) - 1}
        if extras:
            node["extras"] = extras
        gltf["nodes"].append(node)
        gltf["scenes"][0]["nodes"].append(len(gltf["nodes"]) - 1)

    gltf["extensions"] = {"KHR_lights_punctual": {"lights": []}}
    for name, position, colour, intensity in lights:
        gltf["extensions"]["KHR_lights_punctual"]["lights"].append({"name": name, "type": "point", "color": list(colour),
                                                                    "intensity": intensity})
        gltf["nodes"].append({"name": name, "translation": list(position),
                              "extensions": {"KHR_lights_punctual": {"light": len(gltf["extensions"]["KHR_lights_punctual"]["lights"]) - 1}}})
        gltf["scenes"][0]["nodes"].append(len(gltf["nodes"]) - 1)

    gltf["cameras"] = [{"name": "view", "type": "perspective", "perspective": {"yfov": camera["yfov"], "aspectRatio": 4 / 3, "znear": 0.05}}]
    gltf["nodes"].append({"name": "view", "camera": 0, "matrix": look_at_matrix(camera["position"], camera["target"])})
    gltf["scenes"][0]["nodes"].append(len(gltf["nodes"]) - 1)

    for key in ("textures", "images"):
        if not gltf[key]:
            del gltf[key]
    while len(blob) % 4:
        blob.append(0)
    if glb:
        gltf["buffers"] = [{"byteLength": len(blob)}]
        text = json.dumps(gltf, separators=(",", ":")).encode()
        text += b" " * ((4 - len(text) % 4) % 4)
        body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(blob), b"BIN\x00") + bytes(blob)
        with open(os.path.join(out_dir, "scene.glb"), "wb") as f:
            f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
    else:
        gltf["buffers"] = [{"uri": "scene.bin", "byteLength": len(blob)}]
        with open(os.path.join(out_dir, "scene.bin"), "wb") as f:
            f.write(blob)
        with open(os.path.join(out_dir, "scene.gltf"), "w") as f:
            json.dump(gltf, f, indent=1)
    return triangles


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out_dir")
    parser.add_argument("--untextured", action="store_true", help="every texture replaced by its mean colour")
    parser.add_argument("--glb", action="store_true", help="one .glb with its images inside")
    args = parser.parse_args()
    triangles = write_scene(args.out_dir, args.untextured, args.glb)
    print("%s: %d triangles" % (args.out_dir, triangles))


if __name__ == "__main__":
    main()
