"""The Python module against the CLI and the issue's promises (issue 35): the same image as
`crex run` bit for bit, diagnostics raised with their code, line and column, a render stopped
by Ctrl-C with nothing written, the GIL released while rendering. Run by ctest (label python)
with PYTHONPATH at the build's python/ folder and CREX_BINARY, CREX_SOURCE_DIR set."""
import _thread
import json
import os
import subprocess
import threading

import numpy as np
import pytest

import crex

SOURCE = os.environ.get("CREX_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
CLI = os.environ.get("CREX_BINARY", "crex")
SEL_RP = os.path.join(SOURCE, "stdlib", "pipelines", "sel_rp.pipe")


def cli(*args):
    return subprocess.run([CLI, *args], capture_output=True, text=True, check=False)


@pytest.mark.parametrize("source", [SEL_RP, "(TTMRSGD)*"])
def test_the_image_is_the_cli_image_bit_for_bit(tmp_path, source):
    exr = str(tmp_path / "cli.exr")
    plan_args = [source] if source.endswith(".pipe") else ["-e", source]
    r = cli("run", *plan_args, "--scene", "builtin:cornell", "--size", "32x24", "--spp", "2", "--seed", "7", "-q", "-o", exr)
    assert r.returncode == 0, r.stderr
    result = crex.run(crex.compile(source, scene="builtin:cornell"), size=(32, 24), spp=2, seed=7)
    assert result.image.shape == (24, 32, 3) and result.image.dtype == np.float32
    assert np.array_equal(result.image, crex.read_image(exr)), "the Python image differs from the CLI's"
    assert result.image.max() > 0


def test_a_crex_error_is_raised_with_its_code_line_and_column():
    with pytest.raises(crex.CompileError) as caught:
        crex.compile("TT{TD*}2")
    errors = [d for d in caught.value.diagnostics if d.severity == "error"]
    assert [(d.code, d.line, d.column) for d in errors] == [("E004", 1, 6)]
    assert "E004" in str(caught.value)


def test_a_stdlib_pipeline_compiles_by_its_name_alone():
    by_name = crex.compile("sel_rp", scene="builtin:cornell")
    assert by_name.to_dict() == crex.compile(SEL_RP, scene="builtin:cornell").to_dict()
    with pytest.raises(crex.CompileError) as caught:  # neither a crex nor a stdlib name: both said
        crex.compile("sel_r")
    assert "did you mean 'sel_rp'?" in str(caught.value), str(caught.value)


def test_a_pipeline_error_is_located_in_the_pipeline_text():
    text = 'pipeline broken {\n  preselective { crex "TT" spp 4 }\n  guidance { m = saliency(nothing) }\n  selective { vary spp 1 .. 8 by m }\n}\n'
    with pytest.raises(crex.CompileError) as caught:
        crex.compile(text)
    d = next(d for d in caught.value.diagnostics if d.severity == "error")
    assert d.code == "E205" and d.line == 3 and d.column == text.splitlines()[2].index("nothing") + 1, repr(d)
    assert isinstance(caught.value, crex.CrexError)


def test_ctrl_c_stops_a_render_with_nothing_written(tmp_path):
    out = tmp_path / "never.exr"
    # Minutes of work: the interrupt must stop it, and the file must not appear.
    threading.Timer(0.5, _thread.interrupt_main).start()
    with pytest.raises(KeyboardInterrupt):
        crex.run("(TTMRSGD)*", size=(256, 256), spp=4096, output=str(out))
    assert not out.exists()
    assert not [p for p in tmp_path.iterdir()], "a staged file was left behind"


def test_the_gil_is_released_while_rendering():
    counted = [0]
    done = threading.Event()

    def count():
        while not done.is_set():
            counted[0] += 1

    t = threading.Thread(target=count)
    t.start()
    try:
        crex.run("(TTMRSGD)*", size=(32, 32), spp=16)
    finally:
        done.set()
        t.join()
    # With the GIL held for the whole render the other thread could not have counted at all.
    assert counted[0] > 1000


def test_progress_is_reported_and_can_stop_the_render():
    seen = []
    crex.run("(TTMRSGD)*", size=(32, 32), spp=64, progress=seen.append)
    assert seen and all({"stage", "fraction", "rays"} <= set(p) for p in seen)
    assert seen[-1]["rays"] > 0

    class Enough(Exception):
        pass

    def stop(_):
        raise Enough()

    with pytest.raises(Enough):
        crex.run("(TTMRSGD)*", size=(64, 64), spp=4096, progress=stop)


def test_without_components_the_image_is_the_same_and_no_component_is_given():
    # components=False: the film keeps one sum for all the light (a seventh of the memory),
    # so the composite is the same up to the order of the additions.
    full = crex.run("(TTMRSGD)*", size=(16, 12), spp=2, seed=5)
    lean = crex.run("(TTMRSGD)*", size=(16, 12), spp=2, seed=5, components=False)
    assert lean.components == {}
    assert len(full.components) == 7
    assert np.allclose(lean.image, full.image, rtol=1e-6, atol=1e-7)
    assert lean.image.max() > 0


def test_a_run_gives_components_maps_samples_and_the_summary(tmp_path):
    plan = crex.compile(SEL_RP, scene="builtin:cornell")
    assert plan.staged and plan.name == "sel_rp"
    r = crex.run(plan, size=(24, 16), seed=3, output=str(tmp_path / "sel.png"))
    assert (tmp_path / "sel.png").exists()
    h, w = 16, 24
    assert set(r.components) == {"camera", "D", "G", "S", "T", "R", "M"}
    total = sum(r.components.values())
    assert np.allclose(total, r.image, rtol=1e-4, atol=1e-5), "the components add up to the image"
    assert r.maps and all(m.shape == (h, w, 1) for m in r.maps.values())
    assert r.samples_per_pixel.shape == (h, w) and r.samples_per_pixel.min() >= 1
    assert r.samples_per_pixel.max() > r.samples_per_pixel.min(), "sel_rp varies the samples per pixel"
    assert r.summary["pipeline"] == "sel_rp" and r.summary["size"] == [w, h]
    assert r.preview.shape == (h, w, 3)


def test_the_summary_lists_the_warnings_the_scene_said_as_it_loaded(tmp_path):
    obj = tmp_path / "w.obj"
    obj.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nusemtl nothere\nf 1 2 3\n")
    r = crex.run("(TTMRSGD)*", scene=crex.load_scene(str(obj)), size=(8, 8), spp=1)
    missing = [w for w in r.summary["warnings"] if w["code"] == "W301"]
    assert len(missing) == 1 and missing[0]["file"] == str(obj) and missing[0]["line"] == 5, r.summary["warnings"]


def test_check_compile_load_scene_and_compare():
    ds = crex.check("TT{TD*}2")  # as `crex check -e` says: the error, then the warning W101
    assert [(d.code, d.severity, d.column) for d in ds] == [("E004", "error", 6), ("W101", "warning", 8)]
    assert crex.check("(TTMRSGD)*") == []
    assert [d.code for d in crex.check("(TTMRSGD)*", scene="builtin:cornell_diffuse")].count("W103") >= 1
    plan = crex.compile("(TTMRSGD)*", scene="builtin:cornell_diffuse")
    as_json = plan.to_dict()
    assert as_json["format"] == "crex-plan" and as_json["pruned"], "steps the scene cannot need are pruned"
    assert plan.dot.startswith("digraph")
    scene = crex.load_scene("builtin:cornell")
    assert scene.spec == "builtin:cornell" and scene.census()["components"]["D"]["can_occur"]
    a = crex.run("(TTMRSGD)*", scene=scene, size=(32, 32), spp=1, seed=1).image
    b = crex.run("(TTMRSGD)*", scene=scene, size=(32, 32), spp=1, seed=2).image
    same = crex.compare(a, a, ["rmse", "flip"])
    assert same == {"rmse": 0.0, "flip": 0.0}
    other = crex.compare(a, b, ("rmse", "flip", "ssim"))
    assert other["rmse"] > 0 and 0 < other["flip"] < 1 and other["ssim"] < 1


def test_inputs_that_cannot_be_read_raise_input_error(tmp_path):
    with pytest.raises(crex.InputError):
        crex.load_scene(str(tmp_path / "none.json"))
    with pytest.raises(crex.InputError):
        crex.read_image(str(tmp_path / "none.exr"))
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"camera": {"position": [0, 0, 0]}}))
    with pytest.raises(crex.CompileError) as caught:
        crex.load_scene(str(bad))
    assert all(d.file == str(bad) for d in caught.value.diagnostics if d.severity == "error")


