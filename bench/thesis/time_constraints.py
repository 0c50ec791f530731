#!/usr/bin/env python3
"""Time-constraint accuracy (thesis 5.4, table of budget vs actual) and the cost of checkpoints.

  python3 bench/thesis/time_constraints.py [--crex build/release/apps/crex/crex] [--out out/thesis]

For each scene: a full render of the component crex (TT[RS]GMD)* without a budget, saving its profile;
then the same crex under budgets of 10, 25 and 50 % of that time (predicted from the profile):
budget, actual time, overshoot %, tasks skipped, and the error (FLIP, perr) against a converged
reference. Then the same full render with and without --reference (checkpoints every 0.1 s
and at step boundaries), nine times each, alternating: the median slowdown is what taking
checkpoints costs. Prints markdown tables. Not run in CI.
"""
import json
import os
import statistics

from crex_tool import ROOT, SCENES, arguments, crex

CREX = "(TT[RS]GMD)*"  # gold's components, R and S as one [ ] task



def main():
    ap = arguments(__doc__)
    ap.add_argument("--spp", type=int, default=16)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    env = dict(os.environ, CREX_CACHE=os.path.join(a.out, "cache"))
    for name, scene, size in SCENES:
        ref = crex(a.crex, ["reference", scene, "--size", size, "--spp", str(a.reference_spp), "-q"], env).strip()
        profile = os.path.join(a.out, f"{name}_tc.profile.json")
        base = ["run", "-e", CREX, "--scene", scene, "--size", size, "--spp", str(a.spp), "--seed", "1", "--format", "json", "-q"]
        full_img = os.path.join(a.out, f"{name}_tc_full.exr")
        full = json.loads(crex(a.crex, base + ["-o", full_img, "--save-profile", profile], env))
        fc = json.loads(crex(a.crex, ["compare", full_img, ref, "--format", "json"], env))
        print(f"\n### {name} ({size}, {a.spp} spp, crex {CREX}): full render {full['render_seconds']:.3f} s, "
              f"FLIP {fc['flip']:.4f}, perr {fc['perr']:.1f} %\n")
        print("| budget | budget s | actual s | overshoot % | of which camera rays s | tasks skipped | FLIP vs ref | perr % |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|")
        for pct in (10, 25, 50):
            img = os.path.join(a.out, f"{name}_tc_{pct}.exr")
            j = json.loads(crex(a.crex, base + ["-o", img, "--profile", profile, "--budget", f"{pct}%"], env))
            c = json.loads(crex(a.crex, ["compare", img, ref, "--format", "json"], env))
            print(f"| {pct} % | {j['budget_seconds']:.3f} | {j['render_seconds']:.3f} | {j['overshoot_percent']:+.1f} | "
                  f"{j['components']['camera']['seconds']:.3f} | {len(j['skipped_tasks'])} | {c['flip']:.4f} | {c['perr']:.1f} |")
        # Checkpoint cost: alternate runs with and without a reference.
        plain, checked, paused, counts = [], [], [], []
        for _ in range(9):
            plain.append(json.loads(crex(a.crex, base + ["-o", os.path.join(a.out, "tmp.exr")], env))["render_seconds"])
            j = json.loads(crex(a.crex, base + ["-o", os.path.join(a.out, "tmp.exr"), "--reference", ref], env))
            checked.append(j["render_seconds"])
            paused.append(j["checkpoint_seconds"])
            counts.append(len(j["error_curve"]))
        mp, mc = statistics.median(plain), statistics.median(checked)
        print(f"\ncheckpoints: {statistics.median(counts):.0f} per render; median render {mp:.3f} s without, {mc:.3f} s with "
              f"({100 * (mc - mp) / mp:+.1f} %); snapshot copies {1e3 * statistics.median(paused):.1f} ms "
              f"({100 * statistics.median(paused) / mc:.2f} % of the render)")


if __name__ == "__main__":
    main()
