"""Mathematical properties of the stages, over inputs hypothesis draws: the paraboloid
projection round-trips, the warp converges or says a texel failed (never NaN), the SH
cosine lobe keeps a VPL's flux, the VPLs carry the light map's flux, propagation never
creates light, and a frame is the same every time."""
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st
from hypothesis.extra.numpy import arrays

from lpv_preview.gpu import lpv, paraboloid
from lpv_preview.gpu.grids import Grid
from lpv_preview.gpu.lpv import LightPropagationVolume
from lpv_preview.gpu.pipeline import Pipeline, render_once
from lpv_preview.gpu.scene import Camera, Light, Scene
from lpv_preview.gpu.settings import Settings
from lpv_preview.gpu.vpl import VPLSet
from lpv_preview.gpu.warp import STATUS_NAMES

from ..glsl import evaluate

GPU_EXAMPLES = settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
finite = st.floats(-1.0, 1.0, allow_nan=False, width=32)
directions = arrays(np.float64, 3, elements=finite).filter(lambda v: np.linalg.norm(v) > 1e-3)


@settings(max_examples=300, deadline=None)
@given(directions)
def test_the_paraboloid_projection_and_its_inverse_round_trip(v):
    d = v / np.linalg.norm(v)
    if d[2] < -0.999:  # straight behind: the projection's one singular point, tested on its own
        return
    back = paraboloid.direction(paraboloid.project(d))
    assert np.all(np.isfinite(back))
    if d[2] >= 0:  # the front hemisphere is the map's
        np.testing.assert_allclose(back, d, atol=1e-9)


@GPU_EXAMPLES
@given(arrays(np.float32, (64, 3), elements=finite))
def test_the_glsl_paraboloid_projection_matches_float64(glc, points):
    points = points + np.array([0.0, 0.0, 1e-3], np.float32)  # away from the origin's 0/0
    mapped, = evaluate(glc, "paraboloid.glsl", ["vec4(paraboloid_project(x.xyz), 0.0, 0.0)"], points)
    np.testing.assert_allclose(mapped[:, :2], paraboloid.project(points.astype(np.float64)), rtol=2e-5, atol=2e-5)


def fibonacci_sphere(count):
    i = np.arange(count) + 0.5
    z = 1 - 2 * i / count
    r = np.sqrt(1 - z * z)
    phi = math.pi * (1 + 5 ** 0.5) * i
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


SPHERE = fibonacci_sphere(20000)


@settings(max_examples=60, deadline=None)
@given(directions, st.floats(1e-3, 1e3))
def test_a_vpls_sh_lobe_sends_out_its_flux(normal, flux):
    """The injected intensity (flux/π)·cosLobe(n), evaluated in every direction and
    integrated over the sphere, is the VPL's flux; its first moment points along n."""
    n = normal / np.linalg.norm(normal)
    intensity = flux / math.pi * (lpv.sh_basis(SPHERE) @ lpv.cos_lobe(n))
    solid_angle = 4 * math.pi / len(SPHERE)
    assert intensity.sum() * solid_angle == pytest.approx(flux, rel=1e-3)
    moment = (intensity[:, None] * SPHERE).sum(axis=0) * solid_angle
    assert np.dot(moment, n) == pytest.approx(np.linalg.norm(moment), rel=1e-3)


def soup_scene(triangles, light_position):
    triangles = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
    floor = np.array([[(-3, -3, -1), (3, -3, -1), (3, 3, -1)], [(-3, -3, -1), (3, 3, -1), (-3, 3, -1)]])
    triangles = np.concatenate([floor, triangles])
    light = Light("POINT", light_position, (0, 0, -1), (0, 1, 0), (1, 1, 1), 50.0)
    camera = Camera.look_at((0, -4, 2), (0, 0, 0), near=0.01, far=50)
    return Scene(triangles, np.zeros_like(triangles), np.full((len(triangles), 3), 0.7), [light], camera)


triangle_soups = arrays(np.float64, st.tuples(st.integers(1, 6), st.just(3), st.just(3)),
                        elements=st.floats(-2.0, 2.0, allow_nan=False))


def with_slivers(triangles):
    """Some triangles flattened to slivers (a third corner almost on the first edge)."""
    slivers = triangles.copy()
    slivers[::2, 2] = slivers[::2, 0] + 0.5 * (slivers[::2, 1] - slivers[::2, 0]) + 1e-5
    return slivers


