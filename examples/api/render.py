"""The library from Python: compile a pipeline for a scene, run it, write the image.
Usage: python3 render.py PIPELINE.pipe SCENE OUT.png   (e.g. stdlib/pipelines/sel_rp.pipe builtin:cornell)"""
import sys

import crex

pipeline, scene, out = sys.argv[1:4]
try:
    plan = crex.compile(pipeline, scene=scene)  # the scene's census prunes what it can never need
except crex.CompileError as e:
    for d in e.diagnostics:  # each with code, file, line and column
        print(d, file=sys.stderr)
    sys.exit(1)
result = crex.run(plan, size=(64, 48), output=out)  # numpy arrays; the file written once done
print(f"wrote {out}: {result.summary['rays']} rays, mean radiance {result.image.mean():.4f}")
