#!/usr/bin/env python3
"""Does selective rendering pay? Every runnable stdlib pipeline on the Cornell box, the corridor
and the furnished room, under the two protocols of issue 14, side by side in one run.

  python3 bench/thesis/selective_table.py [--crex build/release/apps/crex/crex] [--width 128 | --size 960x540]
        [--reference-spp 4096] [--pipelines adaptive,prog_dis_all,...] [--scenes cornell,room] [--repeat 3]
        [--uniform-spp 1,2,4,8,16] [--seeds 4] [--out out/thesis]

References: a windowed reference committed under --refs (bench/refs/SCENE_WxH.exr, issue 32)
when there is one for the scene and size: every image is then scored on its windows alone;
else --reference-file SCENE=FILE; else a path-traced `crex reference` of the whole frame at
--reference-spp. With --repeat N every render of the table is made once, then all of them
again, N times (A B A B, so that a change of the machine's load falls on all alike), and the
median time of each is kept. With --seeds N every render is made at N seeds instead (images
beside the first seed's, NAME_s2.exr ...), and its time and errors are the means over them: at
frame size one seed's irradiance records move a 40x40 window's FLIP by up to 20 %.

Thesis protocol: the pipeline against its own gold, `crex run P --uniform max` (every selective
variable at its maximum in every pixel): the time ratio gold / pipeline, and the perr of both
against a converged reference; the pipeline's cost in quality is its perr minus gold's (crex's
gold is stochastic, so a difference from gold itself would count gold's own noise).

Equal-error protocol (what a user feels): the pipeline's error against the converged reference
(a path-traced `crex reference` at --reference-spp); the time plain uniform rendering
(`crex run --spp k`: k = 1, 2, 3, 4, 6, 8, ... 512 without the cache (--uncached-max-spp),
1 .. 128 with --ic at the default 256
hemisphere rays per record and at every other `ad` a listed pipeline sets, and at the default
accuracy --aa 0.15 and the finest a listed pipeline's ic_radius reaches, so a pipeline's quieter
and finer records are uniform rendering's too; at aa 0.3 with 4 shadow rays a hit and every count
a pipeline's shadow_rays ranges end at, so its extra light samples are uniform rendering's too,
and there with 512 hemisphere rays a record as well) needs for the same error on its best curve (the
fastest of them at that error, each interpolated log-log between its own points), divided by the
pipeline's time. Two errors:
  FLIP  - mean LDR-FLIP of the tone-mapped images (`crex compare`);
  aFLIP - attention-weighted FLIP, sum(w FLIP) / sum(w) (`crex compare --attention`): w is the
          pipeline's task map (`task`, from its --maps; the scene's tagged objects with the
          pipeline's foveal falloff) for task pipelines on scenes with tags, else the Itti-Koch
          saliency of the reference as displayed.
Speed-ups above 1 mean the pipeline is faster at equal error; "<" marks errors below uniform's
best point (the speed-up is then at least the figure shown).

Prints markdown tables; writes images, maps and selective_table.json to --out. Never in CI.
"""
import json
import math
import os
import statistics
import subprocess
import sys

from crex_tool import ROOT, crex, parser

DEFAULT_PIPELINES = ["adaptive", "prog_dis_all", "prog_all", "prog_rp", "sel_rp", "sel_edge", "sel_st", "sel_task", "osd", "cbr", "apict", "capict",
                     "tpict"]
SCENES = {"cornell": ("builtin:cornell", 1.0), "corridor": (os.path.join(ROOT, "examples/scenes/corridor/scene.json"), 0.75),
          "room": (os.path.join(ROOT, "examples/scenes/room/scene.json"), 0.75),
          # The thesis's Mist Cornell (issue 18): run with --scenes mist --pipelines prog_dis_all,prog_dis_media.
          "mist": (os.path.join(ROOT, "examples/scenes/mist/scene.json"), 1.0),
          # The textured living room (issue 33, docs/textures.md), written by the build.
          "living_room": (os.path.join(ROOT, "build/release/examples/scenes/living_room/scene.gltf"), 0.75)}
