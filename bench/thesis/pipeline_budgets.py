#!/usr/bin/env python3
"""Budgets for the stdlib's time-constrained pipelines (issue 34; thesis 4.8, 5.5, 8.3): how close
each lands to its budget once its preview and guidance are scheduled inside it.

  python3 bench/thesis/pipeline_budgets.py [--crex build/release/apps/crex/crex] [--out out/thesis]
        [--pipelines cbtcr,cbtcr_sel,prog_tc,tc_rp] [--scenes cornell,corridor,room]
        [--sizes 384x288,512x384] [--budgets 10%,25%,50%,0.5s,2s] [--repeat 3]

For each pipeline, scene and size: a full render without a budget that saves its profile (cost
per ray, and the stage costs the preview is sized from); then every budget --repeat times with
that profile. A budget below the pipeline's floor is refused before rendering (exit 2) with
the smallest budget it can meet: the table shows the refusal and that figure. Columns: the
budget in seconds, the actual render time (median of the runs), the overshoot (median and the
worst run), the preview's stride and share of the time, and the camera samples left out.
Goal: |overshoot| <= 2 % wherever the budget is feasible. Prints markdown. Not run in CI.
"""
import json
import os
import re
import statistics
import subprocess

from crex_tool import ROOT, arguments, crex

SCENES = {"cornell": "builtin:cornell", "corridor": os.path.join(ROOT, "examples/scenes/corridor/scene.json"),
          "room": os.path.join(ROOT, "examples/scenes/room/scene.json")}


def budgeted(exe, args):
    """(summary, None) for a render, (None, refusal text) for a budget refused with exit 2."""
    r = subprocess.run([exe] + args, capture_output=True, text=True)
    if r.returncode == 2 and "smallest budget" in r.stderr:
        floor = re.search(r"can meet, ([0-9.e+-]+) s", r.stderr)
        return None, f"refused: floor {floor.group(1)} s" if floor else "refused"
    if r.returncode != 0:
        raise SystemExit(f"crex {' '.join(args)} failed ({r.returncode}):\n{r.stderr}")
    return json.loads(r.stdout), None


def main():
    ap = arguments(__doc__)
    ap.add_argument("--pipelines", default="cbtcr,cbtcr_sel,prog_tc,tc_rp")
    ap.add_argument("--scenes", default="cornell,corridor,room")
    ap.add_argument("--sizes", default="384x288,512x384")
    ap.add_argument("--budgets", default="10%,25%,50%,0.5s,2s")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    print("| pipeline | scene | size | full s | budget | budget s | actual s | overshoot % median | worst | preview every | preview % of time | samples left out |")
    print("|---|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    feasible = []
    for size in a.sizes.split(","):
        for scene in a.scenes.split(","):
            for name in a.pipelines.split(","):
                pipe = os.path.join(ROOT, "stdlib/pipelines", name + ".pipe")
                profile = os.path.join(a.out, f"pb_{name}_{scene}_{size}.profile.json")
                img = os.path.join(a.out, f"pb_{name}_{scene}_{size}.exr")
                base = ["run", pipe, "--scene", SCENES[scene], "--size", size, "--seed", "1", "--format", "json", "-q", "-o", img]
                full = json.loads(crex(a.crex, base + ["--no-budget", "--save-profile", profile]))
                for b in a.budgets.split(","):
                    runs, refusal = [], None
                    for _ in range(a.repeat):
                        j, refusal = budgeted(a.crex, base + ["--profile", profile, "--budget", b])
                        if refusal:
                            break
                        runs.append(j)
                    row = f"| {name} | {scene} | {size} | {full['render_seconds']:.3f} | {b} | "
                    if refusal:
                        print(row + f"- | - | {refusal} | - | - | - | - |")
                        continue
                    over = [j["overshoot_percent"] for j in runs]
                    worst = max(over, key=abs)
                    # A run that rendered everything before its budget ended early: nothing to miss.
                    if not all(j.get("camera_samples_left_out", 0) == 0 and j["overshoot_percent"] < 0 for j in runs):
                        feasible.append(worst)
                    med = statistics.median(j["render_seconds"] for j in runs)
                    print(row + f"{runs[0]['budget_seconds']:.3f} | {med:.3f} | {statistics.median(over):+.1f} | {worst:+.1f} | "
                          f"{runs[0].get('preview_stride', 1)} | {statistics.median(j.get('preview_percent_of_time', 0) for j in runs):.0f} | "
                          f"{runs[-1].get('camera_samples_left_out', 0)} |", flush=True)
    if feasible:
        inside = sum(1 for o in feasible if abs(o) <= 2)
        print(f"\nbudgets cut short (not refused, not rendered whole early): {len(feasible)}; worst run within ±2 %: {inside} ({100 * inside / len(feasible):.0f} %); "
              f"largest |overshoot| {max(abs(o) for o in feasible):.1f} %")


if __name__ == "__main__":
    main()
