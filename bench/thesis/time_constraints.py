#!/usr/bin/env python3
"""Time constraints (issue 15; thesis 5.4-5.6, 8.7-8.8): how close every policy lands to its
budget, and the error it reaches, on every scene; then what taking checkpoints costs.

  python3 bench/thesis/time_constraints.py [--crex build/release/apps/crex/crex] [--out out/thesis]
        [--spp 16] [--repeat 3] [--scenes cornell,corridor,room] [--no-checkpoints]

For each scene: a full render of the component crex (TT[RS]GMD)* without a budget, saving its
profile; then, for each policy (tasks 5.4, batches 5.5, queues 8.3, progressive) and every budget of 5, 10,
25, 50 and 100 % of that time (predicted from the profile) and 0.25, 1 and 5 s, --repeat runs:
the budget, the actual time, the overshoot (median and worst of the runs), the camera samples
left out, the error (FLIP, perr) against a converged reference, and the profile's error per
component. Goal: |overshoot| <= 2 % everywhere the budget can be met (a budget below one sample per pixel cannot), error falling as
the budget grows. Prints markdown tables. Not run in CI.
"""
import json
import os
import statistics

from crex_tool import ROOT, SCENES, arguments, crex

CREX = "(TT[RS]GMD)*"  # gold's components, R and S as one [ ] task



def profile_error(runs):
    """The profile's cost per ray against each run's own, median over the runs (thesis Table 5.4)."""
    keys = sorted({k for j in runs for k in j.get("profile_error_percent", {})}, key=lambda k: "camera DGSTRM".find(k))
    return ", ".join(f"{k} {statistics.median(j['profile_error_percent'][k] for j in runs if k in j.get('profile_error_percent', {})):+.0f}"
                     for k in keys)


def main():
    ap = arguments(__doc__)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scenes", default="cornell,corridor,room")
    ap.add_argument("--no-checkpoints", action="store_true")
    ap.add_argument("--policies", default="tasks,batches,queues,progressive")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    env = dict(os.environ)  # references from the user's crex cache (crex reference keeps them)
    scenes = SCENES + [("room", os.path.join(ROOT, "examples/scenes/room/scene.json"), "128x96")]
    for name, scene, size in [sc for sc in scenes if sc[0] in a.scenes.split(",")]:
        ref = crex(a.crex, ["reference", scene, "--size", size, "--spp", str(a.reference_spp), "-q"], env).strip()
        profile = os.path.join(a.out, f"{name}_tc.profile.json")
        base = ["run", "-e", CREX, "--scene", scene, "--size", size, "--spp", str(a.spp), "--seed", "1", "--format", "json", "-q"]
        full_img = os.path.join(a.out, f"{name}_tc_full.exr")
        full = json.loads(crex(a.crex, base + ["-o", full_img, "--save-profile", profile], env))
        fc = json.loads(crex(a.crex, ["compare", full_img, ref, "--format", "json"], env))
        print(f"\n### {name} ({size}, {a.spp} spp, crex {CREX}): full render {full['render_seconds']:.3f} s, "
              f"FLIP {fc['flip']:.4f}, perr {fc['perr']:.1f} %\n")
        print("| policy | budget | budget s | actual s (median) | overshoot % median | worst | camera samples left out | FLIP | perr % "
              "| profile error % (median per component) |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|")
        budgets = [f"{p}%" for p in (5, 10, 25, 50, 100)] + ["0.25s", "1s", "5s"]
        for policy in a.policies.split(","):
            for b in budgets:
                runs = []
                for r in range(a.repeat):
                    img = os.path.join(a.out, f"{name}_tc_{policy}_{b.replace('%', 'pc')}.exr")
                    j = json.loads(crex(a.crex, base + ["-o", img, "--profile", profile, "--budget", b, "--policy", policy], env))
                    runs.append(j)
                c = json.loads(crex(a.crex, ["compare", img, ref, "--format", "json"], env))
                # A run that rendered everything before its budget has nothing to overshoot with:
                # the median and worst are over the runs the budget cut.
                over = [j["overshoot_percent"] for j in runs
                        if not (j.get("camera_samples_left_out", 0) == 0 and j["overshoot_percent"] < 0)]
                early = not over
                worst = max(over, key=abs) if over else 0
                print(f"| {policy} | {b} | {runs[0]['budget_seconds']:.3f} | {statistics.median(j['render_seconds'] for j in runs):.3f} | "
                      + ("all rendered early | - | " if early else f"{statistics.median(over):+.1f} | {worst:+.1f} | ")
                      + f"{runs[-1].get('camera_samples_left_out', 0)} | "
                      f"{c['flip']:.4f} | {c['perr']:.1f} | {profile_error(runs)} |")
        if a.no_checkpoints:
            continue
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
