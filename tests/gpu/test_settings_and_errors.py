"""Parameters are validated with a sentence naming the parameter and its range; bad
scenes and a missing GPU give our error, never a crash."""
import signal

import numpy as np
import pytest

from lpv_preview.gpu.context import GLContext, dispatch, install_hint, platform_backends
from lpv_preview.gpu.ctrl_c import ctrl_c_held
from lpv_preview.gpu.emitter_grid import EmitterGrid
from lpv_preview.gpu.errors import LPVError
from lpv_preview.gpu.scene import Camera, Light, Scene
from lpv_preview.gpu.settings import PARAMETERS, Settings


def test_defaults_are_valid_and_documented():
    settings = Settings()
    assert settings.rsm_resolution == 512 and settings.vpls_per_light == 2048
    assert settings.indirect_method == "light_grid" and settings.lpv_resolution == 16
    for field in PARAMETERS.values():
        assert field.metadata["description"]


@pytest.mark.parametrize("name, value, words", [
    ("rsm_resolution", 8, ["rsm_resolution", "16", "2048"]),
    ("vpls_per_light", 0, ["vpls_per_light", "1", "65536"]),
    ("lpv_resolution", 1000, ["lpv_resolution", "4", "128"]),
    ("indirect_intensity", float("nan"), ["indirect_intensity"]),
    ("method", "magic", ["method", "cm"]),
    ("occlusion", "yes", ["occlusion"]),
    ("width", 2.5, ["width"]),
])
def test_out_of_range_parameter_names_it_and_its_range(name, value, words):
    with pytest.raises(LPVError) as error:
        Settings(**{name: value})
    message = str(error.value)
    assert all(word in message for word in words), message
    assert message.endswith(".") and "\n" not in message


def test_unknown_parameter():
    with pytest.raises(LPVError, match="Unknown setting 'grid'"):
        Settings().with_changes(grid=3)


def one_triangle_scene(triangles, lights=True):
    triangles = np.asarray(triangles, dtype=np.float32).reshape(-1, 3, 3)
    light = Light("POINT", (0, 0, 2), (0, 0, -1), (0, 1, 0), (1, 1, 1), 10.0)
    return Scene(triangles, np.zeros_like(triangles), np.full((len(triangles), 3), 0.5),
                 [light] if lights else [], Camera.look_at((0, -3, 1), (0, 0, 0)))


def test_nan_and_zero_area_triangles_are_dropped_and_counted():
    good = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    nan = [[0, 0, 0], [np.nan, 0, 0], [0, 1, 0]]
    inf = [[0, 0, np.inf], [1, 0, 0], [0, 1, 0]]
    zero = [[0, 0, 0], [1, 0, 0], [2, 0, 0]]
    point = [[1, 1, 1]] * 3
    scene = one_triangle_scene([good, nan, inf, zero, point]).sanitize()
    assert scene.triangle_count == 1
    assert scene.dropped == {"non_finite": 2, "zero_area": 2}
    np.testing.assert_allclose(scene.normals[0], [[0, 0, 1]] * 3)  # missing normals -> face normal


def test_empty_scene_and_no_lights():
    with pytest.raises(LPVError, match="no renderable triangles"):
        one_triangle_scene(np.zeros((0, 3, 3))).sanitize()
    with pytest.raises(LPVError, match="no renderable triangles"):
        one_triangle_scene([[[0, 0, 0], [np.nan, 0, 0], [0, 1, 0]]]).sanitize()
    with pytest.raises(LPVError, match="no lights"):
        one_triangle_scene([[[0, 0, 0], [1, 0, 0], [0, 1, 0]]], lights=False).sanitize()


def test_bad_light_values():
    with pytest.raises(LPVError, match="power"):
        Light("POINT", (0, 0, 0), (0, 0, -1), (0, 1, 0), (1, 1, 1), -1.0)
    with pytest.raises(LPVError, match="non-finite position"):
        Light("POINT", (0, np.nan, 0), (0, 0, -1), (0, 1, 0), (1, 1, 1), 1.0)
    with pytest.raises(LPVError, match="supported types"):
        Light("MESH", (0, 0, 0), (0, 0, -1), (0, 1, 0), (1, 1, 1), 1.0)


def test_no_gpu_gives_one_clear_error(monkeypatch):
    monkeypatch.setenv("LPV_PREVIEW_NO_GPU", "1")
    with pytest.raises(LPVError) as error:
        GLContext()
    assert "OpenGL 4.5" in str(error.value) and "install" in str(error.value)


