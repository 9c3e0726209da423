"""The comparison with Cycles through real bpy and real Cycles: finite figures for every
metric, the main rows against F12's Combined (ours, EEVEE's and denoised Cycles' alike)
and the diffuse ones under them, a reference cache that renders nothing twice, the scene
untouched when the comparison finishes, is cancelled between steps or fails."""
import json
import math
import os
import re

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview import demo  # noqa: E402
from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.addon.comparison import comparison_steps, markdown_table, row_label  # noqa: E402
from lpv_preview.addon.cycles_reference import run_to_end  # noqa: E402
from lpv_preview.addon.cycles_reference import F12, ReferenceCache  # noqa: E402
from lpv_preview.gpu.errors import LPVError  # noqa: E402
from lpv_preview.gpu.metrics import image_errors  # noqa: E402
from lpv_preview.gpu.settings import INDIRECT_METHODS, Settings  # noqa: E402

from ..blender.test_engine import scene_snapshot  # noqa: E402

SMALL = Settings(width=40, height=32, rsm_resolution=64, vpls_per_light=256, lpv_resolution=16)
SAMPLES = 8


def cycles_state(scene):
    """Every Cycles setting beside the scene snapshot (engine, passes, samples are in it)."""
    return {prop.identifier: getattr(scene.cycles, prop.identifier) for prop in scene.cycles.bl_rna.properties
            if prop.identifier != "rna_type" and prop.type not in {"POINTER", "COLLECTION"}
            and not getattr(prop, "is_array", False)}


def eevee_state(scene):
    """Every plain EEVEE setting (the peers switch its ray tracing and samples on a copy)."""
    from lpv_preview.addon.peers import eevee_values
    return eevee_values(scene.eevee)


@pytest.fixture()
def cornell():
    """The Cornell box under a black sky (a world, so that the snapshots cover one)."""
    scene = demo.build("cornell")
    import addon_utils
    addon_utils.enable("cycles", default_set=True)
    scene.world = bpy.data.worlds.new("Black sky")
    scene.world.color = (0.0, 0.0, 0.0)
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    return scene


def test_a_comparison_gives_finite_figures_and_leaves_the_scene_as_it_was(cornell, tmp_path):
    before = scene_snapshot(cornell), cycles_state(cornell)
    cache = ReferenceCache(str(tmp_path / "cache"))
    comparison = run_to_end(comparison_steps(cornell, ["cm", "wdpm"], SAMPLES, SMALL, cache))
    assert (scene_snapshot(cornell), cycles_state(cornell)) == before
    rows = comparison.table()
    assert [(r["method"], r["reference"]) for r in rows] == [
        ("cm", "f12"), ("wdpm", "f12"), ("Cycles seed 1", "f12"),
        ("cm", "one_bounce"), ("wdpm", "one_bounce"), ("Cycles seed 1", "one_bounce"),
        ("cm", "full_gi"), ("wdpm", "full_gi"), ("Cycles seed 1", "full_gi")]
    assert comparison.main_table() == rows[:3] and comparison.diffuse_table() == rows[3:]
    for row in rows:
        for name in ("combined",) if row["reference"] == F12 else ("indirect", "combined"):
            for metric in ("psnr", "relative_mse", "ssim", "flip"):
                assert math.isfinite(row[f"{name}_{metric}"]), (row, name, metric)
    # The main rows measure our combined image against Cycles' Combined as F12 renders it.
    f12 = comparison.references[F12]
    assert rows[0]["combined_mse"] == image_errors(comparison.methods[0].images["combined"], f12.combined)["mse"]
    assert f12.settings["pixel_filter_width"] == pytest.approx(cornell.cycles.filter_width)
    assert f12.settings["max_bounces"] == cornell.cycles.max_bounces and f12.combined.shape == (32, 40, 3)
    one, full = comparison.references["one_bounce"], comparison.references["full_gi"]
    assert one.indirect.shape == (32, 40, 3)
    # More bounces, more indirect light; the same direct light.
    assert full.indirect.mean() > 1.2 * one.indirect.mean()
    np.testing.assert_allclose(full.direct.mean(), one.direct.mean(), rtol=0.05)
    assert comparison.heat_map(comparison.methods[0], "one_bounce").shape == (32, 40, 3)
    # The second run renders no reference: all six come from the cache, unchanged.
    steps = []
    again = run_to_end(comparison_steps(cornell, ["cm"], SAMPLES, SMALL, cache), steps.append)
    assert all(r.settings["cached"] for r in again.references.values()) and len(again.references) == 3
    assert [text for _, text in steps][:4] == ["Cycles F12 reference: from the cache",
                                               "Cycles F12 noise floor (a second seed): from the cache",
                                               "Cycles one bounce reference: from the cache",
                                               "Cycles one bounce noise floor (a second seed): from the cache"]
    np.testing.assert_array_equal(again.references["full_gi"].indirect, full.indirect)
    np.testing.assert_array_equal(again.references[F12].combined, f12.combined)
    assert (scene_snapshot(cornell), cycles_state(cornell)) == before