# Steps of about 1.4x, not 2x: between powers of two the log-log interpolation of a sparse
# curve overstated uniform's time (capict on the corridor sat between 8 and 16 spp).
UNIFORM_SPP = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 128]
# Path tracing goes on where the cache's bias flattens its curve: a pipeline below uniform's
# 128-spp error is then measured, not bounded (--uncached-max-spp 128 leaves them out).
UNCACHED_EXTRA_SPP = [256, 512]
DEFAULT_AD = 256
DEFAULT_AA = 0.15
DEFAULT_SHADOW_RAYS = 1
# Uniform rendering at its best settings measured at 960x540 (docs/selective-payoff.md):
BEST_AA = 0.3           # accuracy
BEST_SHADOW_RAYS = 4    # shadow rays a hit
QUIET_AD = 512          # hemisphere rays a record


def arguments():
    ap = parser(__doc__)
    ap.add_argument("--out", default=os.path.join(ROOT, "out/thesis"))
    ap.add_argument("--width", type=int, default=128)
    ap.add_argument("--size", default=None, metavar="WxH",
                    help="the frame size for every scene (instead of --width and each scene's aspect), e.g. 960x540")
    ap.add_argument("--refs", default=os.path.join(ROOT, "bench/refs"),
                    help="where windowed references SCENE_WxH.exr are looked for (issue 32)")
    ap.add_argument("--uniform-spp", default=None, metavar="LIST",
                    help="the spp of every uniform curve, comma-separated (default: 1..128 in steps of about 1.4x, "
                         "and 256, 512 path traced up to --uncached-max-spp)")
    ap.add_argument("--reference-spp", type=int, default=4096)
    ap.add_argument("--pipelines", default=",".join(DEFAULT_PIPELINES))
    ap.add_argument("--scenes", default="cornell,corridor,room")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--seeds", type=int, default=1,
                    help="render every point at seeds --seed .. --seed + N - 1 and keep the mean time and the mean "
                         "error (at frame size one seed's irradiance records move a window's FLIP by up to 20 %%)")
    ap.add_argument("--uncached-max-spp", type=int, default=512,
                    help="the largest spp of the path-traced curve (its points beyond 128 cost most of the run)")
    ap.add_argument("--reprint", action="store_true",
                    help="print the tables of --out's selective_table.json again (no rendering)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="renders per point; the median render time is kept (the image is the same: fixed seed)")
    ap.add_argument("--extend", action="store_true",
                    help="render the uniform curves --out's selective_table.json lacks, then print the tables again")
    ap.add_argument("--reference-file", action="append", default=[], metavar="SCENE=FILE",
                    help="use FILE, a path-traced reference of --reference-spp samples made elsewhere (e.g. the mean "
                         "of two seeds' `crex reference -o`), for SCENE instead of `crex reference`; repeatable")
    ap.add_argument("--gold-once", action="store_true",
                    help="time each gold (`--uniform max`, the thesis protocol's reference point) once, not --repeat times "
                         "(at frame size the golds cost about as much as everything else)")
    ap.add_argument("--rescore", action="store_true",
                    help="like --reprint, but compare every image of --out's selective_table.json with its reference again "
                         "(after the reference grew by accumulation); no rendering")
    ap.add_argument("--score-later", action="store_true",
                    help="render and time only; compare nothing (the windowed reference under --refs is still being "
                         "accumulated): --rescore --out DIR scores and prints the tables afterwards")
    ap.add_argument("--thesis-only", action="store_true",
                    help="the thesis protocol only (pipeline, gold, reference): no uniform curves, for sizes where "
                         "they cost too much (512x512)")
    a = ap.parse_args()
    # SCENE=FILE pairs, checked once: a typo in the scene or a missing file is an error here,
    # not a silently ignored option or a traceback after the first scene's renders.
    a.reference_files = {}
    for item in a.reference_file:
        name, sep, path = item.partition("=")
        if not sep or name not in SCENES or not os.path.isfile(path):
            ap.error(f"--reference-file {item}: expected SCENE=FILE with SCENE one of {', '.join(SCENES)} and FILE an image")
        a.reference_files[name] = path
    if a.seeds < 1:
        ap.error("--seeds: expected 1 or more")
    if a.seeds > 1 and a.repeat > 1:
        ap.error("--seeds and --repeat: choose one (the seeds' mean time already averages N renders)")
    if a.size is not None:
        w, sep, h = a.size.partition("x")
        if not sep or not w.isdigit() or not h.isdigit() or int(w) < 1 or int(h) < 1:
            ap.error(f"--size {a.size}: expected WIDTHxHEIGHT, e.g. 960x540")
    if a.uniform_spp is not None:
        try:
            a.uniform_spp = sorted({int(v) for v in a.uniform_spp.split(",")})
        except ValueError:
            a.uniform_spp = None
        if not a.uniform_spp or a.uniform_spp[0] < 1:
            ap.error("--uniform-spp: expected whole numbers from 1, comma-separated, e.g. 1,2,4,8,16")
    return a


def run(a, args, retimed=True):
    """One render (the first of its --repeat): its summary. The repeats are made later, all renders
    of the table in turn (retime), so that the load of the machine falls on every point alike."""
    j = json.loads(crex(a.crex, ["run"] + args + ["--format", "json", "-q", "--seed", str(a.seed)]))
    if a.seeds > 1:  # the other seeds' images beside the first's (seeded_path); the mean time
        seconds = [j["render_seconds"]]
        for k in range(1, a.seeds):
            again = json.loads(crex(a.crex, ["run"] + seeded_args(args, k) + ["--format", "json", "-q", "--seed", str(a.seed + k)]))
            seconds.append(again["render_seconds"])
        j["render_seconds"], j["seed_seconds"] = statistics.mean(seconds), seconds
    j["times"] = [j["render_seconds"]]
    if retimed:
        RENDERS.append((args, j))
    return j


RENDERS = []  # (args, summary) of every render of the table, in order, for retime()


def retime(a):
    """Renders every render of the table again, --repeat - 1 times over, in turn (A B C .. A B C ..),
    and sets each one's render_seconds to the median of its times."""
    for round_ in range(1, max(1, a.repeat)):
        print(f"[retime] round {round_ + 1}/{a.repeat}: {len(RENDERS)} renders (load {os.getloadavg()[0]:.2f})", file=sys.stderr)
        for args, j in RENDERS:
            again = json.loads(crex(a.crex, ["run"] + args + ["--format", "json", "-q", "--seed", str(a.seed)]))
            j["times"].append(again["render_seconds"])
    for _, j in RENDERS:
        j["render_seconds"] = statistics.median(j["times"])


def seeded_path(path, k):
    """Where seed --seed + k's image (or maps) of a point goes: beside seed --seed's, "_s2" etc."""
    if k == 0:
        return path
    stem, ext = os.path.splitext(path)
    return f"{stem}_s{k + 1}{ext}"


def seeded_args(args, k):
    """A render's arguments with its -o image and --maps folder moved to seed k's place."""
    out = list(args)
    for i, v in enumerate(out[:-1]):
        if v in ("-o", "--maps"):
            out[i + 1] = seeded_path(out[i + 1], k)
    return out


def compare(a, test, ref, attention):
    """The errors of `test` against `ref`: with --seeds N, the mean over the N seeds' images."""
    scores = []
    for k in range(max(1, a.seeds)):
        j = json.loads(crex(a.crex, ["compare", seeded_path(test, k), ref, "--format", "json", "--metric", "flip,perr",
                                     "--attention", attention]))
        scores.append({"flip": j["flip"], "perr": j["perr"], "aflip": j["aflip"]})
    return {key: statistics.mean(sc[key] for sc in scores) for key in scores[0]}


def envelope(points):
    """The lower envelope of (time, error) points: each kept point has less error than every
    faster one."""
    best, out = math.inf, []
    for t, e in sorted(points):
        if e < best:
            out.append((t, e))
            best = e
    return out


def time_at(points, err):
    """Uniform's time for `err`: points are (time, error) or (time, error, curve); on each
    curve's envelope, log-log between the two points around err (its cheapest point's time when
    err is above its worst); the smallest over the curves. (time, below) with below=True when
    err is under every curve's best (then the time of the best point, a lower bound of the true
    one); None above the worst of every curve. Interpolation stays within a curve: between a
    path-traced point and a cached one no render lies (a hull across them made capict on the
    Cornell box 0.46x)."""
    curves = {}
    for p in points:
        curves.setdefault(p[2] if len(p) > 2 else None, []).append((p[0], p[1]))
    envs = [env for env in (envelope(pts) for pts in curves.values()) if env]
    if not envs or err > max(env[0][1] for env in envs):
        return None
    candidates = []
    for env in envs:
        if err >= env[0][1]:  # this curve's cheapest point is already good enough
            candidates.append(env[0][0])
            continue
        for (t0, e0), (t1, e1) in zip(env, env[1:]):
            if e1 <= err <= e0:
                a = (math.log(err) - math.log(e0)) / (math.log(e1) - math.log(e0))
                candidates.append(math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0))))
                break
    if candidates:
        return min(candidates), False
    best = min((env[-1] for env in envs), key=lambda p: p[1])
    return best[0], True


