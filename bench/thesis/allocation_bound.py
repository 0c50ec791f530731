"""How much any per-pixel allocation of samples could gain over uniform rendering, measured.

  /usr/bin/python3 bench/thesis/allocation_bound.py --scene SCENE [--size 960x540] [--seeds 8]
      [--weights MAP.exr] [--cost RAYS.exr] [--reference REF.exr] [--out DIR] [--reuse] -- [crex run options, e.g.
      --ic --aa 0.3 --shadow-rays 4 --ad 512 --spp 4]

Renders one frame K times with `crex run` and the options after `--`, seeds 1..K, and takes
each pixel's standard deviation sigma_i over the K images as a viewer sees them (the tone map of
docs/pipeline-language.md, through the mean image's exposure). A pixel given n_i samples
instead of n has error sigma_i sqrt(n / n_i). Selective rendering moves samples between pixels
at a fixed total; the best it can do for a metric is the allocation that minimises it (an
oracle that knows every sigma_i and pays nothing to find them), and this script prints how much
less time that oracle needs than uniform rendering for the same error:

  mean |error| (FLIP, flicker: both a mean over pixels of a per-pixel error that grows with
                the noise): n_i ~ sigma_i^(2/3), time ratio (mean sigma / mean(sigma^(2/3))^(3/2))^2
  RMSE:        n_i ~ sigma_i, time ratio mean(sigma^2) / mean(sigma)^2
  weighted by a map w (--weights: a task or saliency map, attention-weighted FLIP): the same
                with w_i sigma_i in place of sigma_i.

Any pipeline that only moves samples between pixels stays under these figures; one that changes
what a sample costs per pixel, or the cache's bias, is not bounded by them. With --reference
(a converged EXR of the whole frame, or a windowed one of bench/refs/, read through its
`crex:windows` with `oiiotool`) it also prints how much of one render's error is noise: mean |image - reference| against the mean
|error| its sigma alone predicts (sqrt(2/pi) sigma). K seeds estimate sigma_i to about
1/sqrt(2(K-1)); that spread widens the sigma distribution, so the printed ratios err high.

Needs numpy and crex's Python module (built beside the tool, build/release/python).
"""
import os
import subprocess
import sys

from crex_tool import ROOT, crex, numpy_and_crex, parser

np = crexpy = None  # numpy and crex's module, imported once the command line is read (--help needs neither)


def import_modules():
    global np, crexpy
    np, crexpy = numpy_and_crex("allocation_bound.py")


def ratios(sigma, cost=None):
    """(mean-|error| ratio, RMSE ratio) of the oracle allocation over uniform, in time.

    With a per-pixel cost c_i of a sample (--cost), the oracle weighs it too: for the mean
    |error| n_i ~ (sigma_i / c_i)^(2/3), ratio mean(sigma)^2 mean(c) / mean(sigma^(2/3) c^(1/3))^3;
    for RMSE n_i ~ sigma_i / sqrt(c_i), ratio mean(sigma^2) mean(c) / mean(sigma sqrt(c))^2.
    Without one every sample costs the same (c = 1)."""
    s = np.maximum(sigma.ravel(), 0.0)
    c = np.ones_like(s) if cost is None else np.maximum(cost.ravel().astype(np.float64), 1e-12)
    if not s.any():
        return 1.0, 1.0
    mean_abs = s.mean() ** 2 * c.mean() / np.mean(s ** (2 / 3) * c ** (1 / 3)) ** 3
    rms = np.mean(s ** 2) * c.mean() / np.mean(s * np.sqrt(c)) ** 2
    return float(mean_abs), float(rms)


