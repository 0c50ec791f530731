#!/usr/bin/env python3
"""tpict / apict / capict (thesis chapter 7, Tables 7.1-7.2): stratified, adaptive and
per-component adaptive sub-sampling at equal error, with and without the irradiance cache.

  python3 bench/thesis/component_sampling.py [--crex build/release/apps/crex/crex]
        [--scenes cornell,room] [--width 128] [--reference-spp N] [--repeat 3] [--out DIR]

For each scene and cache mode (none, --ic), side by side in one run:
  - tpict's curve: the stdlib tpict pipeline's crex, (TTMRSGD)*, at 1, 2, 4, 8, 16, 32, 64 spp
    (stratified: each pixel's Halton sequence);
  - apict and capict as shipped (preview 1 spp, selective 16 spp);
  - FLIP of each against a converged path-traced reference (`crex reference`, cached), and
    the median render time of --repeat runs (the times of a run's passes, not process start).
Speed-ups, two protocols:
  - "16 spp" - the thesis's Tables 7.1-7.2: tpict's time at 16 spp over the renderer's (same
    settings, the renderer's error next to it);
  - "equal FLIP" - the time tpict's curve needs for the renderer's FLIP (log-log between the two
    points around it; "<" when the error is below tpict's best point, then a lower bound) over
    the renderer's time.
Prints markdown tables and writes component_sampling.json to --out. Never in CI.
"""
import json
import os
import statistics
import sys

from crex_tool import ROOT, crex, parser
from selective_table import time_at

# name: (scene, aspect, reference spp: the converged references the other tables use)
SCENES = {"cornell": ("builtin:cornell", 1.0, 8192), "room": (os.path.join(ROOT, "examples/scenes/room/scene.json"), 0.75, 2048),
          "corridor": (os.path.join(ROOT, "examples/scenes/corridor/scene.json"), 0.75, 8192)}
TPICT_SPP = [1, 2, 4, 8, 16, 32, 64]
RENDERERS = ["apict", "capict"]


def arguments():
    ap = parser(__doc__)
    ap.add_argument("--out", default=os.path.join(ROOT, "out/component_sampling"))
    ap.add_argument("--scenes", default="cornell,room")
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--reference-spp", type=int, help="the reference's spp (default: 8192, the room 2048)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    return ap.parse_args()


def timed(a, args, image):
    """Median render seconds of --repeat runs (the last one's image is kept) and its summary."""
    times, j = [], None
    for _ in range(a.repeat):
        j = json.loads(crex(a.crex, ["run"] + args + ["-o", image, "--format", "json", "-q", "--seed", str(a.seed)]))
        times.append(j["render_seconds"])
    return statistics.median(times), j


def flip(a, image, ref):
    return json.loads(crex(a.crex, ["compare", image, ref, "--format", "json", "--metric", "flip"]))["flip"]


def main():
    a = arguments()
    os.makedirs(a.out, exist_ok=True)
    results = {}
    for name in a.scenes.split(","):
        scene, aspect, ref_spp = SCENES[name]
        ref_spp = a.reference_spp or ref_spp
        size = f"{a.width}x{int(round(a.width * aspect))}"
        print(f"[{name}] reference at {ref_spp} spp ...", file=sys.stderr)
        ref = crex(a.crex, ["reference", scene, "--size", size, "--spp", str(ref_spp), "-q"]).strip()
        for ic in [False, True]:
            mode = "irradiance cache" if ic else "no cache"
            cache = ["--ic"] if ic else []
            out = lambda f: os.path.join(a.out, f"{name}_{f}{'_ic' if ic else ''}.exr")  # noqa: E731
            curve = []
            for spp in TPICT_SPP:
                print(f"[{name}, {mode}] tpict {spp} spp ...", file=sys.stderr)
                t, _ = timed(a, ["-e", "(TTMRSGD)*", "--scene", scene, "--size", size, "--spp", str(spp)] + cache, out(f"tpict{spp}"))
                curve.append({"spp": spp, "seconds": t, "flip": flip(a, out(f"tpict{spp}"), ref)})
            t16 = next(c for c in curve if c["spp"] == 16)
            rows = [{"renderer": "tpict", "seconds": t16["seconds"], "flip": t16["flip"]}]
            for r in RENDERERS:
                print(f"[{name}, {mode}] {r} ...", file=sys.stderr)
                pipe = os.path.join(ROOT, "stdlib/pipelines", r + ".pipe")
                t, j = timed(a, [pipe, "--scene", scene, "--size", size] + cache, out(r))
                rows.append({"renderer": r, "seconds": t, "flip": flip(a, out(r), ref),
                             "corners": j.get("component_subsampled_pixels_rendered") or j.get("subsampled_pixels_rendered")})
            for row in rows:
                row["speedup_16spp"] = t16["seconds"] / row["seconds"]
                eq = time_at([(c["seconds"], c["flip"]) for c in curve], row["flip"])
                row["tpict_seconds_at_flip"] = None if eq is None else eq[0]
                row["below_tpict_best"] = None if eq is None else eq[1]
            results.setdefault(name, {"size": size, "reference": ref})[mode] = {"tpict_curve": curve, "rows": rows}
            print_table(name, size, ref_spp, mode, curve, rows)
    with open(os.path.join(a.out, "component_sampling.json"), "w") as f:
        json.dump(results, f, indent=2)


def print_table(name, size, ref_spp, mode, curve, rows):
    print(f"\n### {name} ({size}, {mode}; reference: path traced, {ref_spp} spp)\n")
    print("| renderer | time s | FLIP | 16 spp: speed-up over tpict | equal FLIP: tpict s | equal FLIP: speed-up | corners rendered |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for r in rows:
        eq = r["tpict_seconds_at_flip"]
        su = "slower than tpict's worst" if eq is None else f"{'>' if r['below_tpict_best'] else ''}{eq / r['seconds']:.2f}x"
        print(f"| {r['renderer']} | {r['seconds']:.3f} | {r['flip']:.4f} | {r['speedup_16spp']:.2f}x | "
              f"{'' if eq is None else f'{eq:.3f}'} | {su} | {r.get('corners') or ''} |")
    print("\ntpict curve (spp, s, FLIP): " + ", ".join(f"({c['spp']}, {c['seconds']:.3f}, {c['flip']:.4f})" for c in curve))


if __name__ == "__main__":
    main()