def test_to_display_is_the_tone_map_of_the_metrics_on_any_stack_of_images():
    grey = np.full((4, 6, 3), 0.5, dtype=np.float32)
    exposure = crex.display_exposure(grey)
    assert exposure == pytest.approx(0.18 / (0.5 + 1e-6), rel=1e-9)  # 0.18 over the log-average luminance
    v = 0.18 / 1.18  # Reinhard of grey at that exposure, then the sRGB curve
    expected = 1.055 * v ** (1 / 2.4) - 0.055
    stack = np.stack([grey, grey * 0, np.full_like(grey, np.nan)])  # (3, 4, 6, 3): the shape is kept
    shown = crex.to_display(stack, exposure)
    assert shown.shape == stack.shape and shown.dtype == np.float32
    assert np.allclose(shown[0], expected, atol=1e-6) and not shown[1].any() and not shown[2].any()
    with pytest.raises(ValueError):
        crex.to_display(np.zeros((4, 6, 2), dtype=np.float32), 1.0)


def test_options_are_checked_as_the_cli_checks_its_flags():
    # A misspelt option must not render with its default, and a wrong value names its option.
    with pytest.raises(TypeError, match="unexpected keyword argument 'sps'"):
        crex.run("(TTMRSGD)*", size=(8, 8), sps=64)
    with pytest.raises(ValueError, match=r"spp: 0 is out of range: expected a whole number from 1 to 1048576"):
        crex.run("(TTMRSGD)*", size=(8, 8), spp=0)
    with pytest.raises(ValueError, match="shadow_rays: 2000 is out of range"):
        crex.run("(TTMRSGD)*", size=(8, 8), shadow_rays=2000)
    with pytest.raises(TypeError, match="size: expected a whole number from 1 to 16384, got float"):
        crex.run("(TTMRSGD)*", size=(8.5, 8))
    with pytest.raises(TypeError, match="spp: expected a whole number"):
        crex.run("(TTMRSGD)*", size=(8, 8), spp=True)
    with pytest.raises(ValueError, match="lw: 2 is out of range"):
        crex.run("(TTMRSGD)*", size=(8, 8), lw=2)
    # Bounds are written as the flags write them, not as 9.00719925474099e+15.
    with pytest.raises(ValueError, match=r"seed: -1 is out of range: expected a whole number from 0 to 9007199254740992$"):
        crex.run("(TTMRSGD)*", size=(8, 8), seed=-1)
    with pytest.raises(ValueError, match=r"budget: 0 is out of range: expected a number from 0.001 to 1000000000$"):
        crex.run("(TTMRSGD)*", size=(8, 8), budget=0)
    with pytest.raises(TypeError, match="components: expected True or False"):
        crex.run("(TTMRSGD)*", size=(8, 8), components="no")
    # numpy integers are whole numbers, as Python's are.
    r = crex.run("(TTMRSGD)*", size=(np.int64(8), np.int32(6)), spp=np.uint16(1), seed=np.int64(3))
    assert r.image.shape == (6, 8, 3)