def curve_of(u):
    """Which uniform curve a point is on: path traced, or the cache at its ad, aa and shadow rays."""
    return "pt" if not u["ic"] else f"ic{u['ad']}aa{u.get('aa', DEFAULT_AA)}sr{u.get('shadow_rays', DEFAULT_SHADOW_RAYS)}"


def reprint(a):
    """The tables again from --out's selective_table.json, with this script's time_at (no
    rendering; task-map aFLIPs of the uniform images are measured again)."""
    with open(os.path.join(a.out, "selective_table.json")) as f:
        results = json.load(f)
    for name, entry in results.items():
        uniform, rows = entry["uniform"], entry["rows"]
        if a.rescore:
            ref = entry["reference"]
            if "windows" in entry.get("reference_text", ""):
                entry["reference_text"] = windowed_reference_text(a, ref)
            for u in uniform:
                u.update(compare(a, u["image"], ref, "saliency"))
            for r in rows:
                out = os.path.join(a.out, f"{name}_{r['pipeline']}")
                weights = out + "_maps/map_task.png" if r["attention"] != "saliency" else "saliency"
                r["vs_reference"], r["gold_vs_reference"] = compare(a, out + ".exr", ref, weights), compare(a, out + "_gold.exr", ref, weights)
        for r in (rows if uniform else []):
            c = r["vs_reference"]
            curve_a = uniform
            if r["attention"] != "saliency":
                task = os.path.join(a.out, f"{name}_{r['pipeline']}_maps", "map_task.png")
                curve_a = [{**u, "aflip": compare(a, u["image"], entry["reference"], task)["aflip"]} for u in uniform]
            r["uniform_seconds_at_flip"] = time_at([(u["seconds"], u["flip"], curve_of(u)) for u in uniform], c["flip"])
            r["uniform_seconds_at_aflip"] = time_at([(u["seconds"], u["aflip"], curve_of(u)) for u in curve_a], c["aflip"])
            r["uniform_seconds_at_gold_flip"] = time_at([(u["seconds"], u["flip"], curve_of(u)) for u in uniform],
                                                        r["gold_vs_reference"]["flip"])
        (print_tables if uniform else print_thesis_table)(name, entry["size"], entry.get("reference_text", f"path traced, {a.reference_spp} spp"),
                                                          uniform, rows)
    if a.rescore:
        with open(os.path.join(a.out, "selective_table.json"), "w") as f:
            json.dump(results, f, indent=2)


