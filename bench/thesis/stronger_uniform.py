#!/usr/bin/env python3
"""Is the issue's uniform curve the best uniform rendering? Speed-ups of selective_table.py's
pipelines again, against an envelope that also holds uniform rendering with more shadow rays.

  python3 bench/thesis/stronger_uniform.py [--table out/thesis/selective_table.json]
        [--scenes cornell] [--shadow-rays 8] [--spp 1,2,3,4,6,8,12,16] [--repeat 3]

Issue 14's uniform curve is `crex run --spp k` with and without --ic at one shadow ray per
hit. With the cache, camera samples are cheap beside the records, and one shadow ray per
sample leaves the direct light grainy: `--shadow-rays 8` costs little and lowers the error a
lot. A pipeline that beats the issue's curve may only be beating that grain. This renders
`crex run --ic --shadow-rays N --spp k` (median time of --repeat runs, fixed seed) on the
table's scenes and prints each pipeline's equal-FLIP and equal-aFLIP speed-up against the
issue's curve and against the envelope with these points added. Never in CI.
"""
import json
import os
import statistics

from crex_tool import ROOT, crex, parser
from selective_table import SCENES, compare, curve_of, speedup, time_at


def arguments():
    ap = parser(__doc__)
    ap.add_argument("--table", default=os.path.join(ROOT, "out/thesis/selective_table.json"))
    ap.add_argument("--scenes", default="cornell")
    ap.add_argument("--shadow-rays", type=int, default=8)
    ap.add_argument("--spp", default="1,2,3,4,6,8,12,16")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=3)
    return ap.parse_args()


def main():
    a = arguments()
    with open(a.table) as f:
        table = json.load(f)
    out_dir = os.path.dirname(os.path.abspath(a.table))
    for name in a.scenes.split(","):
        entry = table[name]
        scene, ref, size = SCENES[name][0], entry["reference"], entry["size"]
        extra = []
        for spp in [int(s) for s in a.spp.split(",")]:
            img = os.path.join(out_dir, f"{name}_uniform{spp}_ic_sr{a.shadow_rays}.exr")
            args = ["run", "--scene", scene, "--size", size, "--spp", str(spp), "--ic", "--shadow-rays", str(a.shadow_rays),
                    "-o", img, "--format", "json", "-q", "--seed", str(a.seed)]
            seconds = statistics.median(json.loads(crex(a.crex, args))["render_seconds"] for _ in range(max(1, a.repeat)))
            extra.append({"spp": spp, "ic": True, "ad": f"256 sr{a.shadow_rays}", "seconds": seconds, "image": img,
                          **compare(a, img, ref, "saliency")})
        print(f"\n### {name} ({size}): uniform with `--ic --shadow-rays {a.shadow_rays}` added to the envelope\n")
        print("| pipeline | time s | FLIP | speed-up: issue's curve | with the new points | aFLIP | weights "
              "| speed-up: issue's curve | with the new points |")
        print("|---|---:|---:|---:|---:|---:|---|---:|---:|")
        base = entry["uniform"]
        for r in entry["rows"]:
            t, c = r["seconds"], r["vs_reference"]
            if r["attention"] == "saliency":
                extra_a = extra
            else:  # the task map the table weighed this pipeline's aFLIP with
                task = os.path.join(out_dir, f"{name}_{r['pipeline']}_maps", "map_task.png")
                extra_a = [{**u, "aflip": compare(a, u["image"], ref, task)["aflip"]} for u in extra]
                base_a = [{**u, "aflip": compare(a, u["image"], ref, task)["aflip"]} for u in base]
            base_a = base if r["attention"] == "saliency" else base_a
            flip = lambda us: [(u["seconds"], u["flip"], curve_of(u)) for u in us]  # noqa: E731
            aflip = lambda us: [(u["seconds"], u["aflip"], curve_of(u)) for u in us]  # noqa: E731
            f_issue, f_all = time_at(flip(base), c["flip"]), time_at(flip(base + extra), c["flip"])
            a_issue, a_all = time_at(aflip(base_a), c["aflip"]), time_at(aflip(base_a + extra_a), c["aflip"])
            print(f"| {r['pipeline']} | {t:.2f} | {c['flip']:.4f} | {speedup(f_issue, t)} | {speedup(f_all, t)} | "
                  f"{c['aflip']:.4f} | {r['attention']} | {speedup(a_issue, t)} | {speedup(a_all, t)} |")
        print(f"\nuniform --ic --shadow-rays {a.shadow_rays} (spp, s, FLIP, aFLIP by saliency): " +
              ", ".join(f"({u['spp']}, {u['seconds']:.2f}, {u['flip']:.4f}, {u['aflip']:.4f})" for u in extra))


if __name__ == "__main__":
    main()
