"""Dual paraboloid maps (METHOD §3): projection, rim clipping, solid angles, flux parity."""
import dataclasses
import math

import numpy as np
import pytest

from lpv_preview.gpu import context, mesh_buffer, paraboloid
from lpv_preview.gpu.mesh_buffer import MeshBuffer
from lpv_preview.gpu.rsm import hemisphere_views, render_rsm
from lpv_preview.gpu.scene import Camera, Light, Scene

from ..glsl import evaluate
from ..synthetic_scenes import room_scene


def test_solid_angles_cover_the_hemisphere():
    resolution = 1024
    centres = (np.arange(resolution) + 0.5) / resolution * 2 - 1
    s, t = np.meshgrid(centres, centres)
    st = np.stack([s, t], -1)
    inside = np.sum(st ** 2, -1) <= 1
    total = paraboloid.texel_solid_angle(st[inside], resolution).sum()
    assert total == pytest.approx(2 * math.pi, rel=1e-3)
    assert inside.mean() == pytest.approx(math.pi / 4, rel=1e-3)


def test_projection_round_trip_in_glsl_matches_float64(glc):
    rng = np.random.default_rng(4)
    count = 4096
    points = rng.normal(size=(count, 3)) * rng.uniform(1e-3, 1e4, size=(count, 1))
    points[:, 2] = np.abs(points[:, 2])  # the front hemisphere
    out = evaluate(glc, "paraboloid.glsl", ["vec4(paraboloid_direction(paraboloid_project(x.xyz)), 0.0)",
                                            "vec4(paraboloid_project(x.xyz), 0.0, 0.0)"], points)
    expected_st = paraboloid.project(points.astype(np.float32).astype(np.float64))
    unit = points / np.linalg.norm(points, axis=1, keepdims=True)
    st_error = np.abs(out[1, :, :2] - expected_st).max()
    round_trip = np.abs(out[0, :, :3] - unit).max()
    print(f"\nGLSL vs float64: (s, t) max error {st_error:.2e}, direction round trip max error {round_trip:.2e}")
    assert st_error < 1e-6 and round_trip < 1e-5
    np.testing.assert_allclose(paraboloid.direction(paraboloid.project(points)), unit, atol=1e-12)


def test_points_straight_behind_stay_finite():
    st = paraboloid.project(np.array([[0.0, 0.0, -1.0], [1e-9, 0.0, -1.0]]))
    assert np.all(np.isfinite(st))


def single_triangle_scene(triangle):
    triangle = np.asarray(triangle, dtype=np.float32).reshape(1, 3, 3)
    light = Light("POINT", (0, 0, 0), (0, 0, -1), (0, 1, 0), (1, 1, 1), 100.0)
    return Scene(triangle, np.zeros_like(triangle), np.full((1, 3), 0.5), [light],
                 Camera.look_at((0, -5, 0), (0, 0, 0))).sanitize()


def test_triangles_straddling_the_rim_are_clipped_there(glc):
    # The light looks down -z; this triangle crosses z = 0 (the rim of both hemispheres).
    scene = single_triangle_scene([[-1.0, 2.0, -1.5], [1.0, 2.0, -1.5], [0.0, 2.0, 1.5]])
    mesh = MeshBuffer(glc, scene)
    rsm = render_rsm(glc, mesh, scene.lights[0], 128, scene.bounds(), method="dpm")
    position = rsm.read(rsm.position)
    views = hemisphere_views(scene.lights[0], scene.lights[0].position)
    resolution = 128
    centres = (np.arange(resolution) + 0.5) / resolution * 2 - 1
    s, t = np.meshgrid(centres, centres)
    radius = np.hypot(s, t)
    for face, view in enumerate(views):
        texels = position[:, face * resolution:(face + 1) * resolution]
        valid = texels[..., 3] > 0
        assert valid.sum() > 50, face  # both hemispheres see part of it
        assert np.all(radius[valid] <= 1.0 + 1.5 / resolution)  # nothing smeared past the rim
        hemisphere = texels[valid, :3] @ view[:3, :3].T + view[:3, 3]
        assert np.all(hemisphere[:, 2] >= -1e-3)  # every texel is on its own side
        assert np.all(np.isfinite(rsm.read(rsm.flux)))
    rsm.release()
    mesh.release()