def test_blenders_default_scene_is_measured_against_cycles_grey_world(tmp_path):
    """The default cube's background is Cycles' grey world in F12's reference, our combined
    image black there: the main row's Cycles mean is the reference's, world included; the
    diffuse reference has no world."""
    bpy.ops.wm.read_factory_settings()
    import addon_utils
    addon_utils.enable("cycles", default_set=True)
    scene = bpy.context.scene
    settings = SMALL.with_changes(width=32, height=24)
    comparison = run_to_end(comparison_steps(scene, ["cm"], 2, settings, ReferenceCache(str(tmp_path)),
                                             noise_floor=False, indirect_methods=["light_grid"]))
    world = scene.world.node_tree.nodes["Background"].inputs["Color"].default_value[0]
    f12, full = comparison.references[F12], comparison.references["full_gi"]
    np.testing.assert_allclose(f12.combined[0, 0], world, rtol=1e-3)  # a corner: the world
    assert full.combined[0, 0].max() == 0.0
    ours = comparison.methods[0].images["combined"]
    row = comparison.main_table()[0]
    assert row["combined_reference_mean"] == pytest.approx(float(f12.combined.mean()))
    assert row["combined_mse"] == pytest.approx(image_errors(ours, f12.combined)["mse"])
    assert f12.settings["samples"] == 2 and f12.settings["denoiser"] is None  # the scene's 4096 adaptive, denoised


def test_the_peers_get_rows_with_the_same_figures_and_leave_the_scene_as_it_was(cornell, tmp_path):
    cornell.eevee.taa_render_samples = 4  # EEVEE's first sample has no ray-traced light yet
    before = scene_snapshot(cornell), cycles_state(cornell), eevee_state(cornell)
    cache = ReferenceCache(str(tmp_path / "cache"))
    settings = SMALL.with_changes(width=32, height=32)
    steps = comparison_steps(cornell, ["wdpm"], SAMPLES, settings, cache, noise_floor=False,
                             indirect_methods=list(INDIRECT_METHODS), peers=True)
    comparison = run_to_end(steps)
    assert (scene_snapshot(cornell), cycles_state(cornell), eevee_state(cornell)) == before
    rows = comparison.table()
    ours = ["WDPM lpv", "WDPM light grid", "WDPM vpl gather"]
    peers = ["Cycles 1 spp + OIDN", "Cycles 4 spp + OIDN", "EEVEE ray tracing"]
    # Every peer is measured against F12's Combined, as ours are; EEVEE's diffuse light
    # also against the diffuse references (denoised Cycles has none).
    assert [(row_label(r), r["reference"]) for r in rows] == (
        [(label, F12) for label in ours + peers] +
        [(label, kind) for kind in ("one_bounce", "full_gi") for label in ours + peers[2:]])
    for row in rows:
        for image in ("combined",) if row["reference"] == F12 else ("indirect", "combined"):
            for metric in ("psnr", "relative_mse", "ssim", "flip", "mse"):
                assert math.isfinite(row[f"{image}_{metric}"]), (row, image, metric)
        assert row["ms"] > 0
    f12 = comparison.references[F12]
    for peer, row in zip(comparison.peers, rows[3:6]):
        assert row["combined_mse"] == image_errors(peer.images["combined"], f12.combined)["mse"], peer.name
    eevee = comparison.peers[-1]
    # Ray tracing adds light where Cycles has indirect light: their means agree roughly.
    reference = comparison.references["one_bounce"]
    assert 0.5 < eevee.diffuse_images["indirect"].mean() / reference.indirect.mean() < 2.0
    table = markdown_table(comparison)
    assert "| Cycles 4 spp + OIDN | " in table and "| EEVEE ray tracing | full gi |" in table
    assert "| Cycles 4 spp + OIDN | full gi |" not in table
    # Again, every peer comes from the cache.
    again = run_to_end(comparison_steps(cornell, ["wdpm"], SAMPLES, settings, cache, noise_floor=False, peers=True))
    assert all(peer.settings["cached"] for peer in again.peers) and len(again.peers) == 3
    np.testing.assert_array_equal(again.peers[-1].diffuse_images["indirect"], eevee.diffuse_images["indirect"])
    np.testing.assert_array_equal(again.peers[-1].images["combined"], eevee.images["combined"])
    assert (scene_snapshot(cornell), cycles_state(cornell), eevee_state(cornell)) == before


