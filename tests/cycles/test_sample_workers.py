"""Cycles sample workers and the corrections they feed (issue 18): a border region renders
the pixels the whole image has there, a request's camera is the one rendered, Dask workers
lose no request when one dies mid-request, and a corrected render comes closer to Cycles
than its preview. Real bpy and Cycles, a real Dask cluster of local processes."""
import json
import math
import os
import time

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview import demo  # noqa: E402
from lpv_preview.__main__ import main  # noqa: E402
from lpv_preview.addon.cycles_reference import cycles_reference, render_cycles_passes  # noqa: E402
from lpv_preview.addon.cycles_samples import SampleRenderer  # noqa: E402
from lpv_preview.addon.sample_renderer import open_sample_renderer  # noqa: E402
from lpv_preview.cli.correction_runs import camera_at, turned  # noqa: E402
from lpv_preview.corrections.sample_request import SampleRequest  # noqa: E402
from lpv_preview.corrections.sample_workers import SampleWorkers  # noqa: E402
from lpv_preview.gpu.errors import LPVError  # noqa: E402
from lpv_preview.gpu.image_io import read_exr  # noqa: E402
from lpv_preview.gpu.metrics import relative_mse  # noqa: E402

from ..depsgraph_updates import recorded_updates  # noqa: E402

SIZE = (32, 24)


@pytest.fixture(scope="module")
def cornell_blend(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("samples") / "cornell.blend")
    demo.build("cornell", resolution=SIZE)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path


def test_a_region_has_the_pixels_of_the_whole_image(cornell_blend):
    renderer = SampleRenderer(cornell_blend)
    try:
        whole = renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 4, seed=3))
        part = renderer.render(SampleRequest((8, 4, 20, 14), SIZE, 4, seed=3))
    finally:
        renderer.close()
    for name, image in part.passes.items():
        assert image.shape == (10, 12, 3)
        np.testing.assert_allclose(image, whole.passes[name][4:14, 8:20], rtol=1e-4, atol=1e-6, err_msg=name)
    assert whole.passes["Combined"].mean() > 0


@pytest.mark.parametrize("size, regions", [
    ((6, 1080), [(0, 995, 6, 1024), (1, 1073, 5, 1080), (0, 128, 6, 256), (2, 0, 3, 7)]),
    ((1279, 4), [(7, 0, 14, 4), (25, 1, 31, 3), (0, 0, 1279, 2), (1270, 2, 1279, 4)]),
])
def test_a_region_of_a_large_image_has_its_pixels(cornell_blend, size, regions):
    """Blender truncates a border's single-precision fraction × size: every region still
    renders its own pixels, not a row or column more, less or beside them."""
    renderer = SampleRenderer(cornell_blend)
    try:
        whole = renderer.render(SampleRequest((0, 0, *size), size, 2, seed=3)).passes["Combined"]
        for x0, y0, x1, y1 in regions:
            part = renderer.render(SampleRequest((x0, y0, x1, y1), size, 2, seed=3)).passes["Combined"]
            np.testing.assert_allclose(part, whole[y0:y1, x0:x1], rtol=1e-4, atol=1e-6, err_msg=str((x0, y0, x1, y1)))
    finally:
        renderer.close()


def test_each_request_renders_its_own_seed_and_samples(cornell_blend):
    """Cycles' own settings do not tag the scene for an update: a request that changed only
    them must still be rendered with them, not as the request before."""
    renderer = SampleRenderer(cornell_blend)
    try:
        one = [renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 1, seed=seed)).passes["Combined"] for seed in (1, 2)]
        many = [renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 64, seed=seed)).passes["Combined"]
                for seed in (3, 4)]
        again = renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 64, seed=4)).passes["Combined"]
    finally:
        renderer.close()
    assert not np.array_equal(one[0], one[1])
    assert np.abs(many[0] - many[1]).mean() < 0.3 * np.abs(one[0] - one[1]).mean()  # 64 samples: less noise
    np.testing.assert_array_equal(again, many[1])


def test_requests_out_of_the_image_are_refused():
    with pytest.raises(LPVError, match="out of range"):
        SampleRequest((0, 0, 40, 10), SIZE, 4)
    shifted = ((1.0, 0.0, 0.2, 0.0), (0.0, 1.333, 0.0, 0.0), (0.0, 0.0, -1.0, -0.1), (0.0, 0.0, -1.0, 0.0))
    with pytest.raises(LPVError, match="unshifted perspective"):
        SampleRequest((0, 0, *SIZE), SIZE, 4, projection=shifted)


