#!/usr/bin/env python3
"""crex against a peer, rpict or Cycles, on a reference converged beyond both (issue 40, docs/peer.md).

Renders one of the peer scenes of bench/peer/ at 256x256 with the peer at a ladder of settings
and with crex (path tracing, the irradiance cache, and a selective pipeline) at a ladder of
samples, one thread each, scores every image against the committed reference
(bench/peer/refs/) with `crex compare` (FLIP, relMSE and RMSE), and prints each renderer's error
against time and the time ratio crex/peer at equal FLIP, relMSE and RMSE, each curve
interpolated log-log between its own points, with the crex curve that gives it. Never in CI; rpict from bench/peer/build_rpict.sh, Cycles from Debian's
`blender` (bench/peer/cycles_render.py builds the scene crex reads from the RADIANCE file).

    python3 bench/peer/peer_table.py --scene diffuse --radiance bench/peer/.radiance/bin --out out/peer
    python3 bench/peer/peer_table.py --scene diffuse --peer cycles --out out/peer
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
    # The spheres box's caustics (the light through the glass ball and off the mirror ball)
    # reach rpict's diffuse surfaces only from a caustic photon map (mkpmap -apc); the same
    # ambient settings with a map of 250,000 photons, each estimate from 50 of them.
    "deep pm": [(f"{name}, caustic photons", opts, 1, 250000) for name, opts in DEEP[:3]],
    "shallow": [
        ("ab 1 aa .3 ad 256", ["-ab", "1", "-aa", ".3", "-ad", "256", "-as", "128", "-ar", "64", "-lw", "1e-4"]),
        ("ab 2 aa .2 ad 512", ["-ab", "2", "-aa", ".2", "-ad", "512", "-as", "256", "-ar", "128", "-lw", "1e-4"]),
    ],
}

# Cycles' settings: path tracing at a ladder of samples, and its adaptive sampling (samples
# stop where a pixel's noise estimate falls under the threshold) at the same maxima.
CYCLES = {
    "pt": [(f"{spp} spp", ["--spp", str(spp)]) for spp in (16, 64, 256, 1024)],
    "adaptive": [(f"adaptive .01, {spp} spp", ["--spp", str(spp), "--adaptive", "0.01"]) for spp in (64, 256, 1024)],
}

RPICT_COMMON = ["-ps", "1", "-pj", ".9", "-dj", ".7", "-ds", ".15", "-lr", "-10"]
# The stdlib's lamp_aa: the cache at 1 spp, and up to 8 samples a pixel only along the outline
# of the lamp the camera sees (edges of `emission`); its points are hemisphere rays a record.
LAMP_AA = os.path.join(ROOT, "stdlib", "pipelines", "lamp_aa.pipe")
# crex's curves: path tracing; the cache at its defaults; the cache with 64 hemisphere rays a
# record and 4 shadow rays a hit (its cheapest images, against rpict's cheapest settings); the
# cache with 512 hemisphere rays, and also at accuracy 0.1 (its finest images, against Cycles'
# finest: the defaults' FLIP stops near 0.026, the records' own noise and interpolation); the
# stdlib's lamp_aa at 24 to 128 hemisphere rays a record (the cheap cache, its lamp antialiased).
CREX = ([("pt", [], spp) for spp in (4, 16, 64, 256)] + [("ic", ["--ic"], spp) for spp in (1, 4, 16, 64)] +
        [("ic cheap", ["--ic", "--ad", "64", "--shadow-rays", "4"], spp) for spp in (1, 2, 4, 8)] +
        [("ic fine", ["--ic", "--ad", "512"], spp) for spp in (4, 16, 64)] +
        [("ic finest", ["--ic", "--aa", "0.1", "--ad", "512"], spp) for spp in (16, 32, 64)] +
        [("edges", {"ad": 64, "spp": "1 .. %d" % hi}, hi) for hi in (16, 64, 256)] +
        [("edges fine", {"ad": 512, "spp": "4 .. %d" % hi}, hi) for hi in (64, 256, 1024)] +
        [("lamp_aa", [LAMP_AA, "--ad", str(ad), "--shadow-rays", "4"], ad) for ad in (24, 32, 48, 64, 128)])

# crex's selective curves: a pipeline whose samples go where a 1-spp preview has edges (the
# lamp's outline, where a pixel is part lamp and part ceiling, is most of every image's RMSE),
# the cache at its default accuracy for the rest; written to the output folder per point.
EDGE_PIPELINE = """pipeline edges_aa {{
  ad {ad}
  preselective {{ crex "(TTMRSGD)*"  spp 1 }}
  guidance {{ e = edges(preview) }}
  selective {{
    vary spp       {spp} by e
    vary ic_radius 0.15 .. 0.15 by e
  }}
}}
"""


def timed(cmd, **kw):
    t = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        raise SystemExit(f"failed ({r.returncode}): {' '.join(cmd)}\n{r.stderr[-2000:]}")
    return time.monotonic() - t, r


METRICS = ("flip", "relmse", "rmse")


def score(crex, image, reference):
    """The image's errors against the reference, {metric: value}, and the image's path."""
    _, r = timed([crex, "compare", image, reference, "--metric", ",".join(METRICS), "--format", "json"])
    j = json.loads(r.stdout)
    return {"image": image, **{m: j[m] for m in METRICS}}


def row(seconds, setting, errors, tag):
    """One point of a curve, printed as it is made."""
    r = {"seconds": seconds, "setting": setting, **errors}
    print(f"{tag:16s} {setting:32s} {seconds:8.2f} s  FLIP {r['flip']:.4f}  relMSE {r['relmse']:.4g}  RMSE {r['rmse']:.4g}", flush=True)
    return r


def time_at(curve, metric, value):
    """Seconds the curve (rows) needs for `value` of `metric`, log-log between its points, and
    ""; or its cheapest point's seconds and "<=" when that point is already at or below `value`;
    None when no point reaches it."""
    pts = sorted((r["seconds"], r[metric]) for r in curve if metric in r)
    if pts and pts[0][1] <= value:
        return pts[0][0], "<="
    for (t0, a), (t1, b) in zip(pts, pts[1:]):
        if min(a, b) <= value <= max(a, b) and a != b:
            f = (math.log(value) - math.log(a)) / (math.log(b) - math.log(a))
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0))), ""
    return None


PEERS = ("rpict", "cycles")


def load_rows(path):
    """The rows of an earlier run's peer_SCENE.json: {curve: [row]} (runs before RMSE have none)."""
    with open(path) as f:
        return json.load(f)