def test_a_cancelled_comparison_leaves_the_scene_as_it_was(cornell, tmp_path):
    before = scene_snapshot(cornell), cycles_state(cornell)
    steps = comparison_steps(cornell, ["cm"], SAMPLES, SMALL, ReferenceCache(str(tmp_path)))
    fractions = [next(steps)[0] for _ in range(3)]  # the first reference, its first part, the estimate; Esc
    steps.close()
    assert fractions == sorted(fractions) and fractions[0] == 0.0
    assert (scene_snapshot(cornell), cycles_state(cornell)) == before


def test_a_failing_comparison_raises_one_error_and_leaves_the_scene_as_it_was(cornell, tmp_path):
    before = scene_snapshot(cornell), cycles_state(cornell)
    with pytest.raises(LPVError, match="Unknown or no method"):
        run_to_end(comparison_steps(cornell, ["cm", "nope"], SAMPLES, SMALL))
    next(light for light in bpy.data.lights).energy = float("nan")
    before = scene_snapshot(cornell), cycles_state(cornell)
    with pytest.raises(LPVError, match="non-finite|power"):
        run_to_end(comparison_steps(cornell, ["cm"], SAMPLES, SMALL, ReferenceCache(str(tmp_path))))
    after = scene_snapshot(cornell), cycles_state(cornell)
    assert str(after) == str(before)  # NaN != NaN: compare the printed values


