#!/usr/bin/env python3
"""Distributed rendering (issue 19; thesis chapter 6, figures 6.8-6.11): `mpirun -np N crex run`
under each way of sharing the irradiance cache, against one process, on the Cornell box and the
corridor with the cache on.

  python3 bench/thesis/distributed.py [--crex build/release/apps/crex/crex] [--out out/thesis]
        [--ranks 1,2,4] [--modes none,central,broadcast,component] [--size 96x96]
        [--pipeline stdlib/pipelines/adaptive.pipe | --pipeline none --spp 8] [--repeat 1]

The workload is a pipeline with a cache (default adaptive.pipe: a 2-spp preview, then three
rounds of adaptive sampling with ic_radius varied), so broadcast and central have exchange
points mid-render (after the preview, before each round); with --pipeline none it is a plain
`crex run --ic --spp S`, where broadcast exchanges nothing before the end and equals none.
One row per scene, rank count and mode (1 rank: one plain process, no mode):
  wall s      the whole command (median of --repeat), mpirun's start-up included
  render s    the slowest rank's render (a PA rank's: from its first message to the last done)
  records     irradiance records computed over all ranks (loaded ones not counted)
  misses      cache misses over all ranks: lookups (every bounce) not interpolated from
              records at their first lookup, the thesis's measure (figure 6.10)
  idle %      time ranks waited for other ranks in MPI over ranks x the slowest render
  speed-up    one process's render s over this row's
  FLIP        against the one-process image
Ranks beyond the machine's cores share them (--oversubscribe): on 2 cores, 4 ranks cannot be
faster than 2, and what the rows show is the work (records, misses) and the waiting.
Prints a markdown table. Not run in CI.
"""
import json
import os
import re
import statistics
import subprocess
import sys
import time

from crex_tool import ROOT, SCENES, arguments, crex

# --bind-to none: by default Open MPI binds each of 2 ranks to one core, so a rank's TBB threads
# get one core even while the other rank waits; component's PA and PR take turns, and bound they
# each ran at half speed (Cornell 96x96 adaptive: 1.63 s bound, 1.01 s unbound).
MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none"]
NOTE = re.compile(r"(\d+) rays and (\d+) irradiance records over all ranks, the slowest rank ([0-9.]+) s; "
                  r"(\d+) cache misses over all ranks; idle ([0-9.]+) %")


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    return wall, r.stdout, r.stderr


def measure(a, n, mode, args):
    """(wall, render s, records, misses, idle %) of one run."""
    if n == 1:
        wall, out, _ = run([a.crex] + args)
        j = json.loads(out)
        ic = j["irradiance_cache"]
        return wall, j["render_seconds"], ic["records_made"], ic["lookups"] - ic["interpolated_at_first_lookup"], 0.0
    wall, _, err = run(MPIRUN + ["-np", str(n), a.crex] + args + ["--ic-share", mode])
    m = NOTE.search(err)
    if not m:
        sys.exit(f"no distributed note in:\n{err}")
    return wall, float(m.group(3)), int(m.group(2)), int(m.group(4)), float(m.group(5))


def main():
    ap = arguments(__doc__)
    ap.add_argument("--ranks", default="1,2,4")
    ap.add_argument("--modes", default="none,central,broadcast,component")
    ap.add_argument("--pipeline", default=os.path.join(ROOT, "stdlib/pipelines/adaptive.pipe"))
    ap.add_argument("--spp", type=int, default=8, help="camera samples of --pipeline none")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--size", default="96x96")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    work = "plain `--ic --spp %d`" % a.spp if a.pipeline == "none" else os.path.relpath(a.pipeline, ROOT)
    print(f"machine: {os.cpu_count()} cores; {a.size}, {work}, cache on, median of {a.repeat}\n")
    print("| scene | ranks | --ic-share | wall s | render s | records | misses | idle % | speed-up | FLIP vs 1 process |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, scene, _ in SCENES:
        base = os.path.join(a.out, f"{name}_dist_1.exr")
        base_render = None
        for n in [int(r) for r in a.ranks.split(",")]:
            for mode in (["-"] if n == 1 else a.modes.split(",")):
                img = base if n == 1 else os.path.join(a.out, f"{name}_dist_{n}_{mode}.exr")
                args = ["run"] + ([] if a.pipeline == "none" else [a.pipeline]) + ["--scene", scene, "--size", a.size]
                args += (["--ic", "--spp", str(a.spp)] if a.pipeline == "none" else []) + ["-o", img, "--format", "json"]
                rows = [measure(a, n, mode, args) for _ in range(a.repeat)]
                wall, render, records, misses, idle = (statistics.median(c) for c in zip(*rows))
                if n == 1:
                    base_render = render
                flip = json.loads(crex(a.crex, ["compare", img, base, "--format", "json"]))["flip"]
                print(f"| {name} | {n} | {mode} | {wall:.2f} | {render:.2f} | {records:.0f} | {misses:.0f} | {idle:.0f} | "
                      f"{base_render / render:.2f} | {flip:.4f} |", flush=True)


if __name__ == "__main__":
    main()
