"""The command line writes every promised output and fails with one line on bad input."""
import json
import os

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.gpu.capacity import available_host_bytes  # noqa: E402
from lpv_preview.gpu.image_io import read_exr  # noqa: E402
from lpv_preview.gpu.indirect import INDIRECT_STAGES  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402

SMALL = ["--width", "64", "--height", "64", "--rsm-resolution", "128", "--vpls-per-light", "512"]


def test_demo_writes_exr_pngs_and_stats(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["demo", "--out", str(out), *SMALL]) == 0
    assert sorted(os.listdir(out)) == ["combined.png", "indirect.png", "passes.exr", "stats.json"]
    passes = read_exr(str(out / "passes.exr"))
    assert sorted(passes) == ["combined", "direct", "indirect", "reflections"]
    for image in passes.values():
        assert image.shape == (64, 64, 3) and np.all(np.isfinite(image))
    stats = json.loads((out / "stats.json").read_text())
    assert stats["vpl_count"] == 512 + 64 and stats["glossy_vpl_count"] == 64 and stats["triangles"] == 900
    assert all(stats[k] > 0 for k in ("rsm_ms", "vpl_ms", *INDIRECT_STAGES[Settings().indirect_method], "total_ms"))


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
    assert sorted(passes) == ["combined", "direct", "indirect", "reflections", "vpl_splats", "warp_status"]
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

    small = ["--rsm-resolution", "64", "--vpls-per-light", "256", "--lpv-resolution", "8"]
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


@pytest.fixture(scope="module")
def cornell_blend(tmp_path_factory):
    from lpv_preview.demo import build
    build("cornell")
    blend = tmp_path_factory.mktemp("blend") / "cornell.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    return blend


def refused_before_any_work(argv, capsys):
    """main's one line of error for `argv`, checked to come before any work: Blender's
    current file, which building a demo scene or opening a .blend replaces, keeps a marker."""
    marker = bpy.data.texts.new("untouched").name
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert marker in bpy.data.texts, f"work was done before the refusal: {err}"
    bpy.data.texts.remove(bpy.data.texts[marker])
    return err


@pytest.mark.parametrize("argv", [
    ["demo", "--out", "OUT", *SMALL],
    ["render", "BLEND", "--out", "OUT", *SMALL],
    ["compare", "cornell", "--samples", "1", "--no-cache", "--out", "OUT", *SMALL],
    ["export", "cornell", "--out", "OUT/scene.npz"],
    ["bench", "--scenes", "cornell", "--methods", "cm", "--frames", "1", "--repeats", "1", "--out", "OUT", *SMALL],
], ids=lambda argv: argv[0])
def test_an_unwritable_out_is_refused_before_any_work(argv, cornell_blend, tmp_path, capsys):
    blocker = tmp_path / "a_file"  # a folder cannot be made inside a file, even by root
    blocker.write_text("")
    out = blocker / "out"
    argv = [arg.replace("OUT", str(out)).replace("BLEND", str(cornell_blend)) for arg in argv]
    err = refused_before_any_work(argv, capsys)
    assert err == (f"lpv_preview: Cannot write into the output folder '{out}' (Not a directory); "
                   f"choose a writable folder.")


def test_bench_scenes_that_are_neither_demo_scenes_nor_files_are_refused_before_any_work(tmp_path, capsys):
    out = tmp_path / "new" / "bench"
    err = refused_before_any_work(["bench", "--scenes", "cornell,nope", "--methods", "cm", "--out", str(out),
                                   *SMALL], capsys)
    assert err == ("lpv_preview: The bench scene 'nope' is neither a demo scene (cornell, atrium, city, particles) nor an "
                   ".npz scene file that exists; check --scenes.")
    assert not (tmp_path / "new").exists()  # the check of --out removed the folders it made


def test_setting_flags_are_refused_before_the_scene_is_built(tmp_path, capsys):
    err = refused_before_any_work(["demo", "--scene", "atrium", "--rsm-resolution", "5", "--out", str(tmp_path)],
                                  capsys)
    assert err == "lpv_preview: Setting 'rsm_resolution' is 5; it must lie between 16 and 2048."