def test_the_compare_command_shows_its_progress_and_writes_the_table_and_images(tmp_path, capsys):
    out = tmp_path / "compare"
    argv = ["compare", "cornell", "--methods", "wdpm", "--samples", str(SAMPLES), "--out", str(out),
            "--cache", str(tmp_path / "cache"), "--width", "40", "--height", "32", "--rsm-resolution", "64",
            "--vpls-per-light", "256", "--lpv-resolution", "16", "--indirect-method", "light_grid", "--no-peers"]
    assert main(argv) == 0
    err = capsys.readouterr().err.splitlines()
    progress = [line for line in err if not line.startswith("lpv_preview: warning: ")]  # llvmpipe's, once
    assert len(err) - len(progress) <= 1
    assert all(re.match(r"\[ +\d+ s +\d+%\] ", line) for line in progress), progress  # elapsed time, fraction
    texts = [line.split("] ", 1)[1] for line in progress]
    assert texts[0] == f"Cycles F12 reference: {SAMPLES} samples at 40×32"
    assert texts[1].startswith(f"Cycles F12 reference: 1/{SAMPLES} samples in ") and texts[1].endswith(" left")
    assert re.fullmatch(rf"Cycles references: about \d+ s for 6 renders of {SAMPLES} samples at 40×32, estimated "
                        rf"from the [\d.]+ s the first sample took \(more bounces take longer\)", texts[2]), texts[2]
    for label in ("F12 reference", "F12 noise floor (a second seed)", "one bounce reference",
                  "one bounce noise floor (a second seed)", "full gi reference", "full gi noise floor (a second seed)"):
        assert re.search(rf"Cycles {re.escape(label)}: {SAMPLES}/{SAMPLES} samples in \d+ s, done", "\n".join(texts))
    assert texts[-1] == "LPV Preview WDPM light grid"
    report = json.loads((out / "comparison.json").read_text())
    assert [(r["method"], r["reference"]) for r in report["rows"]] == [("wdpm", "f12"), ("Cycles seed 1", "f12")]
    assert [(r["method"], r["reference"]) for r in report["diffuse_rows"]] == [
        ("wdpm", "one_bounce"), ("Cycles seed 1", "one_bounce"), ("wdpm", "full_gi"), ("Cycles seed 1", "full_gi")]
    assert report["references"]["f12"]["samples"] == SAMPLES
    table = (out / "comparison.md").read_text()
    assert table.startswith("| method | ms | Cycles s | combined PSNR dB")
    against_f12, diagnostic = table.split("\n## Diffuse light alone (diagnostic)\n")
    assert "| WDPM light grid | " in against_f12 and "indirect" not in against_f12
    assert "| method | reference | ms | Cycles s | indirect PSNR dB" in diagnostic
    assert "| WDPM light grid | one bounce |" in diagnostic and "\n## Legend\n" in diagnostic
    for name in ("cycles_one_bounce_indirect.png", "cycles_f12_combined.png", "ours_wdpm_light_grid_combined.png",
                 "error_wdpm_light_grid_full_gi_indirect.png", "error_wdpm_light_grid_f12_combined.png"):
        assert (out / name).stat().st_size > 0
    capsys.readouterr()
    assert main(["compare", "nowhere.blend", "--out", str(out)]) == 2
    assert "There is no file 'nowhere.blend'" in capsys.readouterr().err


@pytest.fixture()
def registered(cornell, tmp_path, monkeypatch):
    """The Cornell box with the add-on registered, small settings and a private cache."""
    import lpv_preview
    monkeypatch.setenv("LPV_PREVIEW_CACHE", str(tmp_path / "cache"))
    lpv_preview.register()
    cornell.render.resolution_x, cornell.render.resolution_y, cornell.render.resolution_percentage = 40, 32, 100
    properties = cornell.lpv_preview
    properties.rsm_resolution, properties.vpls_per_light, properties.lpv_resolution = 64, 256, 16
    properties.compare_samples, properties.compare_tdpm = SAMPLES, True
    properties.compare_lpv = properties.compare_vpl_gather = properties.compare_peers = False
    yield cornell
    lpv_preview.unregister()