def uniform_curves(a, pipelines):
    """(spp, ad, aa, shadow rays) of every uniform render: path traced (ad None), then the
    cache's curves."""
    cached = a.uniform_spp or UNIFORM_SPP
    uncached = a.uniform_spp or UNIFORM_SPP + UNCACHED_EXTRA_SPP
    return [(spp, None, None, DEFAULT_SHADOW_RAYS) for spp in uncached if spp <= a.uncached_max_spp] + [
        (spp, ad, aa, sr) for ad, aa, sr in cache_settings(a, pipelines) for spp in cached]


def render_uniform(a, name, scene, size, ref, curve):
    spp, ad, aa, sr = curve
    tag = "" if ad is None else "_ic" + ("" if ad == DEFAULT_AD else f"_ad{ad}") + ("" if aa == DEFAULT_AA else f"_aa{aa}")
    tag += "" if sr == DEFAULT_SHADOW_RAYS else f"_sr{sr}"
    img = os.path.join(a.out, f"{name}_uniform{spp}{tag}.exr")
    j = run(a, ["--scene", scene, "--size", size, "--spp", str(spp), "--shadow-rays", str(sr), "-o", img] +
            ([] if ad is None else ["--ic", "--ad", str(ad), "--aa", str(aa)]))
    return {"spp": spp, "ic": ad is not None, "ad": ad, "aa": aa, "shadow_rays": sr, "run": j, "image": img,
            **(UNSCORED if a.score_later else compare(a, img, ref, "saliency"))}


