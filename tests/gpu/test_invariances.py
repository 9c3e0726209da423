"""The same scene anywhere in the world, at any scale and against any grid phase gives the
same picture (bench/invariance.py measures the figures for docs/numerical_stability.md;
these are looser bounds on smaller images), a light sliding across cells changes the
picture smoothly, and the fuzzer finds nothing that escapes as an exception."""
import dataclasses

import numpy as np
import pytest

from lpv_preview.bench.fuzz import fuzz, random_scene
from lpv_preview.bench.synthetic import room_scene
from lpv_preview.gpu.metrics import psnr
from lpv_preview.gpu.pipeline import Pipeline, render_once
from lpv_preview.gpu.settings import Settings

SETTINGS = Settings(width=48, height=48, rsm_resolution=128, vpls_per_light=512, lpv_resolution=16, method="wdpm")


@pytest.fixture(scope="module")
def reference(glc):
    return render_once(room_scene(6), SETTINGS, glc).passes


@pytest.mark.parametrize("offset", [100.0, 1234.567, 1e6])
def test_the_room_far_from_the_origin_renders_like_the_room_at_it(glc, reference, offset):
    moved = render_once(room_scene(6, offset=(offset, offset, 0.0)), SETTINGS, glc).passes
    assert psnr(moved["direct"], reference["direct"]) > 45
    assert psnr(moved["indirect"], reference["indirect"]) > 35


def test_a_far_room_is_kept_relative_to_a_local_origin():
    far = room_scene(2, offset=(1e6, -3e5, 0.0))
    np.testing.assert_allclose(far.origin, (1e6, -3e5, 1.5))
    assert np.abs(far.triangles).max() <= 2.0 and far.triangles.dtype == np.float32
    assert room_scene(2).origin is None  # near the world origin nothing moves


@pytest.mark.parametrize("shift", [0.25, 0.75])
def test_moving_the_grid_against_the_room_barely_changes_the_indirect_light(glc, reference, shift):
    shifted = render_once(room_scene(6), SETTINGS.with_changes(grid_shift=shift), glc).passes
    assert psnr(shifted["indirect"], reference["indirect"]) > 24


def test_one_grid_alone_depends_more_on_its_phase_than_two(glc):
    one = SETTINGS.with_changes(grid_phases=1)
    alone, moved = (render_once(room_scene(6), one.with_changes(grid_shift=f), glc).passes["indirect"]
                    for f in (0.0, 0.5))
    averaged, averaged_moved = (render_once(room_scene(6), SETTINGS.with_changes(grid_shift=f), glc).passes["indirect"]
                                for f in (0.0, 0.25))
    assert psnr(averaged_moved, averaged) > psnr(moved, alone) + 3


def test_scaling_the_room_keeps_its_radiance(glc, reference):
    for scale in (1e-3, 1e3):
        scaled = render_once(room_scene(6, scale=scale), SETTINGS, glc).passes
        assert psnr(scaled["direct"], reference["direct"]) > 45
        assert psnr(scaled["indirect"], reference["indirect"]) > 28


def test_a_light_sliding_across_cells_changes_the_picture_smoothly(glc):
    """A fifth of a cell a frame over two cells: no frame jumps more than twice as much as
    the typical frame (a light or VPL snapping into the next cell would)."""
    pipeline = Pipeline(SETTINGS, glc)
    frames = []
    try:
        for k in range(12):
            scene = room_scene(6, light_position=(0.4 + 0.05 * k, -0.3, 2.0))
            frames.append(pipeline.render(scene, passes=("indirect",)).passes["indirect"])
            cell = pipeline.last_indirect.grids[0].cell_size
    finally:
        pipeline.release()
    assert 0.05 < cell * 0.5  # at most half a cell a frame
    changes = np.array([np.abs(b - a).mean() for a, b in zip(frames, frames[1:])])
    assert changes.max() < 2 * np.median(changes)


def test_fuzzed_scenes_render_or_stop_with_one_sentence(glc):
    report = fuzz(range(30), seconds=60, glc=glc)
    assert report["failures"] == [] and report["counts"]["rendered"] > 20
    assert set(report["refusals"]) <= {"The scene has no lights; add a point, spot, area or sun light, an emissive "
                                       "material, or a world that emits light.",
                                       "The scene has no renderable triangles; add a visible mesh object.",
                                       "The scene has no camera; add a camera and make it the scene's active camera."}


def test_the_fuzzer_is_seeded():
    first, second = random_scene(7), random_scene(7)
    np.testing.assert_array_equal(first.triangles, second.triangles)
    assert [dataclasses.asdict(light)["kind"] for light in first.lights] == [
        dataclasses.asdict(light)["kind"] for light in second.lights]