def test_the_operator_fills_the_table_and_the_images_and_leaves_the_scene_as_it_was(registered):
    from lpv_preview.addon.comparison import last_comparison
    before = scene_snapshot(registered), cycles_state(registered)
    assert bpy.ops.lpv_preview.compare_with_cycles() == {"FINISHED"}
    assert (scene_snapshot(registered), cycles_state(registered)) == before
    comparison = last_comparison()
    assert [r.label for r in comparison.methods] == ["CM light grid", "WDPM light grid", "TDPM light grid"]
    for name in ("LPV Compare Cycles one bounce indirect", "LPV Compare Cycles F12 combined",
                 "LPV Compare WDPM light grid combined", "LPV Compare TDPM light grid error vs full gi",
                 "LPV Compare TDPM light grid error vs F12"):
        image = bpy.data.images[name]
        assert tuple(image.size) == (40, 32)
        pixels = np.empty(40 * 32 * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        assert np.isfinite(pixels).all() and pixels.reshape(-1, 4)[:, :3].max() > 0
    np.testing.assert_allclose(  # the datablock holds the image, bottom row first
        np.asarray(bpy.data.images["LPV Compare CM light grid indirect"].pixels[:]).reshape(32, 40, 4)[::-1, :, :3],
        comparison.methods[0].images["indirect"], rtol=1e-6)


def test_the_panel_shows_the_cycles_cache_whose_button_empties_it(registered, tmp_path, monkeypatch):
    from lpv_preview.addon.cycles_reference import CyclesReference, ReferenceCache, default_cache_folder, size_text
    cache = ReferenceCache()
    assert cache.folder == str(tmp_path / "cache") and cache.describe() == "0 Cycles references, 0 B"
    reference = CyclesReference("one_bounce", np.ones((4, 4, 3), np.float32), np.zeros((4, 4, 3), np.float32),
                                np.ones((4, 4, 3), np.float32), {"samples": 1})
    keys = ("0123456789abcdef0123", "fedcba9876543210fedc")
    for key in keys:
        cache.store(key, reference)
    (tmp_path / "cache" / "notes.txt").write_text("the user's, not the cache's")
    size = sum(os.path.getsize(cache.path(key)) for key in keys)
    assert cache.size() == (2, size) and size > 0
    assert ReferenceCache().describe() == f"2 Cycles references, {size_text(size)}"
    assert bpy.ops.lpv_preview.empty_cycles_cache() == {"FINISHED"}
    assert os.listdir(tmp_path / "cache") == ["notes.txt"] and cache.size() == (0, 0)
    # Outside an installed extension (the command line, the tests) the cache is the XDG one.
    monkeypatch.delenv("LPV_PREVIEW_CACHE")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert default_cache_folder() == str(tmp_path / "xdg" / "lpv_preview" / "cycles")


def test_the_operator_reports_one_error_when_no_method_is_ticked(registered):
    properties = registered.lpv_preview
    properties.compare_cm = properties.compare_wdpm = properties.compare_tdpm = False
    before = scene_snapshot(registered), cycles_state(registered)
    with pytest.raises(RuntimeError) as error:
        bpy.ops.lpv_preview.compare_with_cycles()
    assert str(error.value).strip() == ("Error: No method is ticked for the comparison; tick at least one in the "
                                        "Comparison panel.")
    assert (scene_snapshot(registered), cycles_state(registered)) == before


def test_time_to_equal_error_fits_cycles_error_and_time_against_samples(cornell, tmp_path):
    from lpv_preview.scripts.time_to_equal_error import equal_error_of
    settings = Settings(width=32, height=32, rsm_resolution=64, vpls_per_light=256, lpv_resolution=16, method="wdpm")
    results = equal_error_of(cornell, settings, 64, [1, 4, 16], "one_bounce", ReferenceCache(str(tmp_path)),
                             indirect_methods=["light_grid"], denoised_samples=[1])
    assert [(r.label, r.image) for r in results] == [("WDPM light grid", "indirect"), ("WDPM light grid", "combined"),
                                                     ("Cycles 1 spp + OIDN", "combined_pass")]
    for result in results:
        samples = [rung[0] for rung in result.ladder]
        errors = [rung[2] for rung in result.ladder]
        assert samples == [1, 4, 16] and errors[0] > errors[-1] > 0
        assert 0.5 < result.slope < 1.5  # Monte Carlo: MSE about 1 / samples
        assert result.mse > 0 and result.milliseconds > 0
        if result.samples is not None:
            assert result.samples >= 1 and result.seconds > 0


def lone_plane_blend(path):
    """A lit plane alone under a black sky, seen from above: Cycles' indirect light is black."""
    from lpv_preview.demo.builder import MeshBuilder, add_camera, add_light, principled_material
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    plane = MeshBuilder()
    plane.parallelogram((-1, -1, 0), (2, 0, 0), (0, 2, 0), 4, 4)
    plane.to_object("Plane", [principled_material("Grey", (0.5, 0.5, 0.5))], scene.collection)
    add_light(scene, "Light", "POINT", (0.0, 0.0, 1.0), 50.0)
    add_camera(scene, (0.0, -0.5, 2.5), (0.0, 0.0, 0.0), resolution=(24, 20))
    bpy.ops.wm.save_as_mainfile(filepath=str(path))


def strict_json(text):
    """JSON as the standard has it: NaN and Infinity are not numbers there."""
    def refuse(constant):
        raise ValueError(f"{constant} is not JSON")
    return json.loads(text, parse_constant=refuse)


def test_a_black_reference_is_an_answer_measured_in_absolute_figures(tmp_path, capsys):
    blend = tmp_path / "plane.blend"
    lone_plane_blend(blend)
    out = tmp_path / "compare"
    argv = ["compare", str(blend), "--methods", "cm", "--samples", "4", "--out", str(out), "--cache",
            str(tmp_path / "cache"), "--rsm-resolution", "64", "--vpls-per-light", "256", "--lpv-resolution", "16",
            "--no-peers"]
    assert main(argv) == 0, capsys.readouterr().err
    report = strict_json((out / "comparison.json").read_text())
    rows = report["diffuse_rows"]
    ours = next(row for row in rows if row["method"] == "cm" and row["reference"] == "one_bounce")
    f12 = next(row for row in report["rows"] if row["method"] == "cm")
    assert all(math.isfinite(f12[f"combined_{metric}"]) for metric in ("psnr", "relative_mse", "ssim", "flip"))
    assert ours["indirect_reference_mean"] == 0.0
    assert ours["indirect_mse"] == pytest.approx(ours["indirect_mean"] ** 2, rel=10) and ours["indirect_mse"] >= 0
    for metric in ("psnr", "relative_mse", "ssim", "flip"):
        assert ours[f"indirect_{metric}"] is None  # relative to a black image: undefined
        assert math.isfinite(ours[f"combined_{metric}"])  # the direct light is not black
    noise = next(row for row in rows if row["method"] == "Cycles seed 1" and row["reference"] == "one_bounce")
    assert noise["indirect_mse"] == 0.0 and noise["indirect_psnr"] is None
    table = (out / "comparison.md").read_text()
    assert "indirect MSE" in table and "indirect mean" in table and "| — |" in table


WITHOUT_OPENIMAGEIO = '''
import sys


class WithoutOpenImageIO:
    """A Python without OpenImageIO on its path ('path': Blender as a module in a Python
    that never installed it) or anywhere ('everywhere': not even Blender's bundled copy)."""

    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] == "OpenImageIO" and (path is None or sys.argv[1] == "everywhere"):
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None


sys.meta_path.insert(0, WithoutOpenImageIO())
import bpy
import lpv_preview
from lpv_preview import demo

scene = demo.build("cornell", resolution=(32, 24))
lpv_preview.register()
properties = scene.lpv_preview
properties.rsm_resolution, properties.vpls_per_light, properties.lpv_resolution = 64, 256, 16
properties.compare_samples, properties.compare_noise_floor, properties.compare_peers = 1, False, False
properties.compare_wdpm = properties.compare_lpv = properties.compare_vpl_gather = False
try:
    print("RESULT", bpy.ops.lpv_preview.compare_with_cycles())
except RuntimeError as error:
    print("REPORT", str(error).strip())
'''


@pytest.mark.parametrize("blocked", ["path", "everywhere"])
def test_compare_with_cycles_in_a_python_without_openimageio(blocked, tmp_path):
    """Blender as a module leaves Blender's bundled OpenImageIO off the path: the comparison
    reads its EXRs with that copy; where there is none at all, it reports one sentence
    before any Cycles render."""
    import subprocess
    import sys
    script = tmp_path / "compare.py"
    script.write_text(WITHOUT_OPENIMAGEIO)
    result = subprocess.run([sys.executable, str(script), blocked], capture_output=True, text=True, timeout=300,
                            env={**os.environ, "LPV_PREVIEW_CACHE": str(tmp_path / "cache")})
    assert "Traceback" not in result.stderr + result.stdout, result.stderr
    lines = [line for line in result.stdout.splitlines() if line.startswith(("RESULT", "REPORT"))]
    if blocked == "path":
        assert lines == ["RESULT {'FINISHED'}"], result.stdout + result.stderr
    else:
        assert lines == ["REPORT Error: Reading and writing images needs the OpenImageIO module, which neither this "
                         "Python nor Blender's bundled packages hold; use Blender 5.0 from blender.org, which ships "
                         "it, or install requirements.txt (bash scripts/setup.sh)."], result.stdout + result.stderr
        assert "Saved:" not in result.stdout + result.stderr  # no Cycles render began
