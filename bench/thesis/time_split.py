#!/usr/bin/env python3
"""Where a render's time goes (issue 32, step 3): for every render of a selective_table.py run
(uniform rendering and each pipeline, and its gold), the time of each stage (preview, guidance,
selective), of each bin (camera rays with their direct light, D with the irradiance cache's
records and lookups, T R M, G S), of the caustic photon map, and the cache's counts; of the D
bin's first-bounce queries, the time making records (with their deeper bounces), interpolating
and adding the caustic map's estimate (crex run --format json: irradiance_cache.*_seconds).

  python3 bench/thesis/time_split.py out/frame_cornell/selective_table.json [more.json ...]
        [--renders uniform4_ic,prog_dis_all,...]

A render's bins are measured in its first run; the shares are of that run's time and are shown
in seconds of its median time over the table's interleaved runs. Never in CI.
"""
import argparse
import json
import os

BINS = ["camera", "D", "T", "R", "M", "G", "S"]


def arguments():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("tables", nargs="+", help="selective_table.json files")
    ap.add_argument("--renders", default=None, help="only these renders (names as in the first column), comma-separated")
    return ap.parse_args()


def uniform_name(u):
    if not u["ic"]:
        return f"uniform{u['spp']}"
    return f"uniform{u['spp']}_ic" + ("" if u["ad"] == 256 else f"_ad{u['ad']}") + ("" if u.get("aa", 0.15) == 0.15 else f"_aa{u['aa']}")


def renders(entry):
    for u in entry["uniform"]:
        if "profile" in u:
            yield uniform_name(u), u["profile"]
    for r in entry["rows"]:
        if "profile" in r:
            yield r["pipeline"], r["profile"]
            yield r["pipeline"] + " (gold)", r["gold_profile"]


def row(name, p):
    first = p["times"][0] if p.get("times") else p["render_seconds"]
    scale = p["render_seconds"] / first if first > 0 else 1.0  # shares of the first run, in seconds of the median
    comp = p["components"]
    sec = {b: comp.get(b, {}).get("seconds", 0.0) or 0.0 for b in BINS}
    ic = p.get("irradiance_cache", {}) or {}
    st = p.get("stages", {}) or {}
    caustic = ic.get("caustic_map_seconds", 0.0) or 0.0
    other = first - sum(sec.values()) - caustic
    records = ic.get("records_made", ic.get("records", 0))
    rec = f"{ic['preview_records']:,} / {ic['selective_records']:,}" if "preview_records" in ic else f"{records:,}" if ic else "-"
    fmt = lambda v: f"{v * scale:.2f}"  # noqa: E731
    stages = " / ".join(f"{st[k] * scale:.2f}" for k in ("preview_seconds", "guidance_seconds", "selective_seconds") if k in st) or "-"
    d_split = (f"{fmt(ic['record_seconds'])} / {fmt(ic['lookup_seconds'])} / {fmt(ic['caustic_lookup_seconds'])}"
               if "record_seconds" in ic else "-")
    return (f"| {name} | {p['render_seconds']:.2f} | {stages} | {fmt(caustic)} | {fmt(sec['camera'])} | {fmt(sec['D'])} "
            f"({100 * sec['D'] / first:.0f} %) | {d_split} | {fmt(sec['T'] + sec['R'] + sec['M'])} | {fmt(sec['G'] + sec['S'])} | {fmt(other)} | "
            f"{rec} | {ic.get('lookups', 0) / 1e6:.2f} | {ic.get('hemisphere_rays', 0) / 1e6:.1f} | "
            f"{comp.get('camera', {}).get('rays', 0) / 1e6:.2f} | {comp.get('camera', {}).get('shadow_rays', 0) / 1e6:.2f} |")


def main():
    a = arguments()
    wanted = set(a.renders.split(",")) if a.renders else None
    for path in a.tables:
        with open(path) as f:
            results = json.load(f)
        for scene, entry in results.items():
            print(f"\n#### {scene} ({entry['size']}; {os.path.dirname(path)})\n")
            print("| render | s (median) | preview / guidance / selective s | caustic map s | camera bin s | D bin s (share) "
                  "| of D: records / lookups / caustic lookups s | T+R+M s | G+S s | rest s | records (preview / selective) | lookups M "
                  "| hemisphere rays M | camera samples M | camera-hit shadow rays M |")
            print("|---|---:|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|")
            for name, p in renders(entry):
                if wanted is None or name in wanted:
                    print(row(name, p))


if __name__ == "__main__":
    main()
