"""The command line writes every promised output and fails with one line on bad input."""
import json
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.gpu.image_io import read_exr  # noqa: E402

SMALL = ["--width", "64", "--height", "64", "--rsm-resolution", "128", "--vpls-per-light", "512"]


def test_demo_writes_exr_pngs_and_stats(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["demo", "--out", str(out), *SMALL]) == 0
    assert sorted(os.listdir(out)) == ["combined.png", "indirect.png", "passes.exr", "stats.json"]
    passes = read_exr(str(out / "passes.exr"))
    assert sorted(passes) == ["combined", "direct", "indirect"]
    for image in passes.values():
        assert image.shape == (64, 64, 3) and np.all(np.isfinite(image))
    stats = json.loads((out / "stats.json").read_text())
    assert stats["vpl_count"] == 512 and stats["triangles"] == 900
    assert all(stats[k] > 0 for k in ("rsm_ms", "vpl_ms", "propagate_ms", "total_ms"))


def test_render_a_saved_blend_file(tmp_path):
    from lpv_preview.demo import build
    build("cornell")
    blend = tmp_path / "cornell.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "render"
    assert main(["render", str(blend), "--out", str(out), *SMALL]) == 0
    assert read_exr(str(out / "passes.exr"))["combined"].shape == (64, 64, 3)
    assert main(["render", str(blend), "--out", str(out), "--debug-passes", "--method", "wdpm", *SMALL]) == 0
    passes = read_exr(str(out / "passes.exr"))
    assert sorted(passes) == ["combined", "direct", "indirect", "vpl_splats", "warp_status"]
    assert passes["vpl_splats"].sum() > 0 and passes["warp_status"].sum() > 0


def test_an_animation_renders_one_exr_a_frame_and_resumes(tmp_path, capsys):
    from lpv_preview.demo import build
    scene = build("cornell")
    light = next(o for o in scene.objects if o.type == "LIGHT")
    for frame, x in ((1, -0.3), (3, 0.3)):  # the light slides across the ceiling
        light.location.x = x
        light.keyframe_insert("location", index=0, frame=frame)
    blend = tmp_path / "animated.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "frames"
    argv = ["render", str(blend), "--frames", "1-3", "--out", str(out), *SMALL]

    def run(*extra):
        assert main([*argv, *extra]) == 0
        captured = capsys.readouterr()  # Blender's own log lines come before our JSON
        return json.loads(captured.out[captured.out.index("{\n"):]), captured.err

    stats, progress = run()
    assert sorted(os.listdir(out)) == ["frame_0001.exr", "frame_0002.exr", "frame_0003.exr"]
    assert (stats["rendered"], stats["skipped"]) == (3, 0) and "3/3" in progress
    images = [read_exr(str(out / f"frame_000{f}.exr"))["direct"] for f in (1, 2, 3)]
    left, right = (image[:, :32].mean() - image[:, 32:].mean() for image in (images[0], images[2]))
    assert left > 0 > right  # the light moved from left to right
    assert run()[0]["rendered"] == 0  # everything there: nothing to do
    os.remove(out / "frame_0002.exr")
    stats, _ = run()
    assert (stats["rendered"], stats["skipped"]) == (1, 2)
    assert run("--overwrite")[0]["rendered"] == 3


def test_a_rerun_renders_again_the_frames_made_with_other_settings_or_size(tmp_path, capsys):
    from lpv_preview.demo import build
    build("cornell")
    blend = tmp_path / "still.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "frames"

    def run(*flags):
        assert main(["render", str(blend), "--frames", "1-2", "--out", str(out), *flags]) == 0
        captured = capsys.readouterr()
        stats = json.loads(captured.out[captured.out.index("{\n"):])
        return (stats["rendered"], stats["skipped"], stats["rendered_again"]), captured.err

    small = ["--rsm-resolution", "64", "--vpls-per-light", "256", "--lpv-resolution", "16"]
    assert run("--width", "24", "--height", "16", *small)[0] == (2, 0, {})
    assert run("--width", "24", "--height", "16", *small)[0] == (0, 2, {})  # the same: kept
    stats, err = run("--width", "20", "--height", "16", *small)
    assert stats == (2, 0, {"at another size (24×16)": 2})
    assert f"lpv_preview: rendering again 2 frames already in '{out}', made 2 at another size (24×16)." in err
    assert read_exr(str(out / "frame_0002.exr"))["combined"].shape == (16, 20, 3)
    stats, err = run("--width", "20", "--height", "16", *small[:2], "--method", "wdpm")
    assert stats == (2, 0, {"with other settings (method, vpls_per_light, lpv_resolution)": 2}), err
    stats, _ = run("--width", "20", "--height", "16", *small[:2], "--method", "wdpm", "--debug-passes")
    assert stats == (2, 0, {"with other passes": 2})
    with open(out / "frame_0001.exr", "wb") as handle:  # not an EXR of ours, nor any
        handle.write(b"not an image")
    stats, _ = run("--width", "20", "--height", "16", *small[:2], "--method", "wdpm", "--debug-passes")
    assert stats == (1, 1, {"with no record of its settings": 1})


@pytest.mark.parametrize("argv, words", [
    (["render", "/nonexistent/scene.blend"], "There is no file"),
    (["demo", "--rsm-resolution", "5"], "rsm_resolution"),
    (["demo", "--out", "/proc/forbidden", *SMALL], "Cannot"),
    (["render", __file__, "--frames", "1-x"], "--frames"),
])
def test_errors_print_one_line(argv, words, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and len(err.splitlines()) == 1, err
