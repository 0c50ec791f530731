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
# (-ds), eight ambient bounces (with fewer the box loses light: -ab 2 left it 2-6 % dark) and
# the ambient calculation from cheap to near-converged; -ar scaled to this millimetre scene and
# -lw to the ambient divisions. The earlier ladder (-ab 1 and 2) is --rpict-ladder shallow.
DEEP = [
    ("ab 8 aa .4 ad 64", ["-ab", "8", "-aa", ".4", "-ad", "64", "-as", "16", "-ar", "8", "-lw", "4e-3"]),
    ("ab 8 aa .3 ad 128", ["-ab", "8", "-aa", ".3", "-ad", "128", "-as", "32", "-ar", "16", "-lw", "2e-3"]),
    ("ab 8 aa .2 ad 256", ["-ab", "8", "-aa", ".2", "-ad", "256", "-as", "64", "-ar", "32", "-lw", "1e-3"]),
    ("ab 8 aa .15 ad 512", ["-ab", "8", "-aa", ".15", "-ad", "512", "-as", "128", "-ar", "64", "-lw", "5e-4"]),
]
RPICT = {
    "deep": DEEP,
    # rpict traces one ray a pixel: its edges alias, and that is most of its relMSE at every
    # setting above. RADIANCE's own remedy, an image at twice the size filtered down by pfilt
    # (four rays a pixel, averaged): the same ambient settings, oversampled.
    "deep x2": [(f"{name}, 2x2 + pfilt", opts, 2) for name, opts in DEEP[:3]],
    "shallow": [
        ("ab 1 aa .3 ad 256", ["-ab", "1", "-aa", ".3", "-ad", "256", "-as", "128", "-ar", "64", "-lw", "1e-4"]),
        ("ab 2 aa .2 ad 512", ["-ab", "2", "-aa", ".2", "-ad", "512", "-as", "256", "-ar", "128", "-lw", "1e-4"]),
    ],
}

RPICT_COMMON = ["-ps", "1", "-pj", ".9", "-dj", ".7", "-ds", ".15", "-lr", "-10"]
# crex's curves: path tracing; the cache at its defaults; the cache with 64 hemisphere rays a
# record and 4 shadow rays a hit (its cheapest images, against rpict's cheapest settings).
CREX = ([("pt", [], spp) for spp in (4, 16, 64, 256)] + [("ic", ["--ic"], spp) for spp in (1, 4, 16, 64)] +
        [("ic cheap", ["--ic", "--ad", "64", "--shadow-rays", "4"], spp) for spp in (1, 2, 4, 8)])


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
    relmse), log-log between its points, and "" ; or its cheapest point's seconds and "<=" when
    that point is already at or below `value`; None when no point reaches it."""
    pts = sorted(curve)
    if pts and pts[0][key] <= value:
        return pts[0][0], "<="
    for (t0, *e0), (t1, *e1) in zip(pts, pts[1:]):
        a, b = e0[key - 1], e1[key - 1]
        if min(a, b) <= value <= max(a, b) and a != b:
            f = (math.log(value) - math.log(a)) / (math.log(b) - math.log(a))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), ""
    return None


def load_rows(path):
    """The rows of an earlier run's peer_SCENE.json: {curve: [(seconds, flip, relmse, setting)]}."""
    with open(path) as f:
        return {k: [(r["seconds"], r["flip"], r["relmse"], r["setting"]) for r in v] for k, v in json.load(f).items()}