UNSCORED = {"flip": None, "perr": None, "aflip": None}


def profile(j):
    """Where a render's time went (bench/thesis/time_split.py prints it): its stages, each bin's
    seconds and rays, and the irradiance cache's counts, from its --format json summary."""
    return {"render_seconds": j["render_seconds"], "times": j["times"], "stages": j.get("stages", {}),
            "components": {k: {f: v.get(f) for f in ("seconds", "rays", "shadow_rays")} for k, v in j["components"].items()},
            "irradiance_cache": j.get("irradiance_cache", {}), "passes": j.get("passes")}


def timed(entries):
    """Replaces each entry's "run" (a render's summary, retimed) by its median "seconds" and its
    profile."""
    for e in entries:
        if "run" in e:
            j = e.pop("run")
            e["seconds"], e["profile"] = j["render_seconds"], profile(j)
    return entries


def extend(a):
    """Renders the uniform curves --out's selective_table.json lacks (the curve set grew since
    it was made), adds them, then reprints: the pipelines are not rendered again."""
    path = os.path.join(a.out, "selective_table.json")
    with open(path) as f:
        results = json.load(f)
    for name, entry in results.items():
        have = {(u["spp"], u["ad"], u.get("aa", DEFAULT_AA if u["ic"] else None), u.get("shadow_rays", DEFAULT_SHADOW_RAYS))
                for u in entry["uniform"]}
        for c in uniform_curves(a, [r["pipeline"] for r in entry["rows"]]):
            if c not in have:
                print(f"[{name}] uniform {c} ...", file=sys.stderr)
                entry["uniform"].append(render_uniform(a, name, SCENES[name][0], entry["size"], entry["reference"], c))
    retime(a)
    for entry in results.values():
        timed(entry["uniform"])
    with open(path, "w") as f:
        json.dump(results, f, indent=2)
    reprint(a)


def windowed_reference_text(a, path):
    """What a windowed reference is, for a table's heading (its samples grow by accumulation)."""
    j = json.loads(crex(a.crex, ["compare", path, path, "--format", "json", "--metric", "rmse"]))
    return (f"path traced, {j['reference_spp']} spp, on the {len(j['windows'])} windows ({j['pixels']} pixels) of "
            f"{os.path.relpath(path, ROOT)}")


def reference_for(a, name, scene, size):
    """The reference a scene is scored against, and its samples: a windowed one under --refs, else
    --reference-file, else a path-traced `crex reference` of the whole frame."""
    windowed = os.path.join(a.refs, f"{name}_{size}.exr")
    if a.score_later:
        return windowed, "path traced, on the windows of " + os.path.relpath(windowed, ROOT) + " (scored later)"
    if name not in a.reference_files and os.path.isfile(windowed):
        text = windowed_reference_text(a, windowed)
        print(f"[{name}] reference: {text}", file=sys.stderr)
        return windowed, text
    print(f"[{name}] reference at {a.reference_spp} spp ...", file=sys.stderr)
    ref = a.reference_files.get(name) or crex(a.crex, ["reference", scene, "--size", size, "--spp", str(a.reference_spp), "-q"]).strip()
    return ref, f"path traced, {a.reference_spp} spp"


