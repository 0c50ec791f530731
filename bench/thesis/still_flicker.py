"""Where a walk's flicker is: a still camera, frame by frame, pixel by pixel.

  /usr/bin/python3 bench/thesis/still_flicker.py --scene SCENE --path STILL.json [--frames 16]
      [--size 320x240] [--settle 8] [--out DIR] -- [crex run options, e.g. --ic --spp 2
      --shadow-rays 16 --reuse-frames 8]

A camera that does not move sees the same light every frame, so whatever changes between two
frames is the renderer's noise, and no reprojection stands between a pixel and the one before
it. The script renders the path's frames 0..N-1 with `crex run` and the options after `--`
(EXR frames in DIR), sees every frame through the first one's tone map (crex's own, the one
`crex run`'s flicker uses), and takes each pixel's mean absolute change of display luminance
over the frames after the first `--settle` (a history that has filled up). It prints crex's
flicker (the mean over frames of `flicker.display_difference`), the per-pixel mean and how
concentrated it is (the share held by the 1 %, 5 % and 10 % of pixels that change most), and
writes DIR/flicker.png: the last frame beside the per-pixel flicker (white = the 99th
percentile or more). The path is a camera path with one place and view at two times.
"""
import json
import os
import subprocess
import sys

from crex_tool import crex, numpy_and_crex, parser

np = crexpy = None  # numpy and crex's module, imported once the command line is read (--help needs neither)


def import_modules():
    global np, crexpy
    np, crexpy = numpy_and_crex("still_flicker.py")


def main():
    ap = parser(__doc__)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--path", required=True, help="a camera path that stands still")
    ap.add_argument("--frames", type=int, default=16)
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--settle", type=int, default=8, help="frames left out at the start (the history filling up)")
    ap.add_argument("--out", default="out/still_flicker")
    ap.add_argument("run_options", nargs="*", help="crex run options, after --")
    a = ap.parse_args()
    if not 0 <= a.settle < a.frames - 1:
        sys.exit("--settle must leave at least two frames")
    import_modules()
    os.makedirs(a.out, exist_ok=True)
    out = crex(a.crex, ["run", *a.run_options, "--scene", a.scene, "--camera-path", a.path, "--frames", f"0..{a.frames - 1}",
                        "--size", a.size, "-o", os.path.join(a.out, "f.exr"), "--format", "json", "--force", "-q"])
    frames = json.loads(out)["frames"]
    flicker = [f["flicker"]["display_difference"] for f in frames if "flicker" in f]
    images = np.stack([crexpy.read_image(os.path.join(a.out, f"f.{i:04d}.exr")) for i in range(a.frames)])
    shown = crexpy.to_display(images, crexpy.display_exposure(images[0]))
    luminance = shown @ np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)
    change = np.abs(np.diff(luminance, axis=0))[a.settle:].mean(axis=0)
    ranked = np.sort(change.ravel())[::-1]
    held = np.cumsum(ranked) / max(float(ranked.sum()), 1e-30)
    seconds = sum(f["seconds"] for f in frames)
    print(f"{a.scene} {a.size}, {a.frames} still frames of `crex run {' '.join(a.run_options)}`: {seconds:.2f} s")
    print(f"  crex's flicker (mean of frames 1..{a.frames - 1}): {sum(flicker) / max(len(flicker), 1):.5f}")
    print(f"  per-pixel mean change of display luminance after frame {a.settle}: {change.mean():.5f} "
          f"(median {np.median(change):.5f}, 99th percentile {np.quantile(change, 0.99):.5f})")
    print("  held by the pixels that change most: " +
          ", ".join(f"{int(100 * q)} % of pixels {100 * held[max(int(q * ranked.size) - 1, 0)]:.0f} %" for q in (0.01, 0.05, 0.10)))
    scale = max(float(np.quantile(change, 0.99)), 1e-12)
    picture = np.concatenate([shown[-1], np.repeat(np.clip(change / scale, 0, 1)[..., None], 3, axis=2)], axis=1)
    # Display values already: an 8-bit PPM, turned into a PNG by oiiotool when it is installed.
    ppm = os.path.join(a.out, "flicker.ppm")
    with open(ppm, "wb") as f:
        h, w, _ = picture.shape
        f.write(b"P6\n%d %d\n255\n" % (w, h))
        f.write((np.clip(picture, 0, 1) * 255 + 0.5).astype(np.uint8).tobytes())
    png = os.path.join(a.out, "flicker.png")
    if subprocess.run(["oiiotool", ppm, "-o", png], capture_output=True).returncode == 0:
        os.remove(ppm)
        print(f"  wrote {png} (left: the last frame; right: each pixel's flicker, white at the 99th percentile)")
    else:
        print(f"  wrote {ppm} (left: the last frame; right: each pixel's flicker, white at the 99th percentile)")


if __name__ == "__main__":
    main()
