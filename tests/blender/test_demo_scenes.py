"""The demo scenes build, extract with the triangle counts they promise, and give sane
arrays, lights and cameras. Each scene is built and extracted once per module."""
import bpy
import numpy as np
import pytest

from lpv_preview import demo
from lpv_preview.addon.extract import extract_scene
from lpv_preview.demo.cornell import GREEN, RED, WHITE
from lpv_preview.gpu.errors import LPVError
from lpv_preview.gpu.scene_file import load_scene

CORNELL_TRIANGLES = 10 * 8 ** 2 + 16 * 4 ** 2 + 4  # five 8x8 walls; two boxes: 4x4 sides and a top


def build_and_extract(name, **params):
    demo.build(name, **params)
    return extract_scene(bpy.context.evaluated_depsgraph_get())


@pytest.fixture(scope="module")
def cornell():
    return build_and_extract("cornell")


@pytest.fixture(scope="module")
def atrium():
    return build_and_extract("atrium")


@pytest.fixture(scope="module")
def city():
    return build_and_extract("city")


@pytest.fixture(scope="module")
def big_city():
    return build_and_extract("city", triangles=500_000)


SCENES = ["cornell", "atrium", "city", "big_city"]


@pytest.fixture(params=SCENES)
def any_scene(request):
    return request.getfixturevalue(request.param)


def test_cornell_triangle_count(cornell):
    assert cornell.triangle_count == CORNELL_TRIANGLES


@pytest.mark.parametrize("name, target", [("atrium", 250_000), ("city", 130_000), ("big_city", 500_000)])
def test_triangle_budget_is_met(request, name, target):
    scene = request.getfixturevalue(name)
    assert abs(scene.triangle_count - target) <= 0.1 * target


def test_arrays_are_sane(any_scene):
    assert any_scene.dropped == {"non_finite": 0, "zero_area": 0}
    for array in (any_scene.triangles, any_scene.normals, any_scene.albedo):
        assert np.all(np.isfinite(array))
    np.testing.assert_allclose(np.linalg.norm(any_scene.normals, axis=-1), 1.0, atol=1e-4)
    assert any_scene.albedo.min() >= 0.0 and any_scene.albedo.max() <= 1.0
    assert any_scene.lights


def test_camera_sees_the_middle_of_the_scene(any_scene):
    camera = any_scene.camera
    assert np.all(np.isfinite(camera.view)) and np.all(np.isfinite(camera.projection))
    low, high = any_scene.bounds()
    middle = np.append((low + high) / 2, 1.0)
    clip = camera.projection @ camera.view @ middle
    assert clip[3] > 0
    assert np.all(np.abs(clip[:2] / clip[3]) < 1.0)


def test_cornell_light_hangs_under_the_ceiling(cornell):
    (light,) = cornell.lights
    assert light.kind == "POINT"
    assert abs(light.position[0]) < 0.1 and abs(light.position[1]) < 0.1 and 1.6 < light.position[2] < 2.0
    assert 0 < light.radius <= 0.1 and 40 <= light.power <= 120


def test_cornell_walls_face_into_the_room(cornell):
    """Wall triangles (centroid on a wall plane) have normals pointing inside; the side
    walls carry the classic colours."""
    centroid = cornell.triangles.mean(axis=1)
    normal = cornell.normals.mean(axis=1)
    walls = [(0, 1.0, 0.0, GREEN), (0, -1.0, 0.0, RED), (1, 1.0, 0.0, WHITE), (2, 0.0, 1.0, WHITE),
             (2, 2.0, -1.0, WHITE)]  # axis, plane, then the expected sign for the floor/ceiling
    for axis, plane, vertical_sign, color in walls:
        on_wall = np.abs(centroid[:, axis] - plane) < 1e-4
        assert on_wall.sum() == 2 * 8 ** 2
        inward = -np.sign(plane) if axis < 2 else vertical_sign
        assert np.all(normal[on_wall, axis] * inward > 0.99)
        np.testing.assert_allclose(cornell.albedo[on_wall], np.tile(color, (on_wall.sum(), 1)), atol=1e-6)


def test_cornell_camera_sees_the_back_wall(cornell):
    camera = cornell.camera
    for corner in [(-1, 1, 0), (1, 1, 0), (-1, 1, 2), (1, 1, 2)]:
        clip = camera.projection @ camera.view @ np.append(corner, 1.0)
        assert clip[3] > 0 and np.all(np.abs(clip[:2] / clip[3]) < 1.0)


def test_atrium_has_coloured_banners(atrium):
    colours = {tuple(np.round(c.astype(np.float64), 3)) for c in np.unique(atrium.albedo, axis=0)}
    assert {(0.6, 0.05, 0.04), (0.08, 0.4, 0.08), (0.05, 0.1, 0.5), (0.7, 0.55, 0.08)} <= colours


def test_city_is_deterministic(city):
    again = build_and_extract("city")
    assert again.geometry_key() == city.geometry_key()
    other_seed = build_and_extract("city", seed=8)
    assert other_seed.geometry_key() != city.geometry_key()


def test_export_npz_round_trip(tmp_path):
    path = tmp_path / "cornell.npz"
    exported = demo.export_npz("cornell", path)
    loaded = load_scene(path)
    assert loaded.triangle_count == CORNELL_TRIANGLES
    assert loaded.geometry_key() == exported.geometry_key()
    assert loaded.camera.key() == exported.camera.key()
    assert [light.key() for light in loaded.lights] == [light.key() for light in exported.lights]
    with pytest.raises(LPVError, match="Cannot write scene file .*; choose a writable path."):
        demo.export_npz("cornell", tmp_path / "missing" / "cornell.npz")


def test_unknown_scene_is_a_clear_error():
    with pytest.raises(LPVError, match="Unknown demo scene 'nope'"):
        demo.build("nope")


@pytest.mark.parametrize("name, lights", [("window_room", {"SUN": 1}),
                                          ("sunlit_courtyard", {"SUN": 1}),  # its Sun lamp, along its Sky Texture's sun
                                          ("furnished_room", {"POINT": 1, "AREA": 1}),
                                          ("small_lights_room", {"POINT": 60})])
def test_the_full_gi_rooms_are_lit_as_described(name, lights):
    scene = demo.extracted(name)
    kinds = [light.kind for light in scene.lights]
    assert {kind: kinds.count(kind) for kind in set(kinds)} == lights
    assert scene.diffuse_bounces == 4  # Blender's default Light Paths, which the benchmark compares at
    first, count = scene.light_triangles
    corners = scene.triangles[first:first + count].reshape(-1, 3)
    assert np.all(np.isfinite(corners)) and count > 0
