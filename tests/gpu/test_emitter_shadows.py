"""The point emitters' shadows (issue 17): particles shut in a closed box light nothing
outside it, while an open room keeps its light. Real GL through llvmpipe."""
from lpv_preview.bench.synthetic import particle_room, particles_in_a_box
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import Settings

SMALL = dict(width=64, height=48, emitter_grid_resolution=16, lpv_resolution=8, emitter_bounce_samples=64)


def direct_light(scene, shadows):
    settings = Settings(**SMALL, emitter_shadows=shadows)
    pipeline = Pipeline(settings)
    try:
        frame = pipeline.render(scene, passes=("direct",))
    finally:
        pipeline.release()
    assert ("emitter_shadow_ms" in frame.stats) == shadows
    return frame.passes["direct"]


def test_particles_in_a_closed_box_light_nothing_outside_it():
    scene = particles_in_a_box()
    shut, leaking = direct_light(scene, True), direct_light(scene, False)
    assert leaking.mean() > 0.05
    assert shut.mean() < 0.02 * leaking.mean()


def test_an_open_room_keeps_its_light():
    scene = particle_room(1000)
    shaded, open_ = direct_light(scene, True), direct_light(scene, False)
    assert 0.95 < shaded.mean() / open_.mean() <= 1.0