def test_a_remote_scheduler_is_reached_over_tls_only(cornell_blend):
    with pytest.raises(LPVError, match="not a tls:// address"):
        SampleWorkers(cornell_blend, open_sample_renderer, scheduler="tcp://192.0.2.1:8786")


def test_a_saved_file_is_corrected_by_a_remote_cluster_over_tls(cornell_blend, tmp_path, capsys):
    """`render FILE --correct-seconds 1 --scheduler tls://...` against a real TLS cluster
    (a self-signed certificate, in Dask's configuration as a studio would give it): its
    workers open the file itself and their samples come back."""
    import subprocess
    import dask
    from distributed import LocalCluster
    from distributed.security import Security
    cert, key = str(tmp_path / "cert.pem"), str(tmp_path / "key.pem")
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", key, "-out", cert,
                    "-days", "1", "-subj", "/CN=127.0.0.1"], check=True, capture_output=True)
    tls = {"distributed.comm.tls.ca-file": cert, "distributed.comm.require-encryption": True,
           **{f"distributed.comm.tls.{role}.{part}": path for role in ("scheduler", "worker", "client")
              for part, path in (("cert", cert), ("key", key))}}
    worker_temporary = tmp_path / "worker_tmp"  # the studio's worker's own temporary folder
    worker_temporary.mkdir()
    with dask.config.set(tls):
        with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, protocol="tls://", host="127.0.0.1",
                          dashboard_address=None, security=Security(), local_directory=str(tmp_path / "scratch"),
                          env={"TMPDIR": str(worker_temporary)}) as cluster:
            assert cluster.scheduler_address.startswith("tls://")
            assert main(["render", cornell_blend, "--out", str(tmp_path / "out"), "--width", "32", "--height", "24",
                         "--correct-seconds", "1", "--scheduler", cluster.scheduler_address]) == 0
    captured = capsys.readouterr()
    stats = json.loads(captured.out[captured.out.index("{\n"):])
    assert stats["correction_samples"] > 0
    assert os.listdir(worker_temporary) == []  # its renderer's folder went as it ended


