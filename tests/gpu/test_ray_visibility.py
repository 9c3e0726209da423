"""Blender's ray visibility "Camera" and "Shadow" on a triangle (gpu/scene.py
SEEN_BY_CAMERA, SEEN_BY_LIGHTS): the camera draws only what it sees, the lights' maps
hold only what casts shadows. A floor under a point light with a quad floating between
them, seen from above; the quad's shadow falls beside it."""
import numpy as np
import pytest

from lpv_preview.gpu.pipeline import render_once
from lpv_preview.gpu.scene import SEEN_BY_ALL, SEEN_BY_CAMERA, SEEN_BY_LIGHTS, Camera, Light, Scene
from lpv_preview.gpu.settings import Settings

SETTINGS = Settings(width=48, height=48, rsm_resolution=128, vpls_per_light=256, lpv_resolution=8, method="cm")


def quad(x0, x1, y0, y1, z):
    a, b, c, d = (x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)
    return [[a, b, c], [a, c, d]]


def floor_and_occluder(occluder_seen):
    """A 4 m floor, a 1 m quad at 1 m over (0.8, 0) lit from (1.6, 0, 2): its shadow falls
    around x = 0, its own pixels around x = 0.8 from a camera looking straight down."""
    triangles = np.array(quad(-2, 2, -2, 2, 0.0) + quad(0.3, 1.3, -0.5, 0.5, 1.0), dtype=np.float32)
    visibility = np.array([SEEN_BY_ALL] * 2 + [occluder_seen] * 2, dtype=np.uint8)
    light = Light("POINT", (1.6, 0.0, 2.0), (0, 0, -1), (0, 1, 0), (1, 1, 1), 200.0)
    camera = Camera.look_at((0, 0, 6), (0, 0, 0), up=(0, 1, 0), fov_y=np.radians(40), near=0.1, far=20)
    return Scene(triangles, np.zeros_like(triangles), np.full((4, 3), 0.5, np.float32), [light], camera,
                 visibility=visibility).sanitize()


def direct_at(image, x, y):
    """The direct image's mean around world (x, y) on the floor, for the camera above."""
    size = image.shape[0]
    half = 6 * np.tan(np.radians(20))
    column, row = int((x / half + 1) / 2 * size), int((1 - y / half) / 2 * size)
    return float(image[row - 1:row + 2, column - 1:column + 2].mean())


@pytest.fixture(scope="module")
def images(glc):
    return {seen: render_once(floor_and_occluder(seen), SETTINGS, glc).passes
            for seen in (SEEN_BY_ALL, SEEN_BY_CAMERA, SEEN_BY_LIGHTS)}


def test_the_ranges_put_camera_only_first_and_lights_only_last():
    scene = floor_and_occluder(SEEN_BY_LIGHTS)
    assert scene.camera_triangles == (0, 2) and scene.light_triangles == (0, 4)
    scene = floor_and_occluder(SEEN_BY_CAMERA)
    assert scene.camera_triangles == (0, 4) and scene.light_triangles == (2, 2)
    assert np.all(scene.triangles[:2, :, 2] == 1.0)  # the camera-only quad first
    assert floor_and_occluder(SEEN_BY_ALL).visibility is None


def test_a_shadow_only_quad_casts_its_shadow_but_is_not_drawn(images):
    full, shadow_only = images[SEEN_BY_ALL]["direct"], images[SEEN_BY_LIGHTS]["direct"]
    lit = direct_at(full, -1.2, 1.2)
    assert direct_at(full, 0.0, 0.0) < 0.05 * lit  # the shadow, with the quad drawn
    assert direct_at(shadow_only, 0.0, 0.0) < 0.05 * lit  # the shadow, without it
    # Where the lit quad was drawn the camera now sees the floor in its shadow.
    assert direct_at(full, 0.8, 0.0) > 2 * lit and direct_at(shadow_only, 0.8, 0.0) < 0.05 * lit


def test_a_camera_only_quad_is_drawn_but_casts_no_shadow(images):
    full, camera_only = images[SEEN_BY_ALL]["direct"], images[SEEN_BY_CAMERA]["direct"]
    lit = direct_at(full, -1.2, 1.2)
    assert direct_at(camera_only, 0.0, 0.0) > 0.5 * lit  # no shadow
    np.testing.assert_allclose(camera_only[20:28, 30:38], full[20:28, 30:38], rtol=1e-4, atol=1e-6)  # the quad
