"""Renders a crex scene JSON with Blender's Cycles, for the peer comparison (issue 40, docs/peer.md).

Run by peer_table.py inside Blender (Debian's `blender`; never in CI):

    blender -b --factory-startup -noaudio -P bench/peer/cycles_render.py -- \
        --scene scene.json --out image.exr --size 256 --spp 64 [--adaptive 0.01] [--threads 1]

The scene is the JSON `crex scene-info FILE.rad --export-json` writes, so Cycles sees what crex
read from the RADIANCE file: polygons, spheres, and the materials the two peer boxes use
(Lambertian plastic, light, mirror, clear dielectric). Everything that would bias Cycles is
off: no denoiser, no clamping, no filter glossy, 64 bounces of every kind (Russian roulette
ends paths), a one-pixel box filter as crex's. RADIANCE's lights emit from their front only,
so the emission is masked on back faces. Prints one line `CYCLES {"seconds": ..}`: the
render call's wall time (scene sync, BVH build and sampling), not Blender's start-up.
"""
import json
import math
import sys
import time

import bpy
import mathutils


def args():
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--adaptive", type=float, default=0, help="Cycles' adaptive sampling at this noise threshold (0: off)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--seed", type=int, default=0)
    return ap.parse_args(sys.argv[sys.argv.index("--") + 1 :] if "--" in sys.argv else [])


def material(m):
    """A Blender material for a crex material of the peer scenes."""
    mat = bpy.data.materials.new(m["name"])
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    colour = list(m.get("color", [0.5, 0.5, 0.5]))
    kind = m["type"]
    if kind == "light":
        peak = max(colour) or 1.0
        emit = nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (*[c / peak for c in colour], 1)
        emit.inputs["Strength"].default_value = peak  # a mesh light's radiance is colour x strength
        black = nodes.new("ShaderNodeBsdfDiffuse")
        black.inputs["Color"].default_value = (0, 0, 0, 1)
        back = nodes.new("ShaderNodeNewGeometry")
        mix = nodes.new("ShaderNodeMixShader")
        links.new(back.outputs["Backfacing"], mix.inputs["Fac"])
        links.new(emit.outputs["Emission"], mix.inputs[1])
        links.new(black.outputs["BSDF"], mix.inputs[2])
        links.new(mix.outputs["Shader"], out.inputs["Surface"])
    elif kind == "plastic" and not m.get("specularity") and not m.get("roughness"):
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Color"].default_value = (*colour, 1)
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    elif kind == "mirror":
        bsdf = nodes.new("ShaderNodeBsdfGlossy")
        bsdf.distribution = "SHARP"
        bsdf.inputs["Color"].default_value = (*colour, 1)
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    elif kind == "dielectric" and all(c >= 1 for c in colour):
        bsdf = nodes.new("ShaderNodeBsdfGlass")
        bsdf.distribution = "SHARP"
        bsdf.inputs["Color"].default_value = (1, 1, 1, 1)
        bsdf.inputs["IOR"].default_value = m.get("ior", 1.52)
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    else:
        raise SystemExit(f"cycles_render.py: material {m['name']} ({kind}) is not one the peer scenes use")
    return mat


def add_mesh(name, verts, faces, mat, smooth=False):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    if smooth:
        for p in mesh.polygons:
            p.use_smooth = True
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)


def add_sphere(name, centre, radius, mat):
    # Cycles has no analytic sphere: a fine UV sphere with smooth normals.
    rings, segments = 128, 256
    verts, faces = [], []
    for i in range(1, rings):
        t = math.pi * i / rings
        for j in range(segments):
            p = 2 * math.pi * j / segments
            verts.append((centre[0] + radius * math.sin(t) * math.cos(p), centre[1] + radius * math.cos(t),
                          centre[2] + radius * math.sin(t) * math.sin(p)))
    top, bottom = len(verts), len(verts) + 1
    verts += [(centre[0], centre[1] + radius, centre[2]), (centre[0], centre[1] - radius, centre[2])]
    ring = lambda i, j: (i - 1) * segments + j % segments  # noqa: E731
    for j in range(segments):
        faces.append((top, ring(1, j + 1), ring(1, j)))
        faces.append((bottom, ring(rings - 1, j), ring(rings - 1, j + 1)))
        for i in range(1, rings - 1):
            faces.append((ring(i, j), ring(i, j + 1), ring(i + 1, j + 1), ring(i + 1, j)))
    add_mesh(name, verts, faces, mat, smooth=True)


def camera(c):
    cam = bpy.data.cameras.new("camera")
    cam.sensor_fit = "HORIZONTAL"
    cam.angle = math.radians(c["hfov"])
    cam.clip_start, cam.clip_end = 1e-3, 1e9  # the scenes are in millimetres: Blender would clip at 100
    obj = bpy.data.objects.new("camera", cam)
    bpy.context.scene.collection.objects.link(obj)
    d = mathutils.Vector(c["direction"]).normalized()
    right = d.cross(mathutils.Vector(c["up"])).normalized()
    up = right.cross(d)
    # A Blender camera looks down its -Z with +Y up.
    obj.matrix_world = mathutils.Matrix(
        ((right.x, up.x, -d.x, c["position"][0]), (right.y, up.y, -d.y, c["position"][1]),
         (right.z, up.z, -d.z, c["position"][2]), (0, 0, 0, 1)))
    bpy.context.scene.camera = obj
    if abs(c["hfov"] - c["vfov"]) > 1e-6:
        raise SystemExit("cycles_render.py: the peer scenes' views are square")


def settings(a):
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    cy = s.cycles
    cy.device = "CPU"
    cy.samples = a.spp
    cy.use_adaptive_sampling = a.adaptive > 0
    if a.adaptive > 0:
        cy.adaptive_threshold = a.adaptive
    cy.use_denoising = False
    cy.seed = a.seed
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    for k in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "volume_bounces", "transparent_max_bounces"):
        setattr(cy, k, 64)
    cy.sample_clamp_direct = 0
    cy.sample_clamp_indirect = 0
    cy.blur_glossy = 0
    cy.caustics_reflective = cy.caustics_refractive = True
    cy.use_auto_tile = False
    s.render.threads_mode = "FIXED"
    s.render.threads = a.threads
    s.render.resolution_x = s.render.resolution_y = a.size
    s.render.resolution_percentage = 100
    s.render.film_transparent = False
    s.view_settings.view_transform = "Standard"
    s.view_settings.look = "None"
    s.view_settings.exposure = 0
    s.render.image_settings.file_format = "OPEN_EXR"
    s.render.image_settings.color_depth = "32"
    s.render.image_settings.exr_codec = "ZIP"
    world = bpy.data.worlds.new("black")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0
    s.world = world


def main():
    a = args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    with open(a.scene) as f:
        scene = json.load(f)
    mats = {m["name"]: material(m) for m in scene["materials"]}
    for k, sh in enumerate(scene["shapes"]):
        name = sh.get("name", f"shape{k}")
        if sh["type"] == "polygon":
            add_mesh(name, [tuple(v) for v in sh["vertices"]], [tuple(range(len(sh["vertices"])))], mats[sh["material"]])
        elif sh["type"] == "sphere":
            add_sphere(name, sh["center"], sh["radius"], mats[sh["material"]])
        else:
            raise SystemExit(f"cycles_render.py: shape type {sh['type']} is not one the peer scenes use")
    camera(scene["camera"])
    settings(a)
    t = time.perf_counter()
    bpy.ops.render.render()
    seconds = time.perf_counter() - t
    bpy.data.images["Render Result"].save_render(a.out)
    print("CYCLES " + json.dumps({"seconds": seconds}), flush=True)


main()