def print_table(rows, curves):
    """The markdown table: each rpict point, and the time crex's curves need for its FLIP and
    its relMSE ("<=": crex's cheapest image is already there)."""
    names = " / ".join(c[len("crex "):] for c in curves)
    print(f"\n| rpict setting | rpict s | FLIP | relMSE | crex s at its FLIP ({names}) | crex/rpict | crex s at its relMSE ({names}) | crex/rpict |")
    print("|---|---:|---:|---:|---|---:|---|---:|")
    for seconds, flip, relmse, name in rows["rpict"]:
        cells = []
        for key, value in ((1, flip), (2, relmse)):
            ts = [time_at([r[:3] for r in rows[k]], key, value) for k in curves]
            known = [t for t in ts if t]
            best = min(known) if known else None
            cells.append((" / ".join(f"{t[1]}{t[0]:.2f}" if t else "-" for t in ts), f"{best[1]}{best[0] / seconds:.2f}x" if best else "-"))
        print(f"| {name} | {seconds:.2f} | {flip:.4f} | {relmse:.4g} | {cells[0][0]} | {cells[0][1]} | {cells[1][0]} | {cells[1][1]} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=["diffuse", "spheres"], default="diffuse")
    ap.add_argument("--crex", default=os.path.join(ROOT, "build/release/apps/crex/crex"))
    ap.add_argument("--radiance", default=os.path.join(HERE, ".radiance/bin"), help="folder holding rpict, oconv, xform and pfilt")
    ap.add_argument("--out", default=os.path.join(ROOT, "out/peer"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--rpict-ladder", choices=sorted(RPICT), default="deep")
    ap.add_argument("--rpict-settings", type=int, default=None, help="the first N of the ladder's settings (the finest take longest)")
    ap.add_argument("--crex-from", metavar="JSON", help="take crex's curves from an earlier run's peer_SCENE.json instead of rendering them")
    ap.add_argument("--table-from", metavar="JSON", help="print the table of an earlier run's peer_SCENE.json, rendering nothing")
    a = ap.parse_args()
    if a.table_from:
        rows = load_rows(a.table_from)
        print_table(rows, [k for k in rows if k != "rpict"])
        return
    os.makedirs(a.out, exist_ok=True)
    scene = os.path.join(HERE, f"cornell_{a.scene}.rad")
    reference = os.path.join(HERE, "refs", f"cornell_{a.scene}_{a.size}.exr")
    env = dict(os.environ, PATH=a.radiance + os.pathsep + os.environ["PATH"])
    octree = os.path.join(a.out, f"{a.scene}.oct")
    with open(octree, "wb") as f:
        subprocess.run([os.path.join(a.radiance, "oconv"), "-f", os.path.basename(scene)], cwd=HERE, env=env, stdout=f, check=True)
    curves = list(dict.fromkeys(f"crex {kind}" for kind, _, _ in CREX))
    rows = {"rpict": [], **{c: [] for c in curves}}
    for name, opts, *over in RPICT[a.rpict_ladder][: a.rpict_settings]:
        k = over[0] if over else 1  # rendered at k times the size, then filtered down by pfilt
        out = os.path.join(a.out, f"rpict_{a.scene}_{name.replace(' ', '_').replace('.', '').replace(',', '')}.hdr")
        t = time.monotonic()
        rpict = subprocess.run([os.path.join(a.radiance, "rpict"), "-vf", os.path.join(HERE, f"cornell_{a.scene}.vf"),
                                "-x", str(k * a.size), "-y", str(k * a.size), *RPICT_COMMON, *opts, octree], env=env,
                               capture_output=True, check=True).stdout
        if k > 1:
            rpict = subprocess.run([os.path.join(a.radiance, "pfilt"), "-1", "-e", "1", "-x", f"/{k}", "-y", f"/{k}"], input=rpict,
                                   env=env, capture_output=True, check=True).stdout
        seconds = time.monotonic() - t
        with open(out, "wb") as f:
            f.write(rpict)
        flip, relmse = score(a.crex, out, reference)
        rows["rpict"].append((seconds, flip, relmse, name))
        print(f"rpict {name:22s} {seconds:8.2f} s  FLIP {flip:.4f}  relMSE {relmse:.4g}", flush=True)
    earlier = {k: v for k, v in load_rows(a.crex_from).items() if k != "rpict"} if a.crex_from else {}
    if earlier:
        curves = list(earlier)
        rows = {"rpict": rows["rpict"], **earlier}
    for kind, flags, spp in [] if earlier else CREX:
        out = os.path.join(a.out, f"crex_{a.scene}_{kind}_{spp}.exr")
        _, r = timed([a.crex, "run", "--scene", scene, "--size", f"{a.size}x{a.size}", "--spp", str(spp), *flags, "--threads", "1",
                      "-o", out, "--format", "json"])
        seconds = json.loads(r.stdout)["render_seconds"]
        flip, relmse = score(a.crex, out, reference)
        rows[f"crex {kind}"].append((seconds, flip, relmse, f"{spp} spp"))
        print(f"crex {kind:8s} {spp:4d} spp {seconds:10.2f} s  FLIP {flip:.4f}  relMSE {relmse:.4g}", flush=True)
    print_table(rows, curves)
    with open(os.path.join(a.out, f"peer_{a.scene}.json"), "w") as f:
        json.dump({k: [dict(zip(("seconds", "flip", "relmse", "setting"), r)) for r in v] for k, v in rows.items()}, f, indent=2)


if __name__ == "__main__":
    main()