@pytest.mark.parametrize("certificates, words", [
    ({}, "needs TLS certificates, which Dask's configuration lacks; set distributed.comm.tls.ca-file"),
    ({"ca-file": "/nonexistent/ca.pem", "client.cert": "/nonexistent/cert.pem"}, "cannot be loaded"),
], ids=["none", "missing files"])
def test_a_tls_scheduler_without_certificates_is_refused_before_the_scene_is_opened(cornell_blend, certificates,
                                                                                      words, tmp_path, capsys):
    """Without Dask's TLS settings Dask itself ends in a 30-line traceback (`TLS expects a
    ssl_context`): the command refuses in one sentence naming the settings, before any work."""
    import dask
    import distributed  # noqa: F401 (its defaults in Dask's configuration before the `set`, which removes new keys)
    tls = {f"distributed.comm.tls.{name}": certificates.get(name)
           for name in ("ca-file", "client.cert", "client.key")}
    marker = bpy.data.texts.new("untouched").name  # opening the .blend would replace it
    with dask.config.set(tls):
        assert main(["render", cornell_blend, "--out", str(tmp_path / "out"), "--width", "32", "--height", "24",
                     "--correct-seconds", "5", "--scheduler", "tls://127.0.0.1:1"]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and error[0].startswith("lpv_preview: ") and words in error[0], error
    assert "README" in error[0]
    assert marker in bpy.data.texts
    bpy.data.texts.remove(bpy.data.texts[marker])


def test_corrections_too_large_for_the_free_memory_are_refused(tmp_path, capsys, monkeypatch):
    from lpv_preview.corrections import corrector
    monkeypatch.setattr(corrector, "available_host_bytes", lambda: 2 ** 30)
    argv = ["demo", "--out", str(tmp_path), "--width", "2048", "--height", "2048", "--correct-seconds", "1"]
    assert main(argv) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "need about 3.9 GiB of memory but 1.0 GiB is free" in error[0]
    assert not os.listdir(tmp_path)


def test_a_timed_correction_stops_receiving_a_rebuild_before_its_end(cornell_blend, monkeypatch):
    """The last frame is ready as the time is up: receiving stops as long before the end as
    a rebuild is expected to take (here made 0.4 s), yet takes at least half the time."""
    from lpv_preview.corrections import corrector as corrective
    from lpv_preview.addon.render_scene import scene_to_render
    from lpv_preview.gpu.pipeline import Pipeline
    from lpv_preview.gpu.settings import Settings
    bpy.ops.wm.open_mainfile(filepath=cornell_blend)
    scene = scene_to_render(bpy.context.scene, SIZE)
    pipeline = Pipeline(Settings(width=SIZE[0], height=SIZE[1]))
    try:
        preview = pipeline.render_converged(scene, passes=("combined",)).passes["combined"]
        gbuffer = pipeline.read_gbuffer(scene)
    finally:
        pipeline.release()
    monkeypatch.setattr(corrective, "REBUILD_PIXEL_SECONDS", 0.4 / (SIZE[0] * SIZE[1]))
    with SampleWorkers(cornell_blend, open_sample_renderer, workers=2) as workers:
        workers.open_everywhere()
        workers.settle(SIZE)  # Cycles has the scene: the first requests come back at once
        received = []
        for seconds, receiving in ((1.0, 0.6), (0.5, 0.25)):
            corrector = corrective.Corrector(workers)
            corrector.rest(scene.camera.key(), scene.camera, None, preview, gbuffer)
            started = time.perf_counter()
            timeline = list(corrector.run(seconds))
            ended = time.perf_counter() - started
            corrector.cancel()
            assert receiving - 0.05 <= ended <= receiving + 0.5, (seconds, ended)
            assert len(timeline) == 1
            received.append(corrector.samples_received)
            workers.settle(SIZE)
    assert received[0] > 0


def test_no_request_is_lost_when_a_worker_dies(cornell_blend):
    """Two local workers; one is killed while it renders; every request still returns."""
    requests = [SampleRequest((0, 0, *SIZE), SIZE, 64, seed=seed) for seed in range(6)]
    with SampleWorkers(cornell_blend, open_sample_renderer, workers=2) as workers:
        futures = [workers.submit(request) for request in requests]
        deadline = time.time() + 60
        while time.time() < deadline and not any(workers.client.processing().values()):
            time.sleep(0.05)
        busy = next(address for address, tasks in workers.client.processing().items() if tasks)
        nanny = next(worker for worker in workers.cluster.workers.values() if worker.worker_address == busy)
        nanny.process.process.kill()
        results = workers.client.gather(futures)
    assert [result.request.seed for result in results] == list(range(6))
    assert all(result.passes["Combined"].shape == (SIZE[1], SIZE[0], 3) for result in results)


def test_a_request_renders_its_own_camera(cornell_blend):
    """A request's camera world matrix, not the file's, is the one Cycles renders (and the
    file's again for a request without one)."""
    bpy.ops.wm.open_mainfile(filepath=cornell_blend)
    scene = bpy.context.scene
    matrix = turned(scene.camera.matrix_world.copy(), 30.0)
    with camera_at(scene, matrix):
        expected = render_cycles_passes(scene, ("Combined",), 64, SIZE, 0, 12, 0.0, 0.01)["Combined"]
    own = render_cycles_passes(scene, ("Combined",), 64, SIZE, 0, 12, 0.0, 0.01)["Combined"]
    from lpv_preview.addon.extract import extract_camera
    camera = extract_camera(bpy.context.evaluated_depsgraph_get(), SIZE)  # the 3D view's kind of camera
    renderer = SampleRenderer(cornell_blend)
    try:
        turned_render = renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 64, 5, tuple(map(tuple, matrix))))
        own_render = renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 64, 6))
        projected = renderer.render(SampleRequest((0, 0, *SIZE), SIZE, 64, 7, tuple(map(tuple, np.linalg.inv(
            camera.view))), tuple(map(tuple, camera.projection))))
    finally:
        renderer.close()
    assert relative_mse(projected.passes["Combined"], own) < 0.5 * relative_mse(projected.passes["Combined"], expected)
    assert relative_mse(turned_render.passes["Combined"], expected) < 0.5 * relative_mse(
        turned_render.passes["Combined"], own)
    assert relative_mse(own_render.passes["Combined"], own) < 0.5 * relative_mse(own_render.passes["Combined"],
                                                                                 expected)


