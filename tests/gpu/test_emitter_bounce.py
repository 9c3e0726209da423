"""The emitters' bounce (gpu/emitter_bounce.py): its flux bound is known on the host, so a
frame does not wait to read the bounce's flux back, and the GPU holds the bounce to it
(gpu/bounces.py conserve). Real GL through llvmpipe."""
from dataclasses import replace

import numpy as np
import pytest

from lpv_preview.bench.synthetic import particle_room, room_scene
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings
from lpv_preview.gpu.world import World


def open_room_under_a_white_world():
    """The synthetic room without its ceiling, lit by a white world and its lamp."""
    scene = room_scene(4)
    keep = scene.triangles[:, :, 2].min(axis=1) < 2.9  # the ceiling lies at z = 3
    return replace(scene, triangles=scene.triangles[keep], normals=scene.normals[keep], albedo=scene.albedo[keep],
                   world=World.uniform((1.0, 1.0, 1.0))).sanitize()


@pytest.mark.parametrize("name, make", [("white world", open_room_under_a_white_world),
                                        ("emissive particles", lambda: particle_room(2000, seed=3))])
def test_the_bounce_is_held_within_a_bound_known_before_it_is_drawn(name, make, glc):
    pipeline = Pipeline(Settings(width=48, height=36, rsm_resolution=64, vpls_per_light=256, bounces=1), glc)
    try:
        frame = pipeline.render(make())
        bounce = pipeline.last_indirect.emitter_vpls
        carried = np.frombuffer(bounce.buffer.read(), dtype=np.float32).reshape(-1, 3, 4)[:, 2, :3].sum(axis=0).max()
    finally:
        pipeline.release()
    print(f"\n{name}: bound / carried {bounce.flux_bound / carried:.2f}")
    assert frame.passes["indirect"].mean() > 0
    assert carried <= bounce.flux_bound * 1.0001  # the clusters' fixed-point sums cannot overflow
    assert bounce.flux_bound < 50 * carried  # nor lose their precision to a bound far too wide