def ratio(r):
    return f"{r:.2f}" if r >= 0.1 else f"{r:.1g}"


def print_table(rows, curves, peer):
    """The markdown table: each of the peer's points, and the time crex's curves need for its
    FLIP, relMSE and RMSE ("<=": crex's cheapest image is already there)."""
    names = " / ".join(c[len("crex "):] for c in curves)
    metrics = [m for m in METRICS if all(m in r for r in rows[peer])]
    label = {"flip": "FLIP", "relmse": "relMSE", "rmse": "RMSE"}
    print(f"\ncrex s at the peer's error: {names}\n")
    print(f"| {peer} setting | {peer} s | " + " | ".join(label[m] for m in metrics) + " | " +
          " | ".join(f"crex s at its {label[m]} | crex/{peer}" for m in metrics) + " |")
    print("|---|---:|" + "---:|" * len(metrics) + "---|---:|" * len(metrics))
    for p in rows[peer]:
        cells = []
        for m in metrics:
            ts = [time_at(rows[k], m, p[m]) for k in curves]
            known = [(t, k) for t, k in zip(ts, curves) if t]
            (best, fastest) = min(known) if known else (None, None)
            cells += [" / ".join(f"{t[1]}{t[0]:.2f}" if t else "-" for t in ts),
                      f"{best[1]}{ratio(best[0] / p['seconds'])}x ({fastest[len('crex '):]})" if best else "-"]
        print(f"| {p['setting']} | {p['seconds']:.2f} | " + " | ".join(f"{p[m]:.4g}" for m in metrics) + " | " + " | ".join(cells) + " |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=["diffuse", "spheres"], default="diffuse")
    ap.add_argument("--peer", choices=PEERS, default="rpict")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--crex", default=os.path.join(ROOT, "build/release/apps/crex/crex"))
    ap.add_argument("--radiance", default=os.path.join(HERE, ".radiance/bin"), help="folder holding rpict, oconv, xform, pfilt and mkpmap")
    ap.add_argument("--out", default=os.path.join(ROOT, "out/peer"))
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--rpict-ladder", choices=sorted(RPICT), default="deep")
    ap.add_argument("--peer-settings", "--rpict-settings", dest="rpict_settings", type=int, default=None,
                    help="the first N of each of the peer's ladders (the finest take longest)")
    ap.add_argument("--crex-from", metavar="JSON", help="take crex's curves from an earlier run's peer_SCENE.json instead of rendering them")
    ap.add_argument("--peer-from", metavar="JSON", help="take the peer's points from an earlier run's peer_SCENE*.json instead of rendering them")
    ap.add_argument("--table-from", metavar="JSON", help="print the table of an earlier run's peer_SCENE.json, rendering nothing")
    ap.add_argument("--rescore", action="store_true", help="with --table-from: score its images again (against --scene's reference) first")
    a = ap.parse_args()
    if a.table_from:
        rows = load_rows(a.table_from)
        if a.rescore:
            # Scored again from the images the run kept (its rows name them): new metrics, same times.
            reference = os.path.join(HERE, "refs", f"cornell_{a.scene}_{a.size}.exr")
            for curve in rows.values():
                for r in curve:
                    r.update(score(a.crex, r["image"], reference))
            with open(a.table_from, "w") as f:
                json.dump(rows, f, indent=2)
        peer = next(k for k in rows if k in PEERS)
        print_table(rows, [k for k in rows if k not in PEERS], peer)
        return
    os.makedirs(a.out, exist_ok=True)
    scene = os.path.join(HERE, f"cornell_{a.scene}.rad")
    reference = os.path.join(HERE, "refs", f"cornell_{a.scene}_{a.size}.exr")
    if a.peer_from:
        peer_rows = load_rows(a.peer_from)[a.peer]
    else:
        peer_rows = render_cycles(a, scene, reference) if a.peer == "cycles" else render_rpict(a, scene, reference)
    earlier = {k: v for k, v in load_rows(a.crex_from).items() if k not in PEERS} if a.crex_from else {}
    curves = list(earlier) if earlier else list(dict.fromkeys(f"crex {kind}" for kind, _, _ in CREX))
    rows = {a.peer: peer_rows, **(earlier or {c: [] for c in curves})}
    for kind, flags, spp in [] if earlier else CREX:
        out = os.path.join(a.out, f"crex_{a.scene}_{kind.replace(' ', '_')}_{spp}.exr")
        stdlib_pipeline = isinstance(flags, list) and bool(flags) and flags[0].endswith(".pipe")
        if isinstance(flags, dict):  # a pipeline: at most `spp` samples a pixel
            pipe = out[: -len(".exr")] + ".pipe"
            with open(pipe, "w") as f:
                f.write(EDGE_PIPELINE.format(**flags))
            how = [pipe]
        elif stdlib_pipeline:  # its own samples
            how = flags
        else:
            how = ["--spp", str(spp), *flags]
        _, r = timed([a.crex, "run", *how, "--scene", scene, "--size", f"{a.size}x{a.size}", "--threads", "1",
                      "-o", out, "--format", "json"])
        seconds = json.loads(r.stdout)["render_seconds"]
        setting = (f"spp {flags['spp']}, ad {flags['ad']}" if isinstance(flags, dict) else
                   f"ad {spp}" if stdlib_pipeline else f"{spp} spp")
        rows[f"crex {kind}"].append(row(seconds, setting, score(a.crex, out, reference), f"crex {kind}"))
    print_table(rows, curves, a.peer)
    with open(os.path.join(a.out, f"peer_{a.scene}{'' if a.peer == 'rpict' else '_' + a.peer}.json"), "w") as f:
        json.dump(rows, f, indent=2)


def render_cycles(a, scene, reference):
    """Cycles' points: the scene as crex reads it (its JSON export), each setting rendered by
    cycles_render.py in a Blender of its own; the seconds are the render call's alone."""
    scene_json = os.path.join(a.out, f"{a.scene}.json")
    timed([a.crex, "scene-info", scene, "--export-json", scene_json])
    rows = []
    for kind, ladder in CYCLES.items():
        for name, opts in ladder[: a.rpict_settings]:
            out = os.path.join(a.out, f"cycles_{a.scene}_{kind}_{name.split()[-2]}.exr")
            _, r = timed([a.blender, "-b", "--factory-startup", "-noaudio", "-P", os.path.join(HERE, "cycles_render.py"), "--",
                          "--scene", scene_json, "--out", out, "--size", str(a.size), "--threads", "1", *opts])
            seconds = next(json.loads(l[len("CYCLES "):]) for l in r.stdout.splitlines() if l.startswith("CYCLES "))["seconds"]
            rows.append(row(seconds, name, score(a.crex, out, reference), "cycles"))
    return rows


def render_rpict(a, scene, reference):
    """rpict's points: one octree, then each setting of the ladder (oversampled ones filtered
    down by pfilt); the seconds are rpict's and pfilt's wall time."""
    env = dict(os.environ, PATH=a.radiance + os.pathsep + os.environ["PATH"])
    octree = os.path.join(a.out, f"{a.scene}.oct")
    with open(octree, "wb") as f:
        subprocess.run([os.path.join(a.radiance, "oconv"), "-f", os.path.basename(scene)], cwd=HERE, env=env, stdout=f, check=True)
    rows = []
    for name, opts, *over in RPICT[a.rpict_ladder][: a.rpict_settings]:
        k = over[0] if over else 1  # rendered at k times the size, then filtered down by pfilt
        photons = over[1] if len(over) > 1 else 0
        extra, seconds_before = [], 0.0
        if photons:
            # The photon map is made anew for each row and its time counted in the row's: a
            # user rendering one image pays for it once.
            pmap = os.path.join(a.out, f"{a.scene}_caustic.pm")
            if os.path.exists(pmap):
                os.remove(pmap)
            t = time.monotonic()
            subprocess.run([os.path.join(a.radiance, "mkpmap"), "-apc", pmap, str(photons), octree], env=env, capture_output=True,
                           check=True)
            seconds_before = time.monotonic() - t
            extra = ["-ap", pmap, "50"]
        out = os.path.join(a.out, f"rpict_{a.scene}_{name.replace(' ', '_').replace('.', '').replace(',', '')}.hdr")
        t = time.monotonic()
        rpict = subprocess.run([os.path.join(a.radiance, "rpict"), "-vf", os.path.join(HERE, f"cornell_{a.scene}.vf"),
                                "-x", str(k * a.size), "-y", str(k * a.size), *RPICT_COMMON, *opts, *extra, octree], env=env,
                               capture_output=True, check=True).stdout
        if k > 1:
            rpict = subprocess.run([os.path.join(a.radiance, "pfilt"), "-1", "-e", "1", "-x", f"/{k}", "-y", f"/{k}"], input=rpict,
                                   env=env, capture_output=True, check=True).stdout
        seconds = time.monotonic() - t + seconds_before
        with open(out, "wb") as f:
            f.write(rpict)
        rows.append(row(seconds, name, score(a.crex, out, reference), "rpict"))
    return rows


if __name__ == "__main__":
    main()