def main():
    a = arguments()
    if a.reprint or a.rescore:
        reprint(a)
        return
    if a.extend:
        extend(a)
        return
    os.makedirs(a.out, exist_ok=True)
    results = {}
    pipelines = a.pipelines.split(",")
    for name in a.scenes.split(","):
        scene, aspect = SCENES[name]
        size = a.size or f"{a.width}x{int(round(a.width * aspect))}"
        ref, ref_text = reference_for(a, name, scene, size)
        out = lambda f: os.path.join(a.out, f"{name}_{f}")  # noqa: E731
        curves = [] if a.thesis_only else uniform_curves(a, pipelines)
        uniform = [render_uniform(a, name, scene, size, ref, c) for c in curves]
        rows = []
        for p in pipelines:
            print(f"[{name}] {p} ...", file=sys.stderr)
            pipe = os.path.join(ROOT, "stdlib/pipelines", p + ".pipe")
            img, gold_img, maps = out(f"{p}.exr"), out(f"{p}_gold.exr"), out(f"{p}_maps")
            j = run(a, [pipe, "--scene", scene, "--size", size, "-o", img, "--maps", maps])
            g = run(a, [pipe, "--scene", scene, "--size", size, "-o", gold_img, "--uniform", "max"], retimed=not a.gold_once)
            task = os.path.join(maps, "map_task.png")
            # A task map that is zero everywhere (no tags in the scene) weighs nothing (compare
            # exits 1): saliency then.
            # (Against the image itself when the reference is not there yet: only the map's weights matter.)
            attention = task if os.path.exists(task) and succeeds(a, ["compare", img, img if a.score_later else ref, "--attention", task]) \
                else "saliency"
            if a.score_later:
                c, cg, task_aflip = UNSCORED, UNSCORED, None
            else:
                c, cg = compare(a, img, ref, attention), compare(a, gold_img, ref, attention)
                task_aflip = None if attention == "saliency" else [compare(a, u["image"], ref, attention)["aflip"] for u in uniform]
            rows.append({"pipeline": p, "run": j, "gold_run": g, "vs_reference": c, "gold_vs_reference": cg,
                         "attention": "task map" if attention != "saliency" else "saliency", "stages": j["stages"],
                         "uniform_task_aflip": task_aflip})
        results[name] = {"size": size, "reference": ref, "reference_text": ref_text, "uniform": uniform, "rows": rows}
    retime(a)
    if a.score_later:
        for entry in results.values():
            timed(entry["uniform"])
            for r in entry["rows"]:
                j, g = r.pop("run"), r.pop("gold_run")
                r["seconds"], r["gold_seconds"], r["profile"], r["gold_profile"] = j["render_seconds"], g["render_seconds"], profile(j), profile(g)
                r.pop("uniform_task_aflip")
        with open(os.path.join(a.out, "selective_table.json"), "w") as f:
            json.dump(results, f, indent=2)
        print(f"rendered and timed; scores and tables: --rescore --out {a.out}", file=sys.stderr)
        return
    for name, entry in results.items():
        uniform, rows = timed(entry["uniform"]), entry["rows"]
        flip_curve = [(u["seconds"], u["flip"], curve_of(u)) for u in uniform]
        for r in rows:
            c, cg = r["vs_reference"], r["gold_vs_reference"]
            j, g = r.pop("run"), r.pop("gold_run")
            r["seconds"], r["gold_seconds"], r["profile"], r["gold_profile"] = j["render_seconds"], g["render_seconds"], profile(j), profile(g)
            aflips = r.pop("uniform_task_aflip") or [u["aflip"] for u in uniform]
            r["uniform_seconds_at_flip"] = time_at(flip_curve, c["flip"])
            r["uniform_seconds_at_aflip"] = time_at([(u["seconds"], af, curve_of(u)) for u, af in zip(uniform, aflips)], c["aflip"])
            r["uniform_seconds_at_gold_flip"] = time_at(flip_curve, cg["flip"])
        (print_thesis_table if a.thesis_only else print_tables)(name, entry["size"], entry["reference_text"], uniform, rows)
    print(f"\nload average at the end (1, 5, 15 min): {', '.join(f'{v:.2f}' for v in os.getloadavg())}; "
          + (f"times and errors: the mean of seeds {a.seed}..{a.seed + a.seeds - 1}" if a.seeds > 1
             else f"times: median of {max(1, a.repeat)} interleaved runs"))
    with open(os.path.join(a.out, "selective_table.json"), "w") as f:
        json.dump(results, f, indent=2)


