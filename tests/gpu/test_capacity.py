"""A frame is checked against the driver's limits and the memory free before anything of
it is allocated, and refused with one sentence that says what it needs."""
import math

import numpy as np
import pytest

from lpv_preview.bench.synthetic import particle_room
from lpv_preview.gpu.capacity import available_host_bytes, check_emitter_grid, check_limits, frame_bytes
from lpv_preview.gpu.emitter_grid import EmitterGrid
from lpv_preview.gpu.errors import LPVError
from lpv_preview.gpu.passes import PASS_NAMES, render_passes
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene import Light
from lpv_preview.gpu.settings import Settings
from lpv_preview.gpu.shade import DISPLAY_CHANNELS, FrameTargets

from ..synthetic_scenes import room_scene


def lit_room():
    """The room with a point light, a wide spot (five cube faces, one hemisphere) and a sun."""
    scene = room_scene(4)
    scene.lights += [Light("SPOT", np.array((-1.0, 1.0, 2.5)), (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0,
                           spot_size=math.radians(120)),
                     Light("SUN", np.zeros(3), (0.3, 0.2, -1.0), (0, 1, 0), (1, 1, 1), 2.0)]
    return scene


@pytest.mark.parametrize("method, indirect_method", [("cm", "lpv"), ("dpm", "lpv"), ("wdpm", "lpv"), ("auto", "lpv"),
                                                     ("wdpm", "light_grid"), ("wdpm", "vpl_gather")])
def test_the_estimate_covers_what_a_pipeline_holds_after_a_frame(method, indirect_method, glc):
    """With one grid level: the estimate counts every level the setting allows."""
    scene = lit_room()
    settings = Settings(method=method, width=96, height=64, rsm_resolution=64, vpls_per_light=512, lpv_resolution=16,
                        indirect_method=indirect_method, grid_levels=1)
    passes = tuple(p.name for p in render_passes(debug=True))
    pipeline = Pipeline(settings, glc)
    try:
        pipeline.render(scene, passes=passes, display_into=np.empty((64, 96, DISPLAY_CHANNELS), dtype=np.float32))
        held = pipeline.gpu_bytes()
    finally:
        pipeline.release()
    gpu, host = frame_bytes(settings, scene, passes, display=True)
    # Above what the pipeline holds by no more than the spare maps and depth the context keeps for reuse.
    assert held <= gpu <= 1.5 * held, (held, gpu)
    assert host >= 96 * 64 * 3 * 4 * len(passes)


def test_a_driver_with_smaller_limits_refuses_what_it_cannot_render(glc):
    scene = lit_room()
    limits = dict(glc.gl.info, GL_MAX_TEXTURE_SIZE=4096, GL_MAX_3D_TEXTURE_SIZE=32)
    check_limits(limits, "a small GPU", Settings(width=4096, height=4096, rsm_resolution=1024, lpv_resolution=16,
                                                 indirect_method="lpv"), scene)
    with pytest.raises(LPVError) as error:
        check_limits(limits, "a small GPU", Settings(width=8192, height=4320), scene)
    assert str(error.value) == ("A 8192 x 4320 image is larger than a small GPU can render (4096 x 4096 at most); "
                                "lower the resolution.")
    with pytest.raises(LPVError) as error:
        check_limits(limits, "a small GPU", Settings(rsm_resolution=2048), scene)
    assert str(error.value) == ("An RSM resolution of 2048 makes 6144 x 4096 light maps, larger than a small GPU can "
                                "render (4096 x 4096 at most); lower the RSM resolution.")
    with pytest.raises(LPVError) as error:
        check_limits(limits, "a small GPU", Settings(lpv_resolution=32, indirect_method="lpv"), scene)
    assert str(error.value) == ("A grid resolution of 32 needs volumes of 33 cells a side with indirect method lpv, "
                                "more than a small GPU allows (32); lower the LPV resolution.")
    with pytest.raises(LPVError) as error:
        check_limits(limits, "a small GPU", Settings(lpv_resolution=16, indirect_method="light_grid"), scene)
    assert str(error.value) == ("A grid resolution of 16 needs volumes of 288 cells a side with indirect method "
                                "light_grid, more than a small GPU allows (32); lower the LPV resolution.")


def test_a_frame_larger_than_the_memory_free_is_refused_before_it_is_allocated(glc):
    scene = room_scene(2)
    settings = Settings(width=16384, height=16384, rsm_resolution=64, vpls_per_light=256)
    if available_host_bytes() > sum(frame_bytes(settings, scene, PASS_NAMES)):
        pytest.skip("this machine has the memory of a 16384 x 16384 frame")
    pipeline = Pipeline(settings, glc)
    try:
        with pytest.raises(LPVError) as error:
            pipeline.render(scene)
        assert pipeline.gpu_bytes() == 0  # nothing was allocated
    finally:
        pipeline.release()
    message = str(error.value)
    assert message.startswith("A 16384 x 16384 frame needs about ") and "GiB" in message, message
    assert "; lower the resolution" in message and len(message.splitlines()) == 1, message


def test_images_the_driver_cannot_make_are_refused_in_one_sentence(glc):
    if not glc.is_software:
        pytest.skip("llvmpipe refuses an image of 1.5 GiB; a GPU's limit lies elsewhere")
    with pytest.raises(LPVError) as error:
        FrameTargets(glc.gl, 16384, 16384)
    assert str(error.value) == (f"{glc.renderer} cannot make 16384 x 16384 images (GL_OUT_OF_MEMORY); lower the "
                                f"resolution.")


def test_an_emitter_grid_the_driver_cannot_make_is_refused_in_one_sentence(glc):
    """llvmpipe makes no texture over 1 GiB and says so only through glGetError: a grid of
    256 cells, read super-sampled from 512³ textures, drew no emitter's light."""
    if not glc.is_software:
        pytest.skip("llvmpipe makes no texture over 1 GiB; a GPU's limit lies elsewhere")
    scene = particle_room(64, seed=1)
    settings = Settings(width=32, height=24, rsm_resolution=64, vpls_per_light=64, emitter_grid_resolution=256)
    pipeline = Pipeline(settings, glc)
    try:
        with pytest.raises(LPVError) as error:
            pipeline.render(scene)
        assert pipeline.gpu_bytes() == 0  # refused before anything was allocated
    finally:
        pipeline.release()
    assert str(error.value) == (f"An emitter grid resolution of 256 needs textures of 512³ texels, 2 GiB each, more "
                                f"than {glc.renderer} makes (1 GiB); lower the emitter grid resolution.")
    check_emitter_grid(glc.gl.extensions, glc.renderer, settings.with_changes(emitter_grid_resolution=128), scene,
                       software=True)  # 256³ textures of 256 MiB
    grid = EmitterGrid(glc, 256)
    try:
        with pytest.raises(LPVError) as error:
            grid.supersampled_textures()
    finally:
        grid.release()
    assert str(error.value) == (f"{glc.renderer} cannot make the emitter grid's 512³ textures (GL_OUT_OF_MEMORY); "
                                f"lower the emitter grid resolution.")
