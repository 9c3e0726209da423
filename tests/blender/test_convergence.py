"""A still image converges: each frame another VPL pattern, averaged into the last; and a
second bounce from a second generation of VPLs. Real bpy scenes on real GL."""
import copy
import dataclasses

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from lpv_preview.addon.render_scene import scene_to_render  # noqa: E402
from lpv_preview.gpu.pipeline import Pipeline  # noqa: E402
from lpv_preview.gpu.scene import Film  # noqa: E402
from lpv_preview.gpu.settings import Settings  # noqa: E402
from lpv_preview.gpu.vpl import (VPLSet, concentric_disk, concentric_square, poisson_disk_points,  # noqa: E402
                                 shifted_pattern)

from ..leak_scenes import lone_floor, thin_wall  # noqa: E402

SIZE = (48, 36)
SMALL = dict(width=SIZE[0], height=SIZE[1], method="wdpm", rsm_resolution=64, vpls_per_light=256)


def test_shifted_patterns_land_anywhere_alike_and_stay_in_their_disk():
    square = np.random.default_rng(3).random((500, 2)) * 2 - 1
    np.testing.assert_allclose(concentric_square(concentric_disk(square)), square, atol=1e-9)
    for in_disk in (False, True):
        points = poisson_disk_points(128, in_disk)
        assert shifted_pattern(points, in_disk, 0) is points
        moved = [shifted_pattern(points, in_disk, pattern) for pattern in range(1, 400)]
        assert all(np.all((0 <= m) & (m < 1)) for m in moved)
        assert not np.allclose(moved[0], moved[1])
        first = np.array([m[0] for m in moved]) * 2 - 1  # one point over every pattern
        if in_disk:
            assert all(np.max(np.sum((2 * m - 1) ** 2, axis=1)) <= 1 + 1e-6 for m in moved)
            assert abs(np.mean(np.sum(first ** 2, axis=1)) - 0.5) < 0.05  # r² is uniform over a disk
        else:
            np.testing.assert_allclose(np.mean(first, axis=0), 0.0, atol=0.08)


@pytest.fixture(scope="module")
def rooms():
    built = thin_wall(SIZE)
    built.scene.camera.location = (-2.8, 1.3, 1.6)  # into the lit room
    return scene_to_render(built.scene)


@pytest.mark.parametrize("method", ["vpl_gather", "light_grid"])
def test_a_still_frame_averages_its_vpl_sets_and_a_change_starts_again(rooms, method):
    rooms = dataclasses.replace(rooms, film=Film(filter_width=0.0))  # no sub-pixel offsets: the sets are comparable
    settings = Settings(indirect_method=method, bounces=1, **SMALL)  # one bounce: the pixel gather's bound alone differs
    pipeline = Pipeline(settings)
    try:
        first = pipeline.render(rooms, vpl_set=0, passes=("indirect",))
        # the pixel gather's second set of a converging frame bounds 1/r² half as much (settings.py)
        bound = 0.5 if method == "vpl_gather" else 1.0
        other = pipeline.render(rooms, settings.with_changes(singularity_bound=bound), vpl_set=1, passes=("indirect",))
        assert first.stats["vpl_sets"] == other.stats["vpl_sets"] == 1
        assert not np.allclose(first.passes["indirect"], other.passes["indirect"])
        pipeline.render(rooms, settings, vpl_set=0, passes=())
        both = pipeline.render(rooms, vpl_set=1, accumulate=True, passes=("indirect",))
        assert both.stats["vpl_sets"] == 2 and both.stats["accumulated_vpls"] == 2 * both.stats["vpl_count"]
        np.testing.assert_allclose(both.passes["indirect"], (first.passes["indirect"] + other.passes["indirect"]) / 2,
                                   rtol=1e-4, atol=1e-6)
        # a new pattern samples VPLs again, not the maps; with no sub-pixel offsets the view is
        # the same, so its G-buffer is kept
        assert "rsm_ms" not in both.stats and "gbuffer_ms" not in both.stats and "direct_ms" in both.stats
        moved = copy.copy(rooms)
        moved.camera = rooms.camera.moved_by((0.05, 0.0, 0.0))
        assert pipeline.render(moved, vpl_set=2, accumulate=True, passes=()).stats["vpl_sets"] == 1
        changed = Settings(indirect_method=method, indirect_intensity=1.5, bounces=1, **SMALL)
        assert pipeline.render(moved, changed, vpl_set=3, accumulate=True, passes=()).stats["vpl_sets"] == 1
        assert pipeline.render(moved, changed, vpl_set=4, accumulate=True, passes=()).stats["vpl_sets"] == 2
    finally:
        pipeline.release()


