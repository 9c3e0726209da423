"""Benchmark sweeps (bench/sweep.py, bench/sweep_report.py): the tiny sweep end to end through
the command line, its JSON's schema, the plot and the Markdown table; the sweep file's
checks; the light sets and the scaling fit."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from lpv_preview.gpu.errors import LPVError
from lpv_preview.bench.sweep import load_sweep, sweep_points
from lpv_preview.bench.sweep_report import pareto_front, scaling_fit
from lpv_preview.gpu.scene_edits import with_lights
from lpv_preview.gpu.scene_file import load_scene, stored_cycles_indirect

from ..synthetic_scenes import room_scene

bpy = pytest.importorskip("bpy")

from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.cli.commands import command_export  # noqa: E402
from lpv_preview.cli.parser import build_parser  # noqa: E402

TEST_SWEEPS = str(Path(__file__).parent / "sweeps.toml")
POINT_KEYS = {"scene", "method", "settings", "triangles", "timings_ms", "gpu_bytes", "vpl_count", "errors_vs_cm"}


def test_the_tiny_sweep_writes_a_json_a_plot_and_a_table(tmp_path, capsys, monkeypatch):
    monkeypatch.setenv("LPV_PREVIEW_CACHE", str(tmp_path / "cycles"))
    out = tmp_path / "sweep"
    assert main(["bench", "--sweep", "tiny", "--sweeps", TEST_SWEEPS, "--out", str(out)]) == 0
    report = json.loads((out / "sweep_tiny.json").read_text())
    assert report["schema"] == 1 and report["sweep"] == "tiny" and report["repeats"] == 2
    assert set(report["machine"]) == {"renderer", "version", "cpu", "system"} and report["date"]
    assert report["command"].endswith(f"--out {out}")
    assert [(p["method"], p["settings"]["rsm_resolution"]) for p in report["points"]] == [
        ("cm", 64), ("cm", 128), ("wdpm", 64), ("wdpm", 128)]
    for point in report["points"]:
        assert POINT_KEYS <= set(point)
        assert point["triangles"] == 900 and point["settings"]["width"] == 64 and point["vpl_count"] > 0
        timings = point["timings_ms"]
        assert timings["total_ms"] > 0 and all(timings[k] >= 0 for k in ("rsm_ms", "vpl_ms", "inject_ms"))
        low, high = timings["total_ms_spread"]
        assert low <= timings["total_ms"] <= high
        assert point["gpu_bytes"] > 64 * 64 * 16  # at least the camera images
        for source in ("errors_vs_cm", "errors_vs_cycles"):
            errors = point[source]
            assert set(errors) == {"psnr", "relative_mse", "flip"} and all(math.isfinite(v) for v in errors.values())
    assert report["cycles_samples"] == 8
    assert (out / "pareto_tiny_cornell.png").stat().st_size > 10_000
    table = (out / "sweep_tiny.md").read_text()
    header = next(line for line in table.splitlines() if line.startswith("| method |"))
    assert header.startswith("| method | rsm_resolution | frame ms (spread) | RSM | warp | VPLs | G-buffer |")
    assert "| inject |" in header and "| gather |" in header and "| emitter grid |" not in header  # what ran
    assert "| PSNR dB vs Cycles one bounce | relMSE vs Cycles one bounce |" in table
    assert table.count("| CM | ") == 2 and table.count("| WDPM | ") == 2 and "| yes |" in table
    # The outputs again from the JSON alone (how a GPU machine's run is reported here).
    (out / "sweep_tiny.md").unlink()
    assert main(["bench", "--report", str(out / "sweep_tiny.json"), "--out", str(out)]) == 0
    assert (out / "sweep_tiny.md").read_text() == table


def test_an_export_carries_its_cycles_reference_and_the_sweep_measures_errors_at_its_size(tmp_path, monkeypatch):
    monkeypatch.setenv("LPV_PREVIEW_CACHE", str(tmp_path / "cycles"))
    scene = tmp_path / "box.npz"
    assert main(["export", "cornell", "--lights", "1", "--light-kind", "spot", "--cycles-samples", "4",
                 "--cycles-width", "24", "--out", str(scene)]) == 0
    loaded = load_scene(scene)
    assert [light.kind for light in loaded.lights] == ["SPOT"]
    made, wanted = loaded.lights[0], with_lights(load_scene(scene), 1, "spot").lights[0]
    for name in ("position", "direction", "power", "spot_size", "spot_blend"):
        assert getattr(made, name) == pytest.approx(getattr(wanted, name), rel=1e-6, abs=1e-6), name
    image, samples = stored_cycles_indirect(scene)
    assert image.shape == (24, 24, 3) and samples == 4 and image.max() > 0
    assert stored_cycles_indirect(tmp_path / "other.npz") is None
    sweeps = tmp_path / "sweeps.toml"
    sweeps.write_text(f'[s]\ncycles_samples = 4\nscenes = ["{scene}"]\nmethods = ["wdpm"]\nrsm_resolution = 64\n'
                      'vpls_per_light = 128\nlpv_resolution = 8\nwidth = 48\nheight = 48\nrepeats = 1\n'
                      'viewport_redraws = true\nreference = { rsm_resolution = 128, vpls_per_light = 1024 }\n')
    assert main(["bench", "--sweep", "s", "--sweeps", str(sweeps), "--out", str(tmp_path / "out")]) == 0
    point, = json.loads((tmp_path / "out" / "sweep_s.json").read_text())["points"]
    assert point["error_size"] == [24, 24] and point["settings"]["width"] == 48 and point["cycles_samples"] == 4
    assert point["timings_ms"]["camera_move_ms"] > 0 and point["timings_ms"]["light_edit_ms"] > 0  # viewport_redraws
    assert all(math.isfinite(point[source]["psnr"]) for source in ("errors_vs_cm", "errors_vs_cycles"))
    assert "errors measured at 24×24, times at 48×48" in (tmp_path / "out" / "sweep_s.md").read_text()
    with pytest.raises(LPVError, match="--cycles-width needs --cycles-samples"):
        command_export(build_parser().parse_args(["export", "cornell", "--cycles-width", "24", "--out", str(scene)]))


def test_the_sweep_file_is_checked(tmp_path, capsys):
    with pytest.raises(LPVError, match="There is no sweep 'nope'"):
        load_sweep("nope")
    with pytest.raises(LPVError, match="Cannot read the sweeps file"):
        load_sweep("tiny", tmp_path / "missing.toml")
    bad = tmp_path / "sweeps.toml"
    bad.write_text('[typo]\nscenes = ["cornell"]\nmethods = ["cm"]\nrsm_resoluton = 64\n')
    with pytest.raises(LPVError, match="unknown key 'rsm_resoluton'"):
        load_sweep("typo", bad)
    assert main(["bench", "--sweep", "typo", "--sweeps", str(bad)]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    bad.write_text('[ref]\nscenes = ["cornell"]\nmethods = ["cm"]\nreference = { width = 8 }\n')
    with pytest.raises(LPVError, match="reference setting 'width'"):
        load_sweep("ref", bad)


def test_one_at_a_time_varies_each_axis_around_the_first_values(tmp_path):
    path = tmp_path / "sweeps.toml"
    path.write_text('[s]\nmode = "one-at-a-time"\nscenes = ["a", "b"]\nmethods = ["cm", "wdpm"]\n'
                    'rsm_resolution = [512, 256, 1024]\nlpv_resolution = [32, 16]\n')
    points = sweep_points(load_sweep("s", path))
    assert len(points) == 2 * 2 * (1 + 2 + 1)
    assert {(p["rsm_resolution"], p["lpv_resolution"]) for p in points} == {(512, 32), (256, 32), (1024, 32), (512, 16)}


@pytest.mark.parametrize("kind", ["point", "spot", "area", "sun"])
def test_light_sets_keep_one_lights_power_and_stay_inside_the_scene(kind):
    one = with_lights(room_scene(2), 1, kind).lights
    many = with_lights(room_scene(2), 16, kind).lights
    assert len(one) == 1 and len(many) == 16
    assert sum(light.power for light in many) == pytest.approx(one[0].power)
    low, high = room_scene(2).bounds()
    for light in many:
        assert np.all(light.position > low) and np.all(light.position < high) and light.direction[2] < 0


def test_the_scaling_fit_finds_a_line_and_its_exponent():
    xs = np.array([1e5, 5e5, 1e6, 1.5e6])
    intercept, slope, exponent = scaling_fit(xs, 3.0 + 2e-5 * xs)
    assert intercept == pytest.approx(3.0) and slope == pytest.approx(2e-5)
    assert 0 < exponent < 1  # a fixed cost makes the growth sub-linear
    assert scaling_fit(xs, 4e-6 * xs ** 2)[2] == pytest.approx(2.0)


def test_the_pareto_front_keeps_only_points_nothing_beats():
    def point(ms, error):
        return {"timings_ms": {"total_ms": ms}, "errors_vs_cm": {"relative_mse": error}}
    points = [point(10, 0.5), point(20, 0.2), point(15, 0.6), point(30, 0.2), point(40, 0.1)]
    assert [(p["timings_ms"]["total_ms"]) for p in pareto_front(points)] == [10, 20, 40]


def test_gpu_memory_counts_every_texture_and_buffer(glc):
    from lpv_preview.gpu.context import resource_bytes
    from lpv_preview.gpu.pipeline import Pipeline
    from lpv_preview.gpu.settings import Settings
    gl = glc.gl
    parts = [gl.texture((8, 4), 4, dtype="f4"), gl.texture((8, 4), 4, dtype="u4"), gl.depth_texture((8, 4)),
             gl.texture3d((2, 3, 5), 4, dtype="f4"), gl.buffer(reserve=100)]
    try:
        assert resource_bytes(*parts) == 8 * 4 * 16 * 2 + 8 * 4 * 4 + 2 * 3 * 5 * 16 + 100
    finally:
        for part in parts:
            part.release()
    pipeline = Pipeline(Settings(width=32, height=16, rsm_resolution=32, vpls_per_light=64, lpv_resolution=8), glc)
    try:
        pipeline.render(room_scene(2), passes=())
        held = pipeline.gpu_bytes()
    finally:
        pipeline.release()
    camera_images = 32 * 16 * (16 * 3 + 16 + 4)        # direct, indirect, combined; surface; depth
    cube_maps = 3 * 16 * (3 * 32) * (2 * 32)            # position, normal, flux atlases of six faces
    volumes = 9 * 8 ** 3 * 16 + 9 ** 3 * 16             # ping, pong, sums (a volume per colour each); geometry
    assert held > camera_images + cube_maps + volumes
