"""The glossy reflection of the direct light (docs/method.md, "Specular light"): a floor
under a point light seen at a slant, its direct image against a numpy GGX of the same
pixels (the light's irradiance taken from the floor's diffuse image, so the test needs
no light units)."""
import math

import numpy as np
import pytest

from lpv_preview.gpu.mesh_buffer import VERTEX_LAYOUT
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene import Camera, Light, Scene
from lpv_preview.gpu.settings import Settings

SIZE = 48
ALBEDO = 0.5
FLOOR = np.array([[[-4, -4, 0], [4, -4, 0], [4, 4, 0]], [[-4, -4, 0], [4, 4, 0], [-4, 4, 0]]], np.float32)
EYE = np.array([0.0, -3.0, 2.0])
LAMP = np.array([0.0, 1.0, 1.5])


def floor_scene(specular=None):
    normals = np.zeros_like(FLOOR)
    normals[..., 2] = 1.0
    lamp = Light("POINT", LAMP, (0, 0, -1), (0, 1, 0), (1, 1, 1), 100.0)
    camera = Camera.look_at(EYE, (0, 0.5, 0), (0, 0, 1), fov_y=math.radians(60))
    return Scene(FLOOR.copy(), normals, np.full((2, 3), ALBEDO, np.float32), [lamp], camera,
                 specular=None if specular is None else np.tile(np.asarray(specular, np.float32), (2, 1)))


def floor_points(camera):
    """Each pixel's point on the floor (z = 0), (SIZE, SIZE, 3), top row first."""
    inverse = np.linalg.inv(camera.projection @ camera.view)
    centres = (np.arange(SIZE) + 0.5) / SIZE * 2 - 1
    x, y = np.meshgrid(centres, centres[::-1])
    ends = []
    for depth in (-1.0, 1.0):
        clip = np.stack([x, y, np.full_like(x, depth), np.ones_like(x)], axis=-1) @ inverse.T
        ends.append(clip[..., :3] / clip[..., 3:])
    near, far = ends
    t = near[..., 2] / (near[..., 2] - far[..., 2])
    return near + t[..., None] * (far - near)


def dielectric_fresnel(c, eta):
    g = np.sqrt(eta * eta - 1 + c * c)
    a, b = (g - c) / (g + c), (c * (g + c) - 1) / (c * (g - c) + 1)
    return 0.5 * a * a * (1 + b * b)


def ggx(points, f0, roughness, metallic):
    """The GGX BRDF of shaders/specular.glsl at each point for the lamp and the eye."""
    n = np.array([0.0, 0.0, 1.0])
    l = LAMP - points
    l /= np.linalg.norm(l, axis=-1, keepdims=True)
    v = EYE - points
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    h = (l + v) / np.linalg.norm(l + v, axis=-1, keepdims=True)
    nl, nv, nh, vh = l @ n, v @ n, h @ n, np.sum(v * h, axis=-1)
    a2 = max(roughness ** 2, 0.002) ** 2
    d = a2 / (math.pi * (nh * nh * (a2 - 1) + 1) ** 2)
    vis = 0.5 / (nl * np.sqrt(nv * nv * (1 - a2) + a2) + nv * np.sqrt(nl * nl * (1 - a2) + a2))
    root = math.sqrt(f0)
    dielectric = (dielectric_fresnel(vh, (1 + root) / (1 - root)) - f0) / (1 - f0)
    fresnel = f0 + (1 - f0) * (metallic * (1 - vh) ** 5 + (1 - metallic) * dielectric)
    return d * vis * fresnel


@pytest.fixture(scope="module")
def pipeline():
    p = Pipeline(Settings(width=SIZE, height=SIZE, rsm_resolution=128))
    yield p
    p.release()


def test_the_vertex_carries_f0_and_roughness():
    assert VERTEX_LAYOUT[0].split()[-2:] == ["4f", "1f"] and VERTEX_LAYOUT[-2:] == ("in_specular", "in_metallic")


@pytest.mark.parametrize("f0, roughness, metallic", [(0.04, 0.3, 0.0), (0.9, 0.5, 1.0), (0.3, 0.2, 0.5)])
def test_a_glossy_floor_matches_ggx(pipeline, f0, roughness, metallic):
    diffuse = pipeline.render(floor_scene()).passes["direct"]
    glossy = pipeline.render(floor_scene((f0, f0, f0, roughness, metallic))).passes["direct"]
    irradiance = diffuse[..., 0] * math.pi / ALBEDO
    expected = irradiance * (ALBEDO / math.pi + ggx(floor_points(floor_scene().camera), f0, roughness, metallic))
    lit = irradiance > 0.05 * irradiance.max()
    assert np.abs(glossy[..., 0] - expected)[lit].mean() / expected[lit].mean() < 0.03
    peak = np.unravel_index(np.argmax(np.where(lit, expected, 0)), expected.shape)
    assert np.abs(np.subtract(np.unravel_index(np.argmax(glossy[..., 0]), expected.shape), peak)).max() <= 1
    assert glossy[..., 0].max() > 1.5 * diffuse[..., 0].max()  # a highlight, not a tint


def test_no_f0_no_change(pipeline):
    diffuse = pipeline.render(floor_scene()).passes["direct"]
    black = pipeline.render(floor_scene((0.0, 0.0, 0.0, 0.2, 1.0))).passes["direct"]
    np.testing.assert_allclose(black, diffuse, atol=1e-6)
