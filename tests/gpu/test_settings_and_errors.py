"""Parameters are validated with a sentence naming the parameter and its range; bad
scenes and a missing GPU give our error, never a crash."""
import numpy as np
import pytest

from lpv_preview.gpu.context import GLContext
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