def test_each_platform_makes_its_context_through_its_own_interface():
    """WGL on Windows (glcontext's Windows wheel has no EGL), EGL on Linux, GLX after it
    where a display is there; LPV_PREVIEW_GL_BACKEND picks one; macOS is refused."""
    assert platform_backends("win32", {}) == ("wgl",)
    assert platform_backends("linux", {}) == ("egl",)
    assert platform_backends("linux", {"DISPLAY": ":0", "WAYLAND_DISPLAY": "wayland-0"}) == ("egl", "glx")
    assert platform_backends("linux", {"LPV_PREVIEW_GL_BACKEND": "GLX"}) == ("glx",)
    with pytest.raises(LPVError, match="names no OpenGL interface; set it to one of egl, glx, wgl"):
        platform_backends("linux", {"LPV_PREVIEW_GL_BACKEND": "vulkan"})
    with pytest.raises(LPVError, match="macOS lacks"):
        platform_backends("darwin", {})
    assert "GPU vendor's current driver" in install_hint("win32") and "apt-get" not in install_hint("win32")
    assert "apt-get install libegl1" in install_hint("linux")


def test_a_context_belongs_to_the_thread_that_made_it():
    import threading
    here = GLContext.shared()
    assert GLContext.shared() is here
    made = []

    def make():
        made.append(GLContext.shared())
        made[0].release()  # on its own thread, where it is current

    thread = threading.Thread(target=make)
    thread.start()
    thread.join()
    assert made[0] is not here and made[0].renderer == here.renderer


def test_ctrl_c_during_a_shader_compile_stops_the_command_after_it(glc):
    # moderngl calls Python helpers while it lists a new program's uniforms and does not
    # check what they return: Ctrl-C must not raise inside them, only once it has returned.
    # Ctrl-C's meaning as the command line has it (a shell may run the tests with it ignored).
    key = ("zero_image", (("FORMAT", "r32f"), ("HELD_CTRL_C", 1)))
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            with ctrl_c_held():
                signal.raise_signal(signal.SIGINT)
                glc.compute("zero_image", FORMAT="r32f", HELD_CTRL_C=1)
                assert key in glc._programs
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, before)



@pytest.mark.parametrize("bad, why", [((0, 1), np.nan), ((1, 2), np.inf), ((2, 4), -1.0), ((3, 6), -np.inf)])
def test_each_bad_point_emitter_is_dropped_and_counted(bad, why):
    """The GPU drops a row that is not finite, has a negative flux or area or no flux, and
    counts it (shaders/emitter_select.comp); none of its values reach the emitter rows."""
    emitters = np.tile(np.array([[0.0, 0.0, 1.0, 1.0, 0.5, 0.2, 1e-4]], dtype=np.float32), (6, 1))
    emitters[5, 3:6] = 0.0  # no flux
    box = (np.array([-1.0, -1.0, 0.0]), np.array([1.0, 1.0, 2.0]))

    def selected(rows):
        grid = EmitterGrid(GLContext.shared(), 8)
        try:
            grid.upload(rows, None, id(rows))
            selection = grid.select(box, 0.1, 0.0)
            return selection, np.frombuffer(grid.emitters.read(), np.float32).reshape(-1, 12)[:len(rows)]
        finally:
            grid.release()
    sane, _ = selected(emitters[:5])
    assert (sane.kept, sane.skipped, sane.dropped) == (5, 0, 0)
    emitters[bad] = why
    dirty, rows = selected(emitters)
    assert (dirty.kept, dirty.skipped, dirty.dropped) == (4, 0, 2)
    assert np.isfinite(rows).all() and not rows[[bad[0], 5]].any()
    np.testing.assert_allclose(dirty.box[0], [0.0, 0.0, 1.0])


def test_a_dispatch_past_the_drivers_workgroups_fails_loudly(glc):
    """GL runs nothing past GL_MAX_COMPUTE_WORK_GROUP_COUNT and says so only in glGetError:
    a light grid of 48³ cells drew no indirect light on llvmpipe that way."""
    limit = glc.gl.info["GL_MAX_COMPUTE_WORK_GROUP_COUNT"][0]
    with pytest.raises(ValueError, match="workgroups exceed the driver's"):
        dispatch(glc.compute("zero_buffer"), (limit + 1) * 64, local=(64,))