def main():
    ap = parser(__doc__)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--weights", help="a map (EXR, first channel) to weight each pixel's error by")
    ap.add_argument("--reference", help="a converged EXR of the same frame (black pixels skipped)")
    ap.add_argument("--reuse", action="store_true",
                    help="take the renders an earlier run left in --out (the same options) instead of rendering them again")
    ap.add_argument("--cost", help="a map (EXR, first channel) of each pixel's cost per sample, e.g. "
                    "rays_per_pixel.exr of `crex run --maps` at the same settings: the oracle then "
                    "also gives fewer samples where they cost more")
    ap.add_argument("--out", default=os.path.join(ROOT, "out/allocation_bound"))
    ap.add_argument("run", nargs="*", help="crex run options after --")
    a = ap.parse_args()
    import_modules()
    os.makedirs(a.out, exist_ok=True)
    images = []
    for k in range(1, a.seeds + 1):
        path = os.path.join(a.out, f"seed{k}.exr")
        if not (a.reuse and os.path.exists(path)):
            crex(a.crex, ["run", "--scene", a.scene, "--size", a.size, "--seed", str(k), "-o", path] + a.run)
        images.append(crexpy.read_image(path).astype(np.float64))
    stack = np.stack(images)
    exposure = crexpy.display_exposure(stack.mean(axis=0))
    shown = crexpy.to_display(stack, exposure)
    sigma = shown.std(axis=0, ddof=1).mean(axis=2)  # per pixel, the mean of the channels'
    mean_abs, rms = ratios(sigma)
    print(f"{a.scene} {a.size}, {a.seeds} seeds of `crex run {' '.join(a.run)}`")
    print(f"  per-pixel display sigma: mean {sigma.mean():.5f}, median {np.median(sigma):.5f}, "
          f"90th percentile {np.percentile(sigma, 90):.5f}, 99th {np.percentile(sigma, 99):.5f}")
    print(f"  oracle allocation over uniform, time at equal error: mean |error| {mean_abs:.3f}x, RMSE {rms:.3f}x")
    cost = None
    if a.cost:
        cost = crexpy.read_image(a.cost).astype(np.float64)[..., 0]
        if cost.shape != sigma.shape:
            sys.exit(f"--cost {a.cost}: {cost.shape[1]}x{cost.shape[0]}, the frame is {a.size}")
        cm, cr = ratios(sigma, cost)
        print(f"  with each pixel's cost from {os.path.basename(a.cost)} (mean {cost.mean():.2f}, "
              f"{cost.min():.0f} to {cost.max():.0f}): mean |error| {cm:.3f}x, RMSE {cr:.3f}x")
    if a.weights:
        w = crexpy.read_image(a.weights).astype(np.float64)[..., 0]
        if w.shape != sigma.shape:
            sys.exit(f"--weights {a.weights}: {w.shape[1]}x{w.shape[0]}, the frame is {a.size}")
        wm, wr = ratios(np.clip(w, 0, None) * sigma)
        print(f"  weighted by {os.path.basename(a.weights)}: mean |error| {wm:.3f}x, RMSE {wr:.3f}x")
        if cost is not None:
            wm, wr = ratios(np.clip(w, 0, None) * sigma, cost)
            print(f"  weighted, with the cost: mean |error| {wm:.3f}x, RMSE {wr:.3f}x")
    if a.reference:
        ref, covered = reference_on_frame(a.reference, sigma.shape)
        err = np.abs(shown - crexpy.to_display(ref, exposure)).mean(axis=3)[:, covered].mean()
        predicted = np.sqrt(2 / np.pi) * sigma[covered].mean()
        print(f"  on the reference's {int(covered.sum())} pixels: mean |image - reference| {err:.5f}, "
              f"noise alone predicts {predicted:.5f} ({100 * predicted / err:.0f} %)")
        wm, wr = ratios(sigma[covered])
        print(f"  the oracle on those pixels alone: mean |error| {wm:.3f}x, RMSE {wr:.3f}x")


def reference_on_frame(path, shape):
    """The reference's pixels placed in the frame, and which pixels it covers: a whole frame
    as it is, a windowed one (bench/refs/) through its `crex:windows` (X,Y,W,H;...), the
    windows side by side in the file."""
    ref = crexpy.read_image(path).astype(np.float64)
    if ref.shape[:2] == shape:
        return ref, np.ones(shape, dtype=bool)
    info = subprocess.run(["oiiotool", "--info", "-v", path], capture_output=True, text=True).stdout
    line = next((l for l in info.splitlines() if "crex:windows:" in l), None)
    if line is None:
        sys.exit(f"--reference {path}: neither the frame's size nor a windowed reference (no crex:windows)")
    frame = np.zeros(shape + (3,))
    covered = np.zeros(shape, dtype=bool)
    column = 0
    for window in line.split("crex:windows:", 1)[1].strip().strip('"').split(";"):
        x, y, w, h = (int(v) for v in window.split(","))
        frame[y:y + h, x:x + w] = ref[:h, column:column + w]
        covered[y:y + h, x:x + w] = True
        column += w
    return frame, covered


if __name__ == "__main__":
    main()