def test_compare_refuses_what_crex_compare_refuses():
    zero = np.zeros((4, 4, 3), np.float32)
    nan = zero.copy()
    nan[1, 2, 0] = np.nan
    with pytest.raises(ValueError, match="the test image holds 1 non-finite value"):
        crex.compare(nan, zero)
    with pytest.raises(ValueError, match="the reference image holds 1 non-finite value"):
        crex.compare(zero, nan)
    with pytest.raises(ValueError, match="each side from 1"):
        crex.compare(np.zeros((0, 4, 3), np.float32), np.zeros((0, 4, 3), np.float32))


def test_wrong_kinds_of_scene_output_and_exposure_say_which_argument():
    with pytest.raises(TypeError, match="scene: expected a crex.Scene"):
        crex.run("(TTMRSGD)*", scene=42, size=(8, 8))
    with pytest.raises(TypeError, match="output: expected an image path or a list of them"):
        crex.run("(TTMRSGD)*", size=(8, 8), output=["a.png", 3])
    with pytest.raises(ValueError, match="exposure: nan is not a number above 0"):
        crex.to_display(np.ones((2, 2, 3), np.float32), float("nan"))
    with pytest.raises(ValueError, match="exposure: -1 is not a number above 0"):
        crex.to_display(np.ones((2, 2, 3), np.float32), -1.0)
