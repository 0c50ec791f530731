#!/usr/bin/env python3
"""A stand-in for RADIANCE's test/renders/vase.rtm (the compiled mesh of a scanned vase the
repository snapshot lacks; three of its test scene sets use it): a vase of revolution of
the same size and place (vase.rad moves the mesh by -t 25 5 130 -s .005 -t -4 2.5 1, so its
base centre is at (-25, -5, -130) in mesh units and it stands 46 units, 23 cm, tall), with
texture coordinates around it (u) and up it (v) for vase.rad's picture. Not the scanned vase.

    python3 bench/peer/vase_standin.py vase.obj && obj2mesh vase.obj vase.rtm

obj2mesh is RADIANCE's (bench/peer/build_rpict.sh builds RADIANCE's tools); never in CI."""
import argparse
import math

BASE = (-25.0, -5.0, -130.0)
HEIGHT = 46.0
SEGMENTS, RINGS = 48, 32


def radius(t):
    """The profile: a foot, a belly at a third of the height, a neck and a lip."""
    return 9 + 7 * math.sin(math.pi * min(t / 0.75, 1.0)) ** 1.5 - 3 * max(0.0, (t - 0.7) / 0.3) ** 2 + 2.5 * max(0.0, (t - 0.9) / 0.1) ** 2


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("obj", help="the OBJ file to write")
    out = open(ap.parse_args().obj, "w")
    out.write("# crex bench/peer/vase_standin.py: a stand-in for RADIANCE's vase.rtm\n")
    for i in range(RINGS + 1):
        t = i / RINGS
        for j in range(SEGMENTS + 1):
            phi = 2 * math.pi * j / SEGMENTS
            r = radius(t)
            out.write(f"v {BASE[0] + r * math.cos(phi):.6f} {BASE[1] + r * math.sin(phi):.6f} {BASE[2] + HEIGHT * t:.6f}\n")
            out.write(f"vt {j / SEGMENTS:.6f} {t:.6f}\n")
    w = SEGMENTS + 1
    for i in range(RINGS):
        for j in range(SEGMENTS):
            a, b, c, d = i * w + j + 1, i * w + j + 2, (i + 1) * w + j + 2, (i + 1) * w + j + 1
            # Counter-clockwise seen from outside: the front faces out.
            out.write(f"f {a}/{a} {b}/{b} {c}/{c}\nf {a}/{a} {c}/{c} {d}/{d}\n")
    out.close()


if __name__ == "__main__":
    main()
