#!/usr/bin/env python3
"""crex against rpict at rpict's cheapest settings, timed over repeats (issue 40, docs/peer.md).

Renders of a second or less move by up to 45 % from one run to the next on a small machine,
so single runs (peer_table.py) cannot tell 0.31x from 0.36x there. This renders rpict's
cheapest setting (one ray a pixel, and 2x2 filtered down by pfilt) and crex's cheapest curves
(the cache at 64 hemisphere rays a record and 4 shadow rays a hit, at 1, 2 and 4 spp; the
stdlib's lamp_aa at 24 to 128 hemisphere rays a record; the same with the preview's other
edges at half weight) in turn, --repeat times, one thread
each, and prints each point's median seconds, its errors against the committed reference and
the time ratio crex/rpict at equal FLIP, relMSE and RMSE on each of crex's curves. Never in CI.

    python3 bench/peer/cheapest.py --scene diffuse --repeat 5
"""
import argparse
import json
import os
import statistics

import peer_table as P

# lamp_aa's outlines, and the preview's other edges at half their weight (the blocks' and the
# box's outlines, which one sample a pixel also aliases). Chosen on the diffuse box, against
# rpict's 2x2-oversampled cheapest image; the spheres box was held out of that choice.
EDGES_AND_LAMPS = """pipeline edges_and_lamps {
  preselective { crex "(TTMRSGD)*"  spp 1 }
  guidance {
    lamps = edges(emission)
    other = edges(preview)
    m     = importance(lamps 1, other 0.5, op "max")
  }
  selective {
    vary spp       1    .. 8    by m
    vary ic_radius 0.15 .. 0.15 by m
  }
}
"""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=["diffuse", "spheres"], default="diffuse")
    ap.add_argument("--crex", default=os.path.join(P.ROOT, "build/release/apps/crex/crex"))
    ap.add_argument("--radiance", default=os.path.join(P.HERE, ".radiance/bin"), help="folder holding rpict, oconv and pfilt")
    ap.add_argument("--out", default=os.path.join(P.ROOT, "out/peer_cheapest"))
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args()
    a.size, a.rpict_settings = 256, 1
    os.makedirs(a.out, exist_ok=True)
    scene = os.path.join(P.HERE, f"cornell_{a.scene}.rad")
    reference = os.path.join(P.HERE, "refs", f"cornell_{a.scene}_{a.size}.exr")
    crex = {f"ic cheap {s} spp": ["--spp", str(s), "--ic", "--ad", "64", "--shadow-rays", "4"] for s in (1, 2, 4)}
    crex.update({f"lamp_aa ad {ad}": [P.LAMP_AA, "--ad", str(ad), "--shadow-rays", "4"] for ad in (24, 32, 48, 64, 128)})
    edges = os.path.join(a.out, "edges_and_lamps.pipe")
    with open(edges, "w") as f:
        f.write(EDGES_AND_LAMPS)
    crex.update({f"edges and lamps ad {ad}": [edges, "--ad", str(ad), "--shadow-rays", "4"] for ad in (32, 48, 64)})
    runs = {}
    for _ in range(a.repeat):  # in turn, so a slow spell of the machine touches every point alike
        for ladder in ("deep", "deep x2"):
            a.rpict_ladder = ladder
            r = P.render_rpict(a, scene, reference)[0]
            runs.setdefault(f"rpict {r['setting']}", []).append(r)
        for name, how in crex.items():
            out = os.path.join(a.out, f"crex_{a.scene}_{name.replace(' ', '_')}.exr")
            _, res = P.timed([a.crex, "run", *how, "--scene", scene, "--size", f"{a.size}x{a.size}", "--threads", "1", "-o", out,
                              "--format", "json"])
            runs.setdefault(name, []).append(P.row(json.loads(res.stdout)["render_seconds"], name, P.score(a.crex, out, reference), name))
    points = {}
    for name, rs in runs.items():
        seconds = [r["seconds"] for r in rs]
        points[name] = {**rs[-1], "seconds": statistics.median(seconds), "all_seconds": seconds}
        print(f"{name:34s} median {points[name]['seconds']:.3f} s of {', '.join(f'{s:.3f}' for s in seconds)}; "
              + ", ".join(f"{m} {points[name][m]:.4g}" for m in P.METRICS))
    curves = {c: [p for k, p in points.items() if k.startswith(c)] for c in ("ic cheap", "lamp_aa", "edges and lamps")}
    print("\n| rpict setting | s | " + " | ".join(f"crex/rpict at equal {m}" for m in P.METRICS) + " |")
    print("|---|---:|" + "---|" * len(P.METRICS))
    for name, p in points.items():
        if not name.startswith("rpict"):
            continue
        cells = []
        for m in P.METRICS:
            found = [(t, c) for c, curve in curves.items() if (t := P.time_at(curve, m, p[m]))]
            (best, which) = min(found) if found else (None, None)
            cells.append(f"{best[1]}{P.ratio(best[0] / p['seconds'])}x ({which})" if best else "not reached")
        print(f"| {name[len('rpict '):]} | {p['seconds']:.2f} | " + " | ".join(cells) + " |")
    with open(os.path.join(a.out, f"cheapest_{a.scene}.json"), "w") as f:
        json.dump(points, f, indent=2)


if __name__ == "__main__":
    main()
