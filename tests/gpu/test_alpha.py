"""Alpha and transmission in the G-buffer and the lights' maps (docs/method.md, "Alpha
and transmission"), on synthetic scenes: a floor under a sun and a card above it."""
import math

import numpy as np
import pytest

from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene import SEEN_BY_ALL, SEEN_BY_LIGHTS, Camera, Light, Scene
from lpv_preview.gpu.settings import Settings

SIZE = 32
LIT = 0.8 * 3.0 / math.pi  # the floor's albedo times the sun's irradiance / pi
FLOOR = np.array([[[-2, -2, 0], [2, -2, 0], [2, 2, 0]], [[-2, -2, 0], [2, 2, 0], [-2, 2, 0]]], np.float32)
CENTRE = slice(SIZE // 2 - 3, SIZE // 2 + 3)


def card_scene(alpha=1.0, transmission=None, camera_sees_card=True):
    """The floor and a 0.8 m card 1 m above its centre, the sun straight above."""
    triangles = np.concatenate([FLOOR, FLOOR * 0.2 + np.array([0, 0, 1], np.float32)])
    normals = np.zeros_like(triangles)
    normals[..., 2] = 1.0
    card_seen = SEEN_BY_ALL if camera_sees_card else SEEN_BY_LIGHTS
    sun = Light("SUN", (0, 0, 5), (0, 0, -1), (0, 1, 0), (1, 1, 1), 3.0)
    camera = Camera.look_at((0, 0, 5), (0, 0, 0), (0, 1, 0), fov_y=2 * math.atan(0.3))
    return Scene(triangles, normals, np.full((4, 3), 0.8, np.float32), [sun], camera,
                 visibility=np.array([SEEN_BY_ALL] * 2 + [card_seen] * 2, np.uint8),
                 alpha=np.array([1, 1, alpha, alpha], np.float32),
                 transmission=None if transmission is None else np.array([[1, 1, 1, 0]] * 2 + [transmission] * 2,
                                                                         np.float32))


@pytest.fixture(scope="module")
def pipeline():
    p = Pipeline(Settings(width=SIZE, height=SIZE, rsm_resolution=128, converge_sets=8))
    yield p
    p.release()


def test_a_half_transparent_card_lets_half_the_sun_through_once_converged(pipeline):
    frame = pipeline.render_converged(card_scene(alpha=0.5, camera_sees_card=False).sanitize())
    shadow = frame.passes["direct"][CENTRE, CENTRE].mean()
    assert shadow == pytest.approx(0.5 * LIT, rel=0.08)


def test_a_half_transparent_card_shows_half_of_what_is_behind(pipeline):
    frame = pipeline.render_converged(card_scene(alpha=0.5).sanitize())
    seen = frame.passes["direct"][CENTRE, CENTRE].mean()
    # half the card (lit), half the floor in its half shadow
    assert seen == pytest.approx(0.5 * LIT + 0.5 * 0.5 * LIT, rel=0.08)


def test_an_alpha_zero_card_is_dropped():
    scene = card_scene(alpha=0.0).sanitize()
    assert scene.triangle_count == 2 and scene.dropped["clear"] == 2 and scene.alpha is None


def test_glass_tints_what_is_seen_through_it_and_the_light_its_maps_pass_on(pipeline):
    tint = (1.0, 0.25, 0.5)
    hidden = pipeline.render(card_scene(transmission=(*tint, 1.0), camera_sees_card=False).sanitize(),
                             passes=("direct",))
    # the sun's light crosses the glass once on its way to the floor
    np.testing.assert_allclose(hidden.passes["direct"][CENTRE, CENTRE].mean(axis=(0, 1)), np.multiply(tint, LIT),
                               rtol=0.02)
    scene = card_scene(transmission=(*tint, 1.0)).sanitize()
    frame = pipeline.render(scene, passes=("direct",))
    # and seen through the glass, once more on its way to the camera
    np.testing.assert_allclose(frame.passes["direct"][CENTRE, CENTRE].mean(axis=(0, 1)),
                               np.multiply(np.square(tint), LIT), rtol=0.02)
    flux = pipeline.last_light_maps[0].rsm.read(pipeline.last_light_maps[0].rsm.flux)
    middle = flux.shape[0] // 2
    under_glass, beside = flux[middle, middle, :3], flux[middle, middle + flux.shape[1] // 4, :3]
    np.testing.assert_allclose(under_glass / beside, tint, rtol=0.02)
