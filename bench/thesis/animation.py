#!/usr/bin/env python3
"""Frames along a camera path (issue 36): what carrying the irradiance cache from frame to frame
buys uniform rendering and stdlib pipelines, in seconds per frame, records made per frame,
flicker and error.

For every configuration the walk is rendered twice, with the cache carried and cold
(--no-carry-cache), each in one `crex run --camera-path ... --format json`; with
--reuse-frames N, the cached configurations once more with frames inheriting the frame
before's light (`crex run --reuse-frames N`, cache carried; its "cold" walk carries no cache
but still inherits). Per configuration:
the first frame's seconds, the mean of the others, their ratio; records made in the first
frame and per later frame; the whole walk carried over cold; the mean flicker (the display
difference from the frame before, warped onto it: docs/animation.md); and FLIP against
path-traced reference frames made every --reference-every frames at --reference-spp.

  python3 bench/thesis/animation.py                      # corridor walk, 160x120, frames 0..9
  python3 bench/thesis/animation.py --size 320x240 --frames 0..59 --reference-every 10

Slow (minutes); never in CI. Timings are this machine's, one run each: ratios within one
configuration are the figures to read.
"""
import json
import os
import statistics

from crex_tool import ROOT, arguments, crex

SCENE = os.path.join(ROOT, "examples/scenes/corridor/scene.json")
PATH = os.path.join(ROOT, "examples/paths/corridor_walk.json")


def main():
    ap = arguments(__doc__)
    ap.add_argument("--size", default="160x120")
    ap.add_argument("--frames", default="0..9", help="FIRST..LAST, as crex run --frames")
    ap.add_argument("--spp", type=int, default=4, help="uniform rendering's samples per pixel")
    ap.add_argument("--pipelines", default="prog_all,adaptive", help="stdlib pipelines, comma-separated")
    ap.add_argument("--reference-every", type=int, default=5, help="a reference frame every N frames")
    ap.add_argument("--reuse-frames", type=int, default=8, help="also each cached configuration with --reuse-frames N (0: not)")
    a = ap.parse_args()
    out = os.path.join(a.out, "animation")
    os.makedirs(out, exist_ok=True)
    first, last = (int(x) for x in a.frames.split(".."))
    common = ["--scene", SCENE, "--camera-path", PATH, "--size", a.size, "--force", "--format", "json", "-q"]

    def walk(name, args, carry=True):
        stem = os.path.join(out, name + ("" if carry else ".cold"))
        text = crex(a.crex, ["run"] + args + common + ["--frames", a.frames, "-o", stem + ".exr"] + ([] if carry else ["--no-carry-cache"]))
        return stem, json.loads(text)

    # References: path traced, one frame at a time (each its own process: any frame can be redone).
    refs = {}
    for f in range(first, last + 1, a.reference_every):
        stem = os.path.join(out, f"reference_spp{a.reference_spp}")
        path = f"{stem}.{f:04d}.exr"
        if not os.path.exists(path):
            crex(a.crex, ["run", "--scene", SCENE, "--camera-path", PATH, "--size", a.size, "--frames", str(f),
                          "--spp", str(a.reference_spp), "-q", "-o", stem + ".exr"])
        refs[f] = path

    configs = [(f"uniform {a.spp} spp, path traced", f"uniform_pt", ["--spp", str(a.spp)]),
               (f"uniform {a.spp} spp, --ic", f"uniform_ic", ["--spp", str(a.spp), "--ic"])]
    configs += [(p, p, [os.path.join(ROOT, "stdlib/pipelines", p + ".pipe")]) for p in a.pipelines.split(",") if p]
    if a.reuse_frames > 0:
        configs += [(f"{label}, --reuse-frames {a.reuse_frames}", f"{name}_reuse", args + ["--reuse-frames", str(a.reuse_frames)])
                    for label, name, args in configs[1:]]

    rows = []
    for label, name, args in configs:
        stem, warm = walk(name, args)
        _, cold = walk(name, args, carry=False)
        frames = [f for f in warm["frames"] if not f["skipped"]]
        rest = frames[1:]
        flips = []
        for f, ref in refs.items():
            j = json.loads(crex(a.crex, ["compare", f"{stem}.{f:04d}.exr", ref, "--metric", "flip", "--format", "json"]))
            flips.append(j["flip"])
        flicker = [f["flicker"]["display_difference"] for f in frames if "flicker" in f]
        cold_seconds = sum(f["seconds"] for f in cold["frames"] if not f["skipped"])
        rows.append({
            "label": label,
            "first_s": frames[0]["seconds"],
            "rest_stages": {k: statistics.mean(f["stages"][k] for f in rest) for k in rest[0]["stages"]} if rest else {},
            "rest_s": statistics.mean(f["seconds"] for f in rest) if rest else float("nan"),
            "first_records": frames[0]["records_made"],
            "rest_records": statistics.mean(f["records_made"] for f in rest) if rest else 0,
            "walk_s": warm["seconds"], "cold_walk_s": cold_seconds,
            "flicker": statistics.mean(flicker) if flicker else float("nan"),
            "cold_flicker": statistics.mean(f["flicker"]["display_difference"] for f in cold["frames"] if "flicker" in f),
            "flip": statistics.mean(flips) if flips else float("nan"),
        })

    print(f"corridor walk, frames {a.frames}, {a.size}; references path traced at {a.reference_spp} spp, frames "
          f"{', '.join(str(f) for f in refs)}\n")
    print("| rendering | first frame s | later frames s (mean) | first / later | records: first, later (mean) "
          "| walk s: carried / cold | carried over cold | flicker: carried / cold | FLIP (reference frames) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['label']} | {r['first_s']:.2f} | {r['rest_s']:.2f} | {r['first_s'] / r['rest_s']:.1f}x "
              f"| {r['first_records']:,}, {r['rest_records']:,.0f} | {r['walk_s']:.1f} / {r['cold_walk_s']:.1f} "
              f"| {r['walk_s'] / r['cold_walk_s']:.2f} | {r['flicker']:.4f} / {r['cold_flicker']:.4f} | {r['flip']:.4f} |")
    with open(os.path.join(out, "animation.json"), "w") as f:
        json.dump(rows, f, indent=2)


if __name__ == "__main__":
    main()
