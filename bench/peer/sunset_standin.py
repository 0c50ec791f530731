#!/usr/bin/env python3
"""A stand-in for RADIANCE's test/renders/sunset.hdr (a photographed sunset the repository
snapshot lacks; ten of its test scene sets use it): a synthetic evening sky in the same
180-degree fisheye mapping (fisheye.cal's fish_u, fish_v: the view along +y, up +z), so
that crex and rpict render those sets with the same sky. Not a photograph: a warm horizon
under a blue zenith, a glow around the setting sun (sunset_sky.rad's `bigsun`, turned into
the picture's frame by the pattern's -rz 90) and a dark ground.

    python3 bench/peer/sunset_standin.py OUT.hdr [size]

Writes an uncompressed Radiance RGBE picture (no dependencies beyond Python)."""
import argparse
import math


def to_rgbe(r, g, b):
    v = max(r, g, b)
    if v < 1e-32:
        return bytes((0, 0, 0, 0))
    m, e = math.frexp(v)
    f = m * 256.0 / v
    return bytes((int(r * f), int(g * f), int(b * f), e + 128))


def sky(d, sun):
    x, y, z = d
    if z < 0:  # the ground: dark and warm, a little lighter towards the horizon
        k = 0.06 + 0.06 * math.exp(8 * z)
        return (k * 1.2, k, k * 0.8)
    h = 1 - z  # 1 at the horizon, 0 at the zenith
    base = [0.18 + 0.82 * h ** 3, 0.28 + 0.37 * h ** 3, 0.55 - 0.30 * h ** 3]
    cos_sun = max(-1.0, min(1.0, x * sun[0] + y * sun[1] + z * sun[2]))
    glow = math.exp(-math.acos(cos_sun) / 0.35)
    return (base[0] + 1.6 * glow, base[1] + 0.9 * glow, base[2] + 0.35 * glow)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", help="the picture to write (Radiance RGBE)")
    ap.add_argument("size", nargs="?", type=int, default=512, help="its width and height in pixels")
    a = ap.parse_args()
    out, n = a.out, a.size
    # bigsun (-0.9338, -0.35, 0.001) in the world; the picture's frame is the world turned
    # by -90 degrees about z: (x, y) -> (y, -x).
    s = (-0.35, 0.9338, 0.001)
    norm = math.sqrt(sum(c * c for c in s))
    sun = tuple(c / norm for c in s)
    rows = []
    for row in range(n):  # the file's first row is the top (v = 1)
        v = 1 - (row + 0.5) / n
        line = bytearray()
        for col in range(n):
            u = (col + 0.5) / n
            du, dv = u - 0.5, v - 0.5
            r = math.hypot(du, dv)  # fish_Ry: the angle from +y over pi
            theta = math.pi * min(r, 1.0)
            if r > 0:
                ax, az = du / r, dv / r
            else:
                ax, az = 0.0, 0.0
            d = (math.sin(theta) * ax, math.cos(theta), math.sin(theta) * az)
            line += to_rgbe(*sky(d, sun))
        rows.append(bytes(line))
    with open(out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nSOFTWARE=crex bench/peer/sunset_standin.py\n\n")
        f.write(f"-Y {n} +X {n}\n".encode())
        for line in rows:
            f.write(line)


if __name__ == "__main__":
    main()
