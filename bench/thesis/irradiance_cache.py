#!/usr/bin/env python3
"""The irradiance cache's speed, as ratios measured in one run, and its reuse over a camera walk.

  python3 bench/thesis/irradiance_cache.py [--crex build/release/apps/crex/crex] [--out out/thesis]

For each scene (Cornell box, corridor):
  * path-traced gold at 1..32 spp: its error-against-time curve (FLIP against a converged
    reference, gold at --reference-spp);
  * gold with the cache (--ic, aa 0.15) at 1, 4 and 16 spp, and sel_aa, prog_all and
    prog_dis_all (their ic_radius drives the cache): time, FLIP, and the speed-up over
    path-traced gold at equal FLIP (gold's time read off its curve, log-log);
  * a camera walk of 5 frames: records made per frame with the cache file carried from frame
    to frame (--ic-file) and without.
The thesis reports 10-14x for prog-dis-all against gold (RADIANCE, VDP); ours is printed next to it.
Not run in CI.
"""
import json
import math
import os

from crex_tool import ROOT, SCENES, arguments, crex, gold_time_at






def main():
    ap = arguments(__doc__)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    env = dict(os.environ, CREX_CACHE=os.path.join(a.out, "cache"))
    for name, scene, size in SCENES:
        ref = crex(a.crex, ["reference", scene, "--size", size, "--spp", str(a.reference_spp), "-q"], env).strip()

        def run(pipe, extra, tag):
            out = os.path.join(a.out, f"ic_{name}_{tag}.exr")
            args = ["run", os.path.join(ROOT, "stdlib/pipelines", pipe + ".pipe"), "--scene", scene, "--size", size, "-o", out,
                    "--format", "json", "-q", "--seed", "1"] + extra
            j = json.loads(crex(a.crex, args, env))
            c = json.loads(crex(a.crex, ["compare", out, ref, "--format", "json", "--metric", "rmse,flip,perr"], env))
            return j, c

        curve = []
        for spp in [1, 2, 4, 8, 16, 32]:
            j, c = run("gold", ["--spp", str(spp)], f"gold{spp}")
            curve.append((j["render_seconds"], c["flip"]))
        rows = []
        for spp in [1, 4, 16]:
            rows.append((f"gold + cache, {spp} spp", *run("gold", ["--spp", str(spp), "--ic"], f"goldic{spp}")))
        for p in ["sel_aa", "prog_all", "prog_dis_all"]:
            rows.append((p, *run(p, [], p)))
        print(f"\n### {name} ({size}; reference gold at {a.reference_spp} spp; cache aa 0.15, ad 256, ab 4)\n")
        print("| render | time s | FLIP | perr % | records | path-traced gold time at equal FLIP | speed-up |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for label, j, c in rows:
            t = j["render_seconds"]
            g = gold_time_at(curve, c["flip"])
            recs = j.get("irradiance_cache", {}).get("records", "")
            print(f"| {label} | {t:.3f} | {c['flip']:.4f} | {c['perr']:.1f} | {recs} | "
                  f"{'outside the curve' if g is None else f'{g:.3f}'} | {'' if g is None else f'{g / t:.2f}x'} |")
        print("\npath-traced gold (time s, FLIP): " + ", ".join(f"({t:.3f}, {f:.4f})" for t, f in curve))
        print("thesis, prog-dis-all against gold: 10-14x at a VDP error of 2-4 % of pixels (not comparable with FLIP/perr)")

        # Camera walk: five frames, the camera stepping forward along its view by 2 % of the
        # scene's size per frame.
        base_json = os.path.join(a.out, f"walk_{name}.json")
        crex(a.crex, ["scene-info", scene, "--export-json", base_json], env)
        with open(base_json) as f:
            text = f.read()
        doc = json.loads(text)
        cam = doc["camera"]
        lo = [min(v[i] for s in doc["shapes"] for v in s.get("vertices", [[0, 0, 0]])) for i in range(3)]
        hi = [max(v[i] for s in doc["shapes"] for v in s.get("vertices", [[0, 0, 0]])) for i in range(3)]
        step = 0.02 * max(h - l for h, l in zip(hi, lo))
        d = cam["direction"]
        norm = math.sqrt(sum(x * x for x in d))
        fwd = [x / norm for x in d]
        cache_file = os.path.join(a.out, f"walk_{name}.cache.json")
        if os.path.exists(cache_file):
            os.remove(cache_file)
        print(f"\ncamera walk on {name}: records made per frame (the camera steps {step:.3f} units forward per frame)\n")
        print("| frame | without reuse | with reuse (--ic-file) | time without s | time with s |")
        print("|---:|---:|---:|---:|---:|")
        for frame in range(5):
            doc["camera"] = dict(cam, position=[p + frame * step * f for p, f in zip(cam["position"], fwd)])
            fpath = os.path.join(a.out, f"walk_{name}_{frame}.json")
            with open(fpath, "w") as f:
                json.dump(doc, f)
            common = ["run", "--scene", fpath, "--size", size, "--spp", "4", "--ic", "-q", "--format", "json", "-o",
                      os.path.join(a.out, "walk.exr")]
            fresh = json.loads(crex(a.crex, common, env))
            reused = json.loads(crex(a.crex, common + ["--ic-file", cache_file], env))
            print(f"| {frame} | {fresh['irradiance_cache']['records_made']} | {reused['irradiance_cache']['records_made']} | "
                  f"{fresh['render_seconds']:.3f} | {reused['render_seconds']:.3f} |")


if __name__ == "__main__":
    main()