def test_a_corrected_render_comes_closer_to_cycles(tmp_path, capsys):
    """`demo --correct-seconds 3 --workers 2`: samples come, and the combined image is far
    closer to Cycles' full global illumination than the preview kept beside it."""
    size = ("--width", "32", "--height", "24")
    assert main(["demo", "--out", str(tmp_path), *size, "--correct-seconds", "3", "--workers", "2"]) == 0
    captured = capsys.readouterr()
    stats = json.loads(captured.out[captured.out.index("{\n"):])
    assert stats["correction_samples"] > 0 and stats["correction_samples_per_second"] > 0
    assert 0 < stats["correction_estimated_error"] < 1
    passes = read_exr(str(tmp_path / "passes.exr"))
    reference = cycles_reference(bpy.context.scene, "full_gi", 256, 0, SIZE).combined_pass
    preview_error = relative_mse(passes["preview"], reference)
    # Measured: 0.0110 against the preview's 0.0214 (0.0268 while the light grid's lookup
    # read cells across walls, 0.0362 while the preview's later bounces lost light to a
    # grown 1/r² bound, docs/method.md "Bounces"); the corrected image's error is mostly the
    # 256-sample reference's and the corrections' noise.
    assert relative_mse(passes["combined"], reference) < 0.6 * preview_error
    assert math.isfinite(preview_error)


def test_each_frame_of_an_animation_is_corrected_toward_its_own_cycles_render(tmp_path, capsys):
    """`render --frames 1-2 --correct-seconds 2`: the camera turns 30° between the frames;
    the workers render each frame's own view, so each corrected frame comes closer to
    Cycles at its frame than its preview, and than to Cycles at the other frame."""
    scene = demo.build("cornell", resolution=SIZE)
    bpy.context.view_layer.update()  # the camera's world matrix from its location and rotation
    camera = scene.camera
    for frame, degrees in ((1, 0.0), (2, 30.0)):
        camera.matrix_world = turned(camera.matrix_world.copy(), degrees)
        camera.keyframe_insert("rotation_euler", frame=frame)
        camera.keyframe_insert("location", frame=frame)
    blend = tmp_path / "turning.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    out = tmp_path / "frames"
    argv = ["render", str(blend), "--frames", "1-2", "--out", str(out), "--width", "32", "--height", "24",
            "--correct-seconds", "2", "--workers", "2"]
    assert main(argv) == 0
    captured = capsys.readouterr()
    stats = json.loads(captured.out[captured.out.index("{\n"):])
    assert sorted(stats["corrections"]) == ["1", "2"]
    assert all(frame["correction_samples"] > 0 for frame in stats["corrections"].values())
    references, scene = [], bpy.context.scene  # the file `render` opened
    for frame in (1, 2):
        scene.frame_set(frame)
        references.append(cycles_reference(scene, "full_gi", 256, 0, SIZE).combined_pass)
    for index, frame in enumerate((1, 2)):
        passes = read_exr(str(out / f"frame_000{frame}.exr"))
        own, other = references[index], references[1 - index]
        # Measured: 0.0111 against the preview's 0.0214 (0.0268 while the light grid's
        # lookup read cells across walls; further still before its later bounces kept their
        # light, docs/method.md "Bounces"), the corrected error mostly noise.
        assert relative_mse(passes["combined"], own) < 0.6 * relative_mse(passes["preview"], own)
        assert relative_mse(passes["combined"], own) < 0.4 * relative_mse(passes["combined"], other)
    assert main(argv[:-4]) == 0  # without corrections, the corrected frames are not the ones asked for
    assert "made 2 corrected for another time (2 s)" in capsys.readouterr().err


