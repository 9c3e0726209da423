"""The glossy reflection of the direct light (docs/method.md, "Specular light"): a floor
under a point light seen at a slant, its direct image against a numpy GGX of the same
pixels over the diffuse the layer keeps toward the eye (the light's irradiance taken from
the floor's diffuse image, so the test needs no light units)."""
import math

import numpy as np
import pytest

from lpv_preview.gpu.mesh_buffer import VERTEX_LAYOUT
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.scene import Camera, Light, Scene
from lpv_preview.gpu.settings import Settings
from lpv_preview.gpu.specular_albedo import bounce_colours, specular_albedo
from lpv_preview.gpu.vpl import SHARPEST_ALPHA

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


def diffuse_kept(points, f0, roughness, metallic):
    """The share of the diffuse the glossy layer keeps toward the eye at each point."""
    nv = (EYE - points)[..., 2] / np.linalg.norm(EYE - points, axis=-1)
    layer = specular_albedo(np.full(nv.shape + (3,), f0), np.full(nv.shape, metallic), np.full(nv.shape, roughness), nv)
    return 1.0 - layer.max(axis=-1)


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
    points = floor_points(floor_scene().camera)
    expected = irradiance * (ALBEDO * diffuse_kept(points, f0, roughness, metallic) / math.pi
                             + ggx(points, f0, roughness, metallic))
    lit = irradiance > 0.05 * irradiance.max()
    assert np.abs(glossy[..., 0] - expected)[lit].mean() / expected[lit].mean() < 0.03
    peak = np.unravel_index(np.argmax(np.where(lit, expected, 0)), expected.shape)
    assert np.abs(np.subtract(np.unravel_index(np.argmax(glossy[..., 0]), expected.shape), peak)).max() <= 1
    assert glossy[..., 0].max() > 1.5 * diffuse[..., 0].max()  # a highlight, not a tint


def test_no_f0_no_change(pipeline):
    diffuse = pipeline.render(floor_scene()).passes["direct"]
    black = pipeline.render(floor_scene((0.0, 0.0, 0.0, 0.2, 1.0))).passes["direct"]
    np.testing.assert_allclose(black, diffuse, atol=1e-6)


def test_the_glossy_layer_sends_on_the_light_it_takes_from_the_diffuse():
    """A white surface under a grey layer bounces all the light it gets, whatever the
    layer; with no layer (F0 0) the diffuse colour is unchanged; a black dielectric bounces
    only what its layer reflects, a few percent; a rough gold metal about its colour."""
    roughness, dielectric = np.array([0.0, 0.3, 0.5, 1.0]), np.zeros(4)
    f0 = np.full((4, 3), 0.04)
    np.testing.assert_allclose(bounce_colours(np.ones((4, 3)), f0, dielectric, roughness), 1.0, atol=1e-9)
    albedo = np.tile([0.8, 0.5, 0.2], (4, 1))
    np.testing.assert_allclose(bounce_colours(albedo, np.zeros((4, 3)), dielectric, roughness), albedo, atol=1e-9)
    black = bounce_colours(np.zeros((4, 3)), f0, dielectric, roughness)
    assert np.all((black > 0.02) & (black < 0.15))
    gold = np.array([[1.0, 0.78, 0.34]])
    metal = bounce_colours(np.zeros((1, 3)), gold, np.ones(1), np.array([0.5]))
    assert np.all((metal > 0.9 * gold) & (metal <= 1.0))


def test_a_white_metal_reflects_all_light_at_every_roughness_and_angle():
    """Cycles' multiple-scattering GGX keeps the energy the single-scattering lobe of the
    table loses (a rough lobe's light bounced among its microfacets)."""
    roughness, nv = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0.05, 1, 11))
    white = specular_albedo(np.ones(roughness.shape + (3,)), np.ones(roughness.shape), roughness, nv)
    np.testing.assert_allclose(white, 1.0, atol=1e-9)


@pytest.mark.parametrize("f0, roughness, metallic", [(0.04, 0.5, 0.0), (0.08, 0.15, 0.0), (0.5, 0.8, 0.3)])
def test_the_gbuffer_keeps_the_diffuse_the_layer_lets_through_toward_the_eye(pipeline, f0, roughness, metallic):
    """The G-buffer's albedo is the floor's times 1 - E(cos θv), E read from the shaders'
    texture as the host reads its table (gpu/specular_albedo.py): the two agree."""
    scene = floor_scene((f0, f0, f0, roughness, metallic))
    pipeline.render(scene)
    record = pipeline.read_gbuffer(scene)
    seen = record.seen
    expected = ALBEDO * diffuse_kept(record.position[seen], f0, roughness, metallic)
    np.testing.assert_allclose(record.albedo[seen][:, 0], expected, rtol=2e-3)


@pytest.mark.parametrize("f0, roughness, metallic", [(0.04, 0.25, 0.0), (0.9, 0.3, 1.0)])
def test_glossy_vpls_carry_what_the_layer_reflects_along_the_mirror_direction(pipeline, f0, roughness, metallic):
    """The glossy VPLs' flux is what the map's texels reflect off their layer, the diffuse
    VPLs' the rest, each set summing exactly its share of the map's flux (every texel is
    in a cell of both; the glossy ones' 1 + alpha² times it, what their lobes send below the
    surface given back); each glossy VPL's lobe lies along the lamp's ray mirrored by the
    floor, a GGX lobe of the floor's alpha, at least SHARPEST_ALPHA."""
    scene = floor_scene((f0, f0, f0, roughness, metallic))
    (maps,), _ = pipeline.light_maps(scene)
    flux = maps.rsm.read(maps.rsm.flux)
    channels = flux[..., :3].sum(axis=-1)
    share = flux[..., 3] - np.floor(flux[..., 3])
    diffuse, glossy = maps.vpls.read(), maps.glossy_vpls.read()
    alpha = max(roughness ** 2, SHARPEST_ALPHA)
    reflected = glossy["flux"].sum() / (1 + alpha ** 2)
    assert abs(reflected / (channels * share).sum() - 1.0) < 1e-3
    assert abs((diffuse["flux"].sum() + reflected) / channels.sum() - 1.0) < 1e-3
    expected_share = 1.0 if metallic else 0.15
    assert reflected / channels.sum() < expected_share + 1e-3
    carrying = glossy["valid"] & (glossy["flux"].sum(axis=1) > 0)
    rays = glossy["position"][carrying] - LAMP
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    mirrored = rays * np.array([1.0, 1.0, -1.0])
    np.testing.assert_allclose(glossy["normal"][carrying], mirrored, atol=1e-3)
    np.testing.assert_allclose(glossy["lobe"][carrying], alpha, rtol=2 / 255 / roughness)  # the roughness in 255ths
    assert np.all(diffuse["lobe"] == 0.0)