def test_a_rendered_frame_averages_as_many_sets_as_asked_or_for_as_long(rooms):
    pipeline = Pipeline()
    try:
        counted = pipeline.render_converged(rooms, Settings(indirect_method="vpl_gather", converge_sets=3, **SMALL))
        assert counted.stats["vpl_sets"] == 3 and counted.stats["vpl_pattern"] == 2
        assert counted.passes["indirect"].mean() > 0 and counted.stats["converge_ms"] >= counted.stats["total_ms"]
        timed = pipeline.render_converged(rooms, Settings(indirect_method="vpl_gather", converge_seconds=0.2,
                                                          converge_sets=50, **SMALL))
        assert timed.stats["vpl_sets"] >= 1 and timed.stats["converge_ms"] >= 200
        assert timed.stats["vpl_sets"] < 50 or timed.stats["converge_ms"] < 1000 * 0.2 * 50
    finally:
        pipeline.release()


def generations(pipeline):
    """The flux of the last frame's VPLs summed over them: the first generation's (near
    and far), and every later one's together."""
    first = sum(VPLSet(buffer, count).read()["flux"].sum(axis=0)
                for m in pipeline.last_light_maps for buffer, count in m.emitter_sets())
    later = sum((VPLSet(generation.buffer, generation.count).read()["flux"].sum(axis=0)
                 for generation in pipeline.last_indirect.generations.made), np.zeros(3))
    return first, later


@pytest.mark.parametrize("method", ["vpl_gather", "light_grid"])
def test_more_bounces_add_less_and_less_light(rooms, method):
    pipeline = Pipeline()
    try:
        means, later = [], []
        for bounces in (1, 2, 3):
            # four VPL sets: with 256 VPLs a set's noise is about what the third bounce adds
            frame = pipeline.render_converged(rooms, Settings(indirect_method=method, bounces=bounces, converge_sets=4,
                                                              **SMALL), passes=("indirect",))
            assert ("bounce_ms" in frame.stats) == (bounces > 1)
            means.append(frame.passes["indirect"].mean())
            if bounces > 1:
                first, added = generations(pipeline)
                later.append(added)
        # the albedos are at most 0.8: a generation carries at most 0.8 of the one before (a 2 cm wall's
        # faces, which the occupancy cannot tell apart, would carry more: gpu/bounces.py conserve)
        assert np.all(later[0] > 0.05 * first) and np.all(later[0] <= 0.8 * first * (1 + 1e-4))
        assert np.all(later[1] > later[0]) and np.all(later[1] - later[0] <= 0.8 * later[0] * (1 + 1e-4))
        print(f"\n{method}: indirect means {means}")
        assert means[0] * 1.05 < means[1] < means[2]
    finally:
        pipeline.release()


def test_a_lone_plane_passes_no_light_on():
    floor = scene_to_render(lone_floor(SIZE).scene)
    pipeline = Pipeline(Settings(indirect_method="vpl_gather", bounces=3, **SMALL))
    try:
        pipeline.render(floor, passes=())
        first, added = generations(pipeline)
        assert np.all(first > 0) and np.all(added <= 1e-6 * first)
    finally:
        pipeline.release()
