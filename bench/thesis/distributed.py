#!/usr/bin/env python3
"""Distributed rendering (issue 19; thesis chapter 6): `mpirun -np N crex run` against one
process, on the Cornell box and the corridor with the irradiance cache on.

  python3 bench/thesis/distributed.py [--crex build/release/apps/crex/crex] [--out out/thesis]
        [--ranks 1,2,4] [--spp 16] [--repeat 3] [--size 256x256]

For each scene and rank count (1 = a plain `crex run`): the wall time of the whole command
(median of --repeat), the irradiance records computed over all ranks (with --ic-share none each
rank fills its own cache, so records grow with the ranks: the thesis's measure of what sharing
the cache saves), the slowest rank's render time, the idle share (1 - rank 0's render time / the slowest
rank's: how long rank 0 waited at the last exchange), the speed-up over one process, and FLIP
against the one-process image. These are plain `--ic` runs, on which --ic-share broadcast (records
exchanged after a pipeline's preview and rounds) and none do the same; the central and
component-based modes and broadcast per pass are rows to come. Note the machine's cores: ranks beyond
them share cores (--oversubscribe). Prints a markdown table. Not run in CI.
"""
import json
import os
import re
import statistics
import subprocess
import sys
import time

from crex_tool import ROOT, SCENES, arguments, crex

MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe"]


def run(cmd):
    t = time.perf_counter()
    r = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    return wall, r.stdout, r.stderr


def main():
    ap = arguments(__doc__)
    ap.add_argument("--ranks", default="1,2,4")
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--size", default="256x256")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    print(f"machine: {os.cpu_count()} cores; {a.size}, {a.spp} spp, `--ic`, no sharing mid-render, median of {a.repeat}\n")
    print("| scene | ranks | wall s | slowest rank s | idle % | records (all ranks) | speed-up | FLIP vs 1 process |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for name, scene, _ in SCENES:
        base_img = os.path.join(a.out, f"{name}_dist_1.exr")
        base_wall = None
        for n in [int(r) for r in a.ranks.split(",")]:
            img = os.path.join(a.out, f"{name}_dist_{n}.exr")
            args = ["run", "--scene", scene, "--size", a.size, "--spp", str(a.spp), "--ic", "-o", img, "--format", "json"]
            walls, slowest, idle, records = [], [], [], []
            for _ in range(a.repeat):
                if n == 1:
                    wall, out, err = run([a.crex] + args)
                    j = json.loads(out)
                    walls.append(wall)
                    slowest.append(j["render_seconds"])
                    idle.append(0.0)
                    records.append(j["irradiance_cache"]["records_made"])
                    continue
                wall, out, err = run(MPIRUN + ["-np", str(n), a.crex] + args)
                m = re.search(r"(\d+) rays and (\d+) irradiance records over all ranks, the slowest rank ([0-9.]+) s", err)
                if not m:
                    sys.exit(f"no distributed note in:\n{err}")
                j = json.loads(out)
                walls.append(wall)
                slowest.append(float(m.group(3)))
                records.append(int(m.group(2)))
                idle.append(100 * (1 - j["render_seconds"] / float(m.group(3))))  # rank 0 against the slowest
            w = statistics.median(walls)
            if n == 1:
                base_wall = w
            flip = json.loads(crex(a.crex, ["compare", img, base_img, "--format", "json"]))["flip"]
            print(f"| {name} | {n} | {w:.2f} | {statistics.median(slowest):.2f} | {statistics.median(idle):.0f} | "
                  f"{statistics.median(records):.0f} | {base_wall / w:.2f} | {flip:.4f} |")


if __name__ == "__main__":
    main()