def cache_settings(a, pipelines):
    """The (ad, aa, shadow rays) uniform rendering with the cache is run at: the defaults, every
    `ad` one of the pipelines sets, and every accuracy their ic_radius ranges end at. A pipeline whose
    salient pixels take aa 0.1 gets under the bias floor of uniform's default 0.15, and one
    whose other pixels take 0.5 shows what a coarse cache does for its time: uniform rendering
    at those accuracies must be on the curve too. And 0.3 always: between the default and the
    coarse end it was uniform's best accuracy on the room and on the held-out living room (at 8
    spp 0.0761 FLIP in 44 s there, where 0.15 at 16 spp took 168 s for 0.0877); a table without
    it measured pipelines against a uniform rendering weaker than a user would pick.
    At aa 0.3, also every shadow-ray count the pipelines' shadow_rays ranges end at, and 4
    always: uniform rendering with 4 shadow rays a hit is a setting as plain as --spp, and at
    960x540 it overturned the room's verdict (prog_all 2.43x against 1 shadow ray, 0.46x against
    4 with 512 hemisphere rays: docs/selective-payoff.md). And aa 0.3 with 4 shadow rays and 512
    hemisphere rays a record: at 960x540 quieter records lower what is left past 4 spp at little
    cost (the room at 4 spp: FLIP 0.0441 to 0.0373, about 4 s either way)."""
    ads, accuracies, shadow_rays = {DEFAULT_AD}, {BEST_AA}, {BEST_SHADOW_RAYS}
    for p in pipelines:
        plan = json.loads(crex(a.crex, ["plan", os.path.join(ROOT, "stdlib/pipelines", p + ".pipe"), "--format", "json"]))
        ads.add(plan.get("settings", {}).get("ad", DEFAULT_AD))
        for v in plan.get("variables", []):
            if v["variable"] == "ic_radius":
                accuracies.update((v["from"], v["to"]))
            if v["variable"] == "shadow_rays":
                shadow_rays.update(int(round(x)) for x in (v["from"], v["to"]))
    sr1 = DEFAULT_SHADOW_RAYS
    return ([(ad, DEFAULT_AA, sr1) for ad in sorted(ads)] + [(DEFAULT_AD, aa, sr1) for aa in sorted(accuracies - {DEFAULT_AA})] +
            [(DEFAULT_AD, BEST_AA, sr) for sr in sorted(shadow_rays - {sr1})] + [(QUIET_AD, BEST_AA, BEST_SHADOW_RAYS)])


def succeeds(a, args):
    return subprocess.run([a.crex] + args, capture_output=True).returncode == 0


def speedup(eq, t):
    if eq is None:
        return "slower than uniform's worst"
    tu, below = eq
    return f"{'>' if below else ''}{tu / t:.2f}x"


def print_tables(name, size, ref_text, uniform, rows):
    print(f"\n### {name} ({size}; reference: {ref_text})\n")
    print("| pipeline | time s | thesis: gold s | thesis: gold/pipeline | perr % (gold's) | perr cost, points "
          "| FLIP (gold's) | equal FLIP: uniform s | speed-up | aFLIP | weights | equal aFLIP: uniform s | speed-up "
          "| why below 1x (equal FLIP), or a floor effect |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---|")
    for r in rows:
        c, cg, t = r["vs_reference"], r["gold_vs_reference"], r["seconds"]
        ef, ea = r["uniform_seconds_at_flip"], r["uniform_seconds_at_aflip"]
        print(f"| {r['pipeline']} | {t:.2f} | {r['gold_seconds']:.2f} | {r['gold_seconds'] / t:.2f}x | "
              f"{c['perr']:.1f} ({cg['perr']:.1f}) | {c['perr'] - cg['perr']:+.1f} | {c['flip']:.4f} ({cg['flip']:.4f}) | "
              f"{'' if ef is None else f'{ef[0]:.2f}'} | {speedup(ef, t)} | {c['aflip']:.4f} | {r['attention']} | "
              f"{'' if ea is None else f'{ea[0]:.2f}'} | {speedup(ea, t)} | {why_slower(r, uniform)} |")
    print("\nuniform (spp, cache, s, FLIP, aFLIP by saliency): " + ", ".join(
        f"({u['spp']}{uniform_tag(u)}, {u['seconds']:.2f}, {u['flip']:.4f}, {u['aflip']:.4f})" for u in uniform))


