#!/usr/bin/env python3
"""The thesis's comparison, on our scenes, from one run: every runnable stdlib pipeline against
gold, as time and error against a converged reference, and gold's time at the same error.

  python3 bench/thesis/selective_table.py [--crex build/release/apps/crex/crex] [--size 128]
                                          [--reference-spp 256] [--out out/thesis]

For each scene: a reference (gold at --reference-spp), gold at 1, 2, 4, 8, 16 and 32 spp (its
error-against-time curve), then each pipeline at its own settings (max 16 spp, like gold 16).
Pipelines with a budget in % (tc_rp) get it of gold 16's time, from its saved profile.
"Speed-up at equal FLIP" divides gold's time at the pipeline's FLIP (interpolated on the curve,
log-log) by the pipeline's time. Prints a markdown table; writes the images and JSON to --out.
Not run in CI (the reference alone takes minutes).
"""
import json
import os
import sys

from crex_tool import ROOT, SCENES, arguments, crex, gold_time_at

PIPELINES = ["sel_rp", "osd", "sel_edge", "cbr", "sel_st", "prog_rp", "prog_all", "tc_rp", "apict"]




def render(exe, pipe, scene, size, out, extra=()):
    args = ["run", os.path.join(ROOT, "stdlib/pipelines", pipe + ".pipe"), "--scene", scene, "--size", size,
            "-o", out, "--format", "json", "-q", "--seed", "1"] + list(extra)
    return json.loads(crex(exe, args))


def compare(exe, test, ref):
    return json.loads(crex(exe, ["compare", test, ref, "--format", "json"]))




def main():
    a = arguments(__doc__).parse_args()
    os.makedirs(a.out, exist_ok=True)
    results = {}
    for name, scene, size in SCENES:
        ref = os.path.join(a.out, f"{name}_reference.exr")
        print(f"[{name}] reference, gold at {a.reference_spp} spp ...", file=sys.stderr)
        ref_run = render(a.crex, "gold", scene, size, ref, ["--spp", str(a.reference_spp)])
        rows, curve = [], []
        for spp in [1, 2, 4, 8, 16, 32]:
            out = os.path.join(a.out, f"{name}_gold{spp}.exr")
            profile = os.path.join(a.out, f"{name}_gold16.profile.json")
            j = render(a.crex, "gold", scene, size, out, ["--spp", str(spp)] + (["--save-profile", profile] if spp == 16 else []))
            c = compare(a.crex, out, ref)
            curve.append((j["render_seconds"], c["flip"]))
            if spp == 16:
                gold16 = out
                rows.append(("gold (16 spp)", j, c, None))
        for p in PIPELINES:
            out = os.path.join(a.out, f"{name}_{p}.exr")
            print(f"[{name}] {p} ...", file=sys.stderr)
            j = render(a.crex, p, scene, size, out, ["--profile", profile])  # budgets in % are of gold 16
            c = compare(a.crex, out, ref)
            g = compare(a.crex, out, gold16)
            rows.append((p, j, c, g))
        results[name] = {"reference_seconds": ref_run["render_seconds"], "gold_curve": curve,
                         "rows": [{"pipeline": r[0], "run": r[1], "vs_reference": r[2], "vs_gold16": r[3]} for r in rows]}
        gold_t = rows[0][1]["render_seconds"]
        print(f"\n### {name} ({size}; reference: gold at {a.reference_spp} spp, "
              f"{ref_run['render_seconds']:.1f} s)\n")
        print("| pipeline | time s | time / gold16 | preview % of time | RMSE vs ref | FLIP vs ref | perr % | RMSE vs gold16 | gold time at equal FLIP | speed-up at equal FLIP |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for label, j, c, g in rows:
            t = j["render_seconds"]
            eq = gold_time_at(curve, c["flip"])
            pre = j.get("preview_percent_of_time")
            pre_s = "" if pre is None or label.startswith("gold") else f"{pre:.0f}"
            g_s = "" if g is None else f"{g['rmse']:.4f}"
            eq_s = "outside the curve" if eq is None else f"{eq:.3f}"
            up_s = "" if eq is None else f"{eq / t:.2f}x"
            print(f"| {label} | {t:.3f} | {t / gold_t:.2f} | {pre_s} | {c['rmse']:.4f} | {c['flip']:.4f} | {c['perr']:.1f} | "
                  f"{g_s} | {eq_s} | {up_s} |")
        print("\ngold's curve (time s, FLIP): " + ", ".join(f"({t:.3f}, {f:.4f})" for t, f in curve))
    with open(os.path.join(a.out, "selective_table.json"), "w") as f:
        json.dump(results, f, indent=2)


if __name__ == "__main__":
    main()