@pytest.mark.parametrize("argv, words", [
    (["render", "missing.blend", "--scheduler", "tls://192.0.2.1:8786"], "give --correct-seconds too"),
    (["render", "missing.blend", "--correct-seconds", "2", "--scheduler", "tcp://192.0.2.1:8786"],
     "not a tls:// address"),
    (["render", "missing.blend", "--correct-seconds", "2", "--scheduler", "tls://192.0.2.1:8786", "--workers", "2"],
     "give one of them"),
    (["demo", "--correct-seconds", "-1"], "correct_seconds"),
    (["bench", "--corrections", "--gpu-previews", "missing.json"], "Cannot read the GPU's preview times"),
    (["bench", "--corrections", "--bounces", "99"], "Setting 'bounces' is 99"),  # the previews' settings
    (["bench", "--corrections", "--width", "100"], "leave out --width and --height"),
])
def test_bad_correction_flags_are_refused_before_any_work(argv, words, tmp_path, capsys):
    assert main([*argv, "--out", str(tmp_path)]) == 2
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and words in error[0]


def test_gpu_preview_times_of_another_size_are_refused(tmp_path, capsys):
    times = tmp_path / "previews.json"
    times.write_text(json.dumps({"scenes": {"cornell": {"size": [64, 64], "preview_ms": 3.0}}}))
    assert main(["bench", "--corrections", "--gpu-previews", str(times), "--out", str(tmp_path / "out")]) == 2
    assert "timed at 64 x 64, not at the benchmark's 128 x 128" in capsys.readouterr().err


def test_the_still_viewport_streams_corrections_and_keeps_them_over_a_move():
    """A viewport session with corrections on: a still view improves redraw after redraw
    toward Cycles, a small camera move rests on the corrections that still apply, a
    material edit starts them again on a new copy of the scene once edits stop, switching
    them off removes it all, and on again starts afresh."""
    import lpv_preview
    from lpv_preview.addon.extract import extract_camera
    from lpv_preview.addon.viewport import ViewportSession
    scene = demo.build("cornell", resolution=SIZE)
    lpv_preview.register()
    session = ViewportSession()
    try:
        properties = scene.lpv_preview
        properties.rsm_resolution, properties.vpls_per_light, properties.lpv_resolution = 64, 256, 16
        properties.viewport_corrections, properties.correction_viewport_width = True, SIZE[0]

        def redraw():
            depsgraph = bpy.context.evaluated_depsgraph_get()
            frame = session.frame_to_draw(depsgraph, extract_camera(depsgraph, SIZE), SIZE)
            return frame, np.array(session.display.rows.reshape(SIZE[1], SIZE[0], 3)[::-1])

        first, preview = redraw()  # the view is new: shown as it is
        assert "correction_problem" not in first.stats and session.corrections.streaming
        deadline = time.time() + 20
        while time.time() < deadline and first.stats.get("correction_samples", 0) < 200_000:
            time.sleep(0.1)
            first, image = redraw()
        reference = cycles_reference(scene, "full_gi", 256, 0, SIZE).combined_pass
        # Measured: 0.0154 against the preview's 0.0303 (0.0132 against 0.0326 before the
        # light grid's clusters were squares): what is left is mostly the 256-sample
        # reference's own noise, so a closer preview leaves the corrections less to halve.
        assert relative_mse(image, reference) < 0.6 * relative_mse(preview, reference)
        folder = session.corrections.folder
        assert os.listdir(folder) == ["scene_1.blend"]

        scene.camera.location.x += 0.02
        _, moved_preview = redraw()  # moving: the preview alone
        moved, moved_image = redraw()  # at rest: the layers of the view before apply
        moved_reference = cycles_reference(scene, "full_gi", 256, 0, SIZE).combined_pass
        assert relative_mse(moved_image, moved_reference) < 0.6 * relative_mse(moved_preview, moved_reference)

        material = next(m for m in bpy.data.materials if m.users and m.node_tree)
        colour = material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value
        session.note_updates(recorded_updates(lambda: colour.__setitem__(1, colour[1] * 0.9)))
        redraw()  # while edits come, nothing is written
        assert sorted(os.listdir(folder)) == ["scene_1.blend"] and session.corrections.streaming
        edited, _ = redraw()  # the edits stopped: a fresh copy, the corrections from nothing
        assert edited.stats["correction_samples"] == 0 and os.path.isfile(os.path.join(folder, "scene_2.blend"))

        properties.viewport_corrections = False
        redraw()
        assert not os.path.exists(folder) and not session.corrections.streaming
        properties.viewport_corrections = True
        redraw()  # shown first
        again, _ = redraw()  # then at rest: the workers start again
        assert session.corrections.workers is not None and "correction_problem" not in again.stats
    finally:
        session.release()
        lpv_preview.unregister()
