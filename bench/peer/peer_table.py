#!/usr/bin/env python3
"""crex against rpict on a reference converged beyond both (issue 40, docs/peer.md).

Renders one of the peer scenes of bench/peer/ at 256x256 with rpict at a ladder of settings
and with crex (path tracing, and the irradiance cache) at a ladder of samples, one thread
each, scores every image against the committed reference (bench/peer/refs/) with
`crex compare` (FLIP and relMSE), and prints each renderer's error against time and the time
ratio crex/rpict at equal FLIP and at equal relMSE, each curve interpolated log-log between
its own points. Never in CI; rpict from bench/peer/build_rpict.sh.

    python3 bench/peer/peer_table.py --scene diffuse --radiance bench/peer/.radiance/bin --out out/peer
"""
import argparse
import json
import math
import os
import subprocess
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# rpict's settings, coarse to fine: jittered pixels and sources (-pj, -dj), subdivided sources
# (-ds), and the ambient calculation from cheap to near-converged.
RPICT = [
    ("ab 1 aa .3 ad 256", ["-ab", "1", "-aa", ".3", "-ad", "256", "-as", "128", "-ar", "64"]),
    ("ab 2 aa .2 ad 512", ["-ab", "2", "-aa", ".2", "-ad", "512", "-as", "256", "-ar", "128"]),
    ("ab 4 aa .15 ad 1024", ["-ab", "4", "-aa", ".15", "-ad", "1024", "-as", "512", "-ar", "256"]),
    ("ab 8 aa .1 ad 2048", ["-ab", "8", "-aa", ".1", "-ad", "2048", "-as", "1024", "-ar", "512"]),
]

RPICT_COMMON = ["-ps", "1", "-pj", ".9", "-dj", ".7", "-ds", ".15", "-lw", "1e-4", "-lr", "-10"]
CREX = [("pt", [], spp) for spp in (4, 16, 64, 256)] + [("ic", ["--ic"], spp) for spp in (1, 4, 16, 64)]


def timed(cmd, **kw):
    t = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise SystemExit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr[-2000:]}")
    return time.monotonic() - t, r


def score(crex, image, reference):
    _, r = timed([crex, "compare", image, reference, "--metric", "flip,relmse", "--format", "json"])
    j = json.loads(r.stdout)
    return j["flip"], j["relmse"]


def time_at(curve, key, value):
    """Seconds the curve [(seconds, flip, relmse)] needs for `value` of metric `key` (1 flip, 2
    relmse), log-log between its points; None beyond its ends."""
    pts = sorted(curve)
    for (t0, *e0), (t1, *e1) in zip(pts, pts[1:]):
        a, b = e0[key - 1], e1[key - 1]
        if min(a, b) <= value <= max(a, b) and a != b:
            f = (math.log(value) - math.log(a)) / (math.log(b) - math.log(a))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=["diffuse", "spheres"], default="diffuse")
    ap.add_argument("--crex", default=os.path.join(ROOT, "build/release/apps/crex/crex"))
    ap.add_argument("--radiance", default=os.path.join(HERE, ".radiance/bin"), help="folder holding rpict, oconv and xform")
    ap.add_argument("--out", default=os.path.join(ROOT, "out/peer"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--rpict-settings", type=int, default=len(RPICT), help="the first N of rpict's settings (the finest take longest)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    scene = os.path.join(HERE, f"cornell_{a.scene}.rad")
    reference = os.path.join(HERE, "refs", f"cornell_{a.scene}_{a.size}.exr")
    env = dict(os.environ, PATH=a.radiance + os.pathsep + os.environ["PATH"])
    octree = os.path.join(a.out, f"{a.scene}.oct")
    with open(octree, "wb") as f:
        subprocess.run([os.path.join(a.radiance, "oconv"), "-f", os.path.basename(scene)], cwd=HERE, env=env, stdout=f, check=True)
    rows = {"rpict": [], "crex pt": [], "crex ic": []}
    for name, opts in RPICT[: a.rpict_settings]:
        out = os.path.join(a.out, f"rpict_{a.scene}_{name.replace(' ', '_').replace('.', '')}.hdr")
        with open(out, "wb") as f:
            t = time.monotonic()
            subprocess.run([os.path.join(a.radiance, "rpict"), "-vf", os.path.join(HERE, f"cornell_{a.scene}.vf"),
                            "-x", str(a.size), "-y", str(a.size), *RPICT_COMMON, *opts, octree], env=env, stdout=f,
                           stderr=subprocess.DEVNULL, check=True)
            seconds = time.monotonic() - t
        flip, relmse = score(a.crex, out, reference)
        rows["rpict"].append((seconds, flip, relmse, name))
        print(f"rpict {name:22s} {seconds:8.2f} s  FLIP {flip:.4f}  relMSE {relmse:.4g}", flush=True)
    for kind, flags, spp in CREX:
        out = os.path.join(a.out, f"crex_{a.scene}_{kind}_{spp}.exr")
        _, r = timed([a.crex, "run", "--scene", scene, "--size", f"{a.size}x{a.size}", "--spp", str(spp), *flags, "--threads", "1",
                      "-o", out, "--format", "json"])
        seconds = json.loads(r.stdout)["render_seconds"]
        flip, relmse = score(a.crex, out, reference)
        rows[f"crex {kind}"].append((seconds, flip, relmse, f"{spp} spp"))
        print(f"crex {kind} {spp:4d} spp {seconds:10.2f} s  FLIP {flip:.4f}  relMSE {relmse:.4g}", flush=True)
    print(f"\n| rpict setting | rpict s | FLIP | relMSE | crex s at its FLIP (pt / ic) | crex/rpict | crex s at its relMSE (pt / ic) | crex/rpict |")
    print("|---|---:|---:|---:|---|---:|---|---:|")
    for seconds, flip, relmse, name in rows["rpict"]:
        cells = []
        for key, value in ((1, flip), (2, relmse)):
            ts = [time_at([r[:3] for r in rows[k]], key, value) for k in ("crex pt", "crex ic")]
            known = [t for t in ts if t]
            best = min(known) if known else None
            cells.append((" / ".join(f"{t:.2f}" if t else "-" for t in ts), f"{best / seconds:.2f}x" if best else "-"))
        print(f"| {name} | {seconds:.2f} | {flip:.4f} | {relmse:.4g} | {cells[0][0]} | {cells[0][1]} | {cells[1][0]} | {cells[1][1]} |")
    with open(os.path.join(a.out, f"peer_{a.scene}.json"), "w") as f:
        json.dump({k: [dict(zip(("seconds", "flip", "relmse", "setting"), r)) for r in v] for k, v in rows.items()}, f, indent=2)


if __name__ == "__main__":
    main()