@pytest.mark.parametrize("argv, message", [
    (["demo", "--triangles", "100"], "The demo scene 'cornell' has a fixed triangle count; give a triangle count "
                                     "only for atrium or city."),
    (["demo", "--scene", "atrium", "--triangles", "-5"], "The demo scene 'atrium' is built with 5,000 to "
                                                         "10,000,000 triangles, not -5; choose a triangle count in "
                                                         "that range."),
    (["demo", "--scene", "atrium", "--triangles", "100000000"], "The demo scene 'atrium' is built with 5,000 to "
                                                                "10,000,000 triangles, not 100,000,000; choose a "
                                                                "triangle count in that range."),
    (["demo", "--scene", "city", "--triangles", "0"], "The demo scene 'city' is built with 500 to 10,000,000 "
                                                      "triangles, not 0; choose a triangle count in that range."),
    (["export", "city", "--triangles", "0", "--out", "OUT/city.npz"], "The demo scene 'city' is built with 500 to "
                                                                      "10,000,000 triangles, not 0; choose a "
                                                                      "triangle count in that range."),
], ids=["cornell", "atrium-negative", "atrium-huge", "city-zero", "export-city-zero"])
def test_triangle_counts_a_scene_cannot_be_built_with_are_refused(argv, message, tmp_path, capsys):
    argv = [arg.replace("OUT", str(tmp_path)) for arg in argv]
    if argv[0] == "demo":
        argv += ["--out", str(tmp_path), *SMALL]
    assert refused_before_any_work(argv, capsys) == "lpv_preview: " + message


@pytest.mark.parametrize("flag", ["--repeats", "--frames"])
def test_bench_counts_below_one_are_refused_by_the_parser(flag, tmp_path, capsys):
    with pytest.raises(SystemExit) as exit:
        main(["bench", "--scenes", "cornell", "--methods", "cm", "--out", str(tmp_path), *SMALL, flag, "0"])
    assert exit.value.code == 2
    assert f"argument {flag}: '0' is not a whole number of at least 1" in capsys.readouterr().err


