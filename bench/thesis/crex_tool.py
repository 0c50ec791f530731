"""What the bench/thesis scripts share: running the crex tool and failing loudly."""
import argparse
import math
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DEFAULT_CREX = os.path.join(ROOT, "build/release/apps/crex/crex")
SCENES = [("cornell", "builtin:cornell", "128x128"), ("corridor", os.path.join(ROOT, "examples/scenes/corridor/scene.json"), "128x96")]


def crex(exe, args, env=None):
    """Runs `exe args`; exits the script with crex's stderr if it fails; returns stdout."""
    r = subprocess.run([exe] + args, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        sys.exit(f"crex {' '.join(args)} failed ({r.returncode}):\n{r.stderr}")
    return r.stdout


def gold_time_at(curve, flip):
    """Gold's time at a FLIP value on its (time, FLIP) curve, interpolated log-log between the
    two points around it, extrapolated along the last segment below gold's best; None above
    gold's worst."""
    pts = sorted(curve)
    for (t0, f0), (t1, f1) in zip(pts, pts[1:]):
        if f1 <= flip <= f0 and f0 > f1 > 0:
            a = (math.log(flip) - math.log(f0)) / (math.log(f1) - math.log(f0))
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0)))
    if len(pts) >= 2 and 0 < flip < pts[-1][1] and pts[-2][1] > pts[-1][1] > 0:
        (t0, f0), (t1, f1) = pts[-2], pts[-1]
        slope = (math.log(t1) - math.log(t0)) / (math.log(f1) - math.log(f0))
        return math.exp(math.log(t1) + slope * (math.log(flip) - math.log(f1)))
    return None


def parser(doc):
    """A command line whose --help is the script's docstring, with --crex."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--crex", default=DEFAULT_CREX)
    return ap


def arguments(doc):
    """The options every table script takes: --crex, --out, --reference-spp."""
    ap = parser(doc)
    ap.add_argument("--out", default=os.path.join(ROOT, "out/thesis"))
    ap.add_argument("--reference-spp", type=int, default=256)
    return ap


def numpy_and_crex(script):
    """numpy and crex's Python module (build/release/python), imported when a script needs them
    (--help needs neither); exits with what to do when they are missing."""
    sys.path.insert(0, os.path.join(ROOT, "build/release/python"))
    try:
        import numpy
        import crex as crex_module
    except ImportError as e:  # the module is built for Debian's /usr/bin/python3
        sys.exit(f"{script} needs numpy and crex's Python module ({e}); run it with /usr/bin/python3")
    return numpy, crex_module
