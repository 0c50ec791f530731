"""crex: selective-rendering pipelines, compiled and run from Python.

    import crex
    plan = crex.compile("stdlib/pipelines/sel_rp.pipe")   # a .pipe file, a pipeline's text, or a crex
    result = crex.run(plan, size=(128, 96), seed=1)
    result.image              # numpy float32 (height, width, 3), linear radiance
    result.components["D"]    # what diffuse interreflection brought, per pixel
    result.maps["sal"]        # the pipeline's guidance maps
    result.samples_per_pixel  # camera samples each pixel got
    result.summary            # as `crex run --format json` prints it

The renders are `crex run`'s: the same library, so the same plan, scene, options and seed give
the same image bit for bit. Errors in a pipeline or a scene raise CompileError, whose
`diagnostics` carry code, line and column; files that cannot be read raise InputError. A render
releases the GIL and stops on Ctrl-C (KeyboardInterrupt), writing nothing.
"""

from . import _crex
from ._crex import (CompileError, CrexError, Diagnostic, InputError, Plan, Scene, check, display_exposure, load_scene, read_image,
                    to_display)

__all__ = ["CompileError", "CrexError", "Diagnostic", "InputError", "Plan", "RunResult", "Scene", "check", "compare",
           "compile", "display_exposure", "load_scene", "read_image", "run", "to_display"]


class RunResult:
    """What crex.run() rendered: numpy arrays and the run's summary."""

    def __init__(self, parts):
        self.image = parts["image"]                           # (height, width, 3) float32, linear
        self.components = parts["components"]                 # "camera", "D", "G", "S", "T", "R", "M" -> image
        self.maps = parts["maps"]                             # guidance map name -> (height, width, 1)
        self.samples_per_pixel = parts["samples_per_pixel"]   # (height, width) uint32
        self.preview = parts.get("preview")                   # a pipeline's pre-selective image
        self.summary = parts["summary"]                       # dict, as `crex run --format json`

    def __repr__(self):
        h, w, _ = self.image.shape
        return f"<crex.RunResult {w}x{h}, {self.summary.get('rays', 0)} rays in {self.summary.get('render_seconds', 0):.3f} s>"


def compile(source, scene=None, pipeline=""):
    """A plan for `scene` (a Scene, a scene spec, or None: the pipeline's own, else builtin:cornell).

    `source` is a path to a .pipe file, a pipeline file's text, or a crex such as "(TTMRSGD)*";
    `pipeline` names one pipeline of a file (default: its last). Raises CompileError.
    """
    return _crex.compile(source, scene, pipeline)


def run(plan, scene=None, *, progress=None, output=None, **options):
    """Renders `plan` (a Plan, or anything compile() takes) and returns a RunResult.

    Options override the plan's settings: size=(width, height), spp, seed, lw, max_depth,
    rounds, ambient (a radiance, or "auto"), budget (seconds), no_budget, policy ("tasks",
    "batches", "queues", "progressive"), shadow_rays, uniform ("min", "max"),
    irradiance_cache, max_memory_mib, components (default True; False: no per-component images,
    and a film a seventh of the size, for large frames). `progress(info)` is called now and then with a dict
    (stage, fraction, pass, passes, rays, step); raising from it stops the render. `output`: an
    image path (or a list of them) written once the render is done, all or none. An unknown
    option raises TypeError; a value out of its flag's range in `crex run`, ValueError.
    """
    if not isinstance(plan, Plan):
        plan = compile(plan, scene)
        scene = None
    return RunResult(_crex.run(plan, scene, progress, output, options))


def compare(test, reference, metrics=("rmse", "flip")):
    """Metrics of `test` against `reference` (arrays of shape (height, width, 3) or image paths):
    some of "rmse", "relmse" (linear), "ssim", "flip", "perr" (as a viewer sees them, both
    through the reference's exposure). Returns {metric: value}."""
    if isinstance(test, str):
        test = read_image(test)
    if isinstance(reference, str):
        reference = read_image(reference)
    if isinstance(metrics, str):
        metrics = metrics.split(",")
    return _crex.compare(test, reference, list(metrics))