@GPU_EXAMPLES
@given(triangle_soups, arrays(np.float64, 3, elements=st.floats(-0.5, 0.5)))
def test_the_warp_converges_or_says_the_texel_failed_never_nan(glc, triangles, light):
    """Random triangles around the light (many crossing a hemisphere's rim), slivers among
    them: every warped texel ends converged, approximate or failed, and the map is finite."""
    pipeline = Pipeline(Settings(width=16, height=16, rsm_resolution=32, vpls_per_light=64, method="wdpm",
                                 lpv_resolution=8), glc)
    try:
        scene = soup_scene(with_slivers(triangles), light)
        pipeline.render(scene, passes=())
        (maps,), _ = pipeline.light_maps(scene)
        status, _, _ = maps.warp.read()
        assert sum(maps.warp.counts[name] for name in STATUS_NAMES) == status.size
        for texture in (maps.rsm.position, maps.rsm.normal, maps.rsm.flux):
            assert np.all(np.isfinite(maps.rsm.read(texture)))
    finally:
        pipeline.release()


@GPU_EXAMPLES
@given(triangle_soups, arrays(np.float64, 3, elements=st.floats(-0.5, 0.5)), st.sampled_from(["cm", "wdpm"]),
       st.sampled_from([64, 4096]))
def test_the_vpls_carry_the_light_maps_flux(glc, triangles, light, method, vpls):
    """The VPLs' summed flux is the map's, whether each texel is a VPL of its own (4096
    VPLs for a 32² map's 2 048 or 6 144 texels) or Poisson cells gather many."""
    pipeline = Pipeline(Settings(width=16, height=16, rsm_resolution=32, vpls_per_light=vpls, method=method,
                                 lpv_resolution=8), glc)
    try:
        scene = soup_scene(triangles, light)
        pipeline.render(scene, passes=())
        (maps,), _ = pipeline.light_maps(scene)
        texels = maps.rsm.read(maps.rsm.flux)[..., :3].astype(np.float64).sum(axis=(0, 1))
        carried = maps.vpls.read()
        flux = carried["flux"][carried["valid"]].astype(np.float64).sum(axis=0)
    finally:
        pipeline.release()
    np.testing.assert_allclose(flux, texels, rtol=1e-4, atol=1e-9 * texels.max())


@GPU_EXAMPLES
@given(arrays(np.float32, (40, 3), elements=st.floats(0.5, 7.5, width=32)), arrays(np.float32, (40, 3),
       elements=finite).filter(lambda n: np.all(np.linalg.norm(n, axis=1) > 1e-2)), st.booleans())
def test_propagation_never_creates_light(glc, positions, normals, occlusion):
    """Random VPLs in an 8³ grid: the light travelling (the volume's integral) after every
    step is at most what it was before, with the geometry volume's blocking or without."""
    normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    data = np.zeros((len(positions), 3, 4), np.float32)
    data[:, 0, :3], data[:, 0, 3] = positions, 1.0
    data[:, 1, :3], data[:, 1, 3] = normals, 0.01
    data[:, 2, :3] = 1.0
    volume = LightPropagationVolume(glc, Grid((0.0, 0.0, 0.0), 1.0, 8))
    buffer = glc.gl.buffer(data.tobytes())
    try:
        volume.inject([VPLSet(buffer, len(data))], flux_bound=float(len(data)))

        def travelling():
            return sum(float(np.maximum(LightPropagationVolume.read(v)[..., 0], 0).sum()) for v in volume.ping)

        before = travelling()
        for _ in range(4):
            volume.propagate(1, occlusion)
            volume.ping, volume.pong = volume.pong, volume.ping  # one step: its result is in the other grid
            after = travelling()
            assert after <= before * (1 + 1e-5) + 1e-9
            before = after
    finally:
        buffer.release()
        volume.release()


def test_a_frame_is_the_same_every_time(glc):
    from ..synthetic_scenes import room_scene
    settings = Settings(width=32, height=32, rsm_resolution=64, vpls_per_light=256, lpv_resolution=8, method="wdpm")
    first, second = (render_once(room_scene(3), settings, glc).passes for _ in range(2))
    for name in first:
        np.testing.assert_array_equal(first[name], second[name])