def why_slower(r, uniform):
    """Why a pipeline is slower than uniform rendering at its FLIP, from what was measured:
    its renderer at full quality (gold) against uniform at gold's FLIP, and its preview's time
    against uniform's whole render. At 1x or above, only a floor effect (floor_effect) or nothing."""
    eq, t, c = r["uniform_seconds_at_flip"], r["seconds"], r["vs_reference"]
    floor = floor_effect(r, uniform)
    if eq is not None and eq[0] / t >= 1:
        return floor
    if eq is None:
        worst = max(u["flip"] for u in uniform)
        return f"worse than uniform's cheapest render (FLIP {c['flip']:.3f} > {worst:.3f})"
    reasons = []
    eg, tg = r.get("uniform_seconds_at_gold_flip"), r["gold_seconds"]
    if eg is not None and tg > 1.05 * eg[0]:
        reasons.append(f"its renderer at full quality (gold) is already {tg / eg[0]:.1f}x slower than uniform at gold's FLIP")
    preview = r.get("stages", {}).get("preview_seconds")
    if preview is not None and preview >= 0.5 * eq[0]:
        reasons.append(f"its preview alone takes {preview / eq[0]:.0%} of uniform's time at its FLIP")
    if not reasons and preview is not None:
        reasons.append(f"its selective pass ({t - preview:.2f} s) spends more than uniform's whole render "
                       f"({eq[0]:.2f} s) less its preview ({preview:.2f} s)")
    return "; ".join(reasons + ([floor] if floor else []))


def floor_effect(r, uniform):
    """A cached pipeline whose FLIP is under the best point of every cached uniform curve has its
    uniform time read off the path-traced curve, often many times slower: its speed-up then
    measures the cache's bias floor, not the pipeline (corridor at 960x540: adaptive 3.96x with
    FLIP 0.0430 against a cached floor of 0.0436). Says so, with the speed-up against the best
    cached render, which is what a user of the cache would compare with. Empty otherwise."""
    cached = [u for u in uniform if u["ic"]]
    flip, t = r["vs_reference"]["flip"], r["seconds"]
    if not cached or "irradiance_cache" not in r.get("profile", {}) or flip >= min(u["flip"] for u in cached):
        return ""
    best = min(cached, key=lambda u: (u["flip"], u["seconds"]))
    return (f"floor effect: FLIP {flip:.4f} is under every cached uniform curve (best {best['flip']:.4f}, "
            f"{best['spp']} spp at aa {best.get('aa', DEFAULT_AA)}, {best.get('shadow_rays', DEFAULT_SHADOW_RAYS)} shadow rays, {best['seconds']:.2f} s: {best['seconds'] / t:.2f}x against it)")


def print_thesis_table(name, size, ref_text, uniform, rows):
    """The thesis protocol alone (--thesis-only): with the preview's share of gold's time, the
    speed-up a free selective pass would reach."""
    print(f"\n### {name} ({size}; thesis protocol only; reference: {ref_text})\n")
    print("| pipeline | time s | preview s | gold s | gold/pipeline | bound: gold/preview | perr % (gold's) "
          "| perr cost, points | FLIP (gold's) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        c, cg, t, tg = r["vs_reference"], r["gold_vs_reference"], r["seconds"], r["gold_seconds"]
        preview = r["stages"]["preview_seconds"]
        print(f"| {r['pipeline']} | {t:.2f} | {preview:.2f} | {tg:.2f} | {tg / t:.2f}x | {tg / preview:.1f}x | "
              f"{c['perr']:.1f} ({cg['perr']:.1f}) | {c['perr'] - cg['perr']:+.1f} | {c['flip']:.4f} ({cg['flip']:.4f}) |")


def uniform_tag(u):
    if not u["ic"]:
        return ""
    aa, sr = u.get("aa", DEFAULT_AA), u.get("shadow_rays", DEFAULT_SHADOW_RAYS)
    return (" ic" + ("" if u["ad"] == DEFAULT_AD else f" ad {u['ad']}") + ("" if aa == DEFAULT_AA else f" aa {aa}") +
            ("" if sr == DEFAULT_SHADOW_RAYS else f" sr {sr}"))


if __name__ == "__main__":
    main()