def test_a_frame_larger_than_the_memory_free_is_refused_in_one_line(tmp_path, capsys):
    if available_host_bytes() > 64 * 2 ** 30:
        pytest.skip("this machine has the memory of a 16384 x 16384 frame (about 66 GiB on llvmpipe)")
    assert main(["demo", "--width", "16384", "--height", "16384", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lpv_preview: A 16384 x 16384 frame needs about ") and len(err.splitlines()) == 1, err
    assert not os.listdir(tmp_path)


def test_compare_is_refused_before_the_cycles_references_where_our_renderer_cannot_run(tmp_path, capsys,
                                                                                     monkeypatch):
    monkeypatch.setenv("LPV_PREVIEW_NO_GPU", "1")
    cache = tmp_path / "cycles"
    argv = ["compare", "cornell", "--samples", "1", "--cache", str(cache), "--out", str(tmp_path / "out"), *SMALL]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("lpv_preview: No OpenGL 4.5 context is available") and len(err.splitlines()) == 1, err
    assert not cache.exists() or not any(cache.iterdir())



TINY = ["--out", "TMP/out", "--width", "32", "--height", "24"]


def saved_blend(path, edit):
    """The Cornell box at 32 x 24 after `edit(scene)`, saved at `path`; an empty file when
    `edit` is None."""
    from lpv_preview.demo import build
    if edit is None:
        bpy.ops.wm.read_factory_settings(use_empty=True)
    else:
        edit(build("cornell", resolution=(32, 24)))
    bpy.ops.wm.save_as_mainfile(filepath=str(path))


def without_camera(scene):
    bpy.data.objects.remove(scene.camera)


def at_one_percent(scene):
    scene.render.resolution_percentage = 1


ODD_BLENDS = {"EMPTY": None, "NO_CAMERA": without_camera, "ONE_PERCENT": at_one_percent}
"""The .blend files a user might give, by the name the arguments below give them."""


@pytest.mark.parametrize("argv, error", [
    (["render", "TMP/EMPTY.blend", *TINY],
     "The scene has no camera; add a camera and make it the scene's active camera."),
    (["render", "TMP/NO_CAMERA.blend", "--correct-seconds", "1", *TINY],
     "The scene has no camera; add a camera and make it the scene's active camera."),
    (["compare", "TMP/NO_CAMERA.blend", "--samples", "1", "--no-cache", *TINY],
     "The scene has no camera; add a camera and make it the scene's active camera."),
    (["render", "TMP/ONE_PERCENT.blend", *TINY],
     "Scene 'Scene' renders 1 % of 32 x 24 pixels, too small for Blender; raise its Output resolution or percentage."),
    (["export", "cornell", "--out", "TMP"], "--out 'TMP' is not a .npz file's path; give one like TMP/cornell.npz."),
    (["export", "cornell", "--out", "TMP/scene"],
     "--out 'TMP/scene' is not a .npz file's path; give one like TMP/scene.npz."),
    (["bench", "--report", "TMP/table.json", "--out", "TMP/out"],
     "'TMP/table.json' is not a sweep report (it lacks sweep, description, repeats, points); give a "
     "sweep_NAME.json file that `bench --sweep NAME` wrote."),
], ids=["empty scene", "no camera, corrected", "compare without camera", "1 % resolution", "export to a folder",
        "export without .npz", "bench report of another JSON"])
def test_odd_inputs_are_refused_in_one_sentence(argv, error, tmp_path, capsys):
    """What a user might try (issue 29): each ends in one sentence that names the fix and
    status 2, never a traceback, and leaves no output behind."""
    for name, edit in ODD_BLENDS.items():
        if any(f"/{name}." in arg for arg in argv):
            saved_blend(tmp_path / f"{name}.blend", edit)
    (tmp_path / "table.json").write_text(json.dumps({"machine": {}, "rows": []}))  # Table 1's, say
    before = sorted(os.listdir(tmp_path))
    assert main([arg.replace("TMP", str(tmp_path)) for arg in argv]) == 2
    assert capsys.readouterr().err.strip().splitlines() == ["lpv_preview: " + error.replace("TMP", str(tmp_path))]
    assert sorted(os.listdir(tmp_path)) == before


def test_the_renderer_is_named_and_a_software_one_warned_of_once(glc, tmp_path, capsys):
    """stats.json and each EXR's header name the OpenGL renderer; on a software rasterizer
    (llvmpipe here) they carry the warning too, and each command prints it once."""
    from lpv_preview.addon.batch import RENDERER_ATTRIBUTE, RENDERER_WARNING_ATTRIBUTE
    from lpv_preview.addon.frame_stats import renderer_warning
    from lpv_preview.gpu.image_io import read_exr_metadata
    warning = renderer_warning({"renderer": glc.renderer, "software_renderer": glc.is_software})
    assert (warning is not None) == glc.is_software
    assert main(["demo", "--out", str(tmp_path / "demo"), "--width", "32", "--height", "24"]) == 0
    captured = capsys.readouterr()
    stats = json.loads((tmp_path / "demo" / "stats.json").read_text())
    assert stats["renderer"] == glc.renderer and stats["software_renderer"] == glc.is_software
    assert stats.get("renderer_warning") == warning
    printed = [line for line in captured.err.splitlines() if line.startswith("lpv_preview: warning: ")]
    assert printed == ([f"lpv_preview: warning: {warning}"] if warning else [])
    exrs = [tmp_path / "demo" / "passes.exr"]
    blend = tmp_path / "cornell.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))  # the demo scene just built
    assert main(["render", str(blend), "--frames", "1-2", "--out", str(tmp_path / "frames"), "--width", "32",
                 "--height", "24"]) == 0
    captured = capsys.readouterr()
    assert captured.err.count("lpv_preview: warning: ") == (1 if warning else 0)
    assert json.loads(captured.out[captured.out.index("{\n"):])["renderer"] == glc.renderer
    exrs += [tmp_path / "frames" / "frame_0001.exr", tmp_path / "frames" / "frame_0002.exr"]
    for exr in exrs:
        assert read_exr_metadata(exr, RENDERER_ATTRIBUTE) == glc.renderer
        assert read_exr_metadata(exr, RENDERER_WARNING_ATTRIBUTE) == warning