def test_each_hemisphere_draws_its_own_triangles_and_clips_only_those_crossing_the_rim(glc):
    # Light at the origin looking down -z: the front hemisphere is z < 0, the rear z > 0.
    below = [[-1.0, -1.0, -2.0], [1.0, -1.0, -2.0], [0.0, 1.0, -2.0]]
    above = [[-1.0, -1.0, 2.0], [1.0, -1.0, 2.0], [0.0, 1.0, 2.0]]
    crossing = [[-1.0, 2.0, -1.5], [1.0, 2.0, -1.5], [0.0, 2.0, 1.5]]
    triangles = np.array([below, below, above, crossing], dtype=np.float32)
    light = Light("POINT", (0, 0, 0), (0, 0, -1), (0, 1, 0), (1, 1, 1), 100.0)
    scene = Scene(triangles, np.zeros_like(triangles), np.full((4, 3), 0.5), [light],
                  Camera.look_at((0, -5, 0), (0, 0, 0))).sanitize()
    mesh = MeshBuffer(glc, scene)
    front_view, rear_view = hemisphere_views(light, light.position)
    for hemisphere, (view, expected_front) in enumerate(((front_view, [0, 1]), (rear_view, [2]))):
        for _ in range(2):  # sorting again starts the lists afresh
            lists, commands = mesh.split_at_rim(view, hemisphere)
        command = np.frombuffer(commands.read(), dtype=np.uint32).reshape(2, 5)
        assert command[:, 1].tolist() == [1, 1]  # one instance each
        indices = np.frombuffer(lists.read(), dtype=np.uint32)
        listed = [indices[first:first + count:3] // 3 for count, _, first, _, _ in command]
        front_triangles = sorted(listed[0])
        crossing_triangles = listed[1]
        assert front_triangles == expected_front and crossing_triangles.tolist() == [3]
    mesh.release()


def position_quality(glc, quads_per_side, resolution=256):
    """Position PSNR of DPM, WDPM, TDPM and TWDPM against the reference DPM, and fluxes."""
    from lpv_preview.gpu.metrics import psnr
    from lpv_preview.gpu.warp import reference_paraboloid_map, warp_paraboloid_map
    scene = room_scene(quads_per_side)
    light = scene.lights[0]
    mesh = MeshBuffer(glc, scene)
    cube = render_rsm(glc, mesh, light, resolution, scene.bounds(), method="cm")
    maps = {"dpm": render_rsm(glc, mesh, light, resolution, scene.bounds(), method="dpm"),
            "tdpm": render_rsm(glc, mesh, light, resolution, scene.bounds(), method="dpm", tessellation_unit=0.1)}
    reference = reference_paraboloid_map(glc, cube, maps["dpm"])
    statuses = []
    for name, source, alpha in (("wdpm", "dpm", 0.7), ("twdpm", "tdpm", 0.9)):
        maps[name], status = warp_paraboloid_map(glc, maps[source], alpha, 16, 2)
        statuses.append(status)
    total = lambda rsm: rsm.read(rsm.flux)[..., :3].astype(np.float64).sum(axis=(0, 1))
    valid = reference.read(reference.position)[..., 3] > 0
    truth = reference.read(reference.position)[..., :3]
    quality = {name: psnr(m.read(m.position)[..., :3], truth, mask=valid) for name, m in maps.items()}
    fluxes = {"cube": total(cube), "reference": total(reference)}
    for rsm in (cube, reference, *maps.values()):
        rsm.release()
    for status in statuses:
        status.release()
    mesh.release()
    return quality, fluxes


def test_reference_dpm_keeps_the_cube_flux_and_warping_approaches_it(glc):
    quality, fluxes = position_quality(glc, quads_per_side=8)
    print("\nposition PSNR against the reference DPM, 8x8 quads a side: "
          + ", ".join(f"{k} {v:.2f} dB" for k, v in quality.items()) + f"; flux {fluxes}")
    np.testing.assert_allclose(fluxes["reference"], fluxes["cube"], rtol=0.01)
    assert quality["wdpm"] > quality["dpm"] + 3.0


def test_tessellation_corrects_large_triangles(glc):
    quality, _ = position_quality(glc, quads_per_side=1)
    print("\nposition PSNR against the reference DPM, one quad a side: "
          + ", ".join(f"{k} {v:.2f} dB" for k, v in quality.items()))
    assert quality["tdpm"] > quality["dpm"] + 5.0
    assert quality["twdpm"] > quality["wdpm"] + 5.0


def test_the_compute_pass_rasterises_small_triangles_as_the_rasterizer_does(glc, monkeypatch):
    # RASTER_SPAN 0 leaves every triangle that covers a texel centre to the rasterizer.
    scene = room_scene(40)
    light = dataclasses.replace(scene.lights[0], position=np.array([0.7, -1.1, 1.2]))
    mesh = MeshBuffer(glc, scene)
    maps, listed = {}, {}
    for span in (0, mesh_buffer.RASTER_SPAN):
        monkeypatch.setattr(mesh_buffer, "RASTER_SPAN", span)
        rsm = render_rsm(glc, mesh, light, 512, scene.bounds(), method="dpm")
        maps[span] = [rsm.read(texture) for texture in (rsm.position, rsm.normal, rsm.flux)]
        listed[span] = sum(int(np.frombuffer(mesh.rim_lists[h][1].read(), dtype=np.uint32)[0]) for h in (0, 1))
        rsm.release()
    hardware, compute = maps[0], maps[mesh_buffer.RASTER_SPAN]
    assert listed[mesh_buffer.RASTER_SPAN] < listed[0] / 2  # most in front rasterised, the rest drawn over them
    assert not np.any((hardware[0][..., 3] > 0) & (compute[0][..., 3] <= 0))  # no texel left empty
    for drawn, rasterised in zip(hardware, compute):
        differing = np.abs(drawn - rasterised).max(axis=-1) > 1e-4 * np.abs(drawn).max()
        assert differing.mean() < 1e-4  # equal depths, where the two keep different triangles
    assert compute[2][..., :3].sum() == pytest.approx(hardware[2][..., :3].sum(), rel=1e-5)
    mesh.release()


def test_the_rim_split_reaches_every_triangle_of_a_scene_larger_than_one_dispatch(glc, monkeypatch):
    # GL promises 65,535 workgroups a dispatch: 4,194,240 triangles in rows of 64. Rows
    # of 640 triangles here split the room's 19,200 into 30 dispatches.
    scene = room_scene(40)
    mesh = MeshBuffer(glc, scene)
    whole = render_rsm(glc, mesh, scene.lights[0], 128, scene.bounds(), method="dpm")
    monkeypatch.setattr(context, "ROW_INVOCATIONS", 640)
    rowed = render_rsm(glc, mesh, scene.lights[0], 128, scene.bounds(), method="dpm")
    for texture in ("position", "normal", "flux"):
        np.testing.assert_array_equal(rowed.read(getattr(rowed, texture)), whole.read(getattr(whole, texture)))
    for rsm in (whole, rowed):
        rsm.release()
    mesh.release()
