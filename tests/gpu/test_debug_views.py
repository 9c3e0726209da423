"""The debug passes and overlay data (gpu/debug_views.py) on real GL: VPL splats carry the
flux of the VPLs the camera sees, the warp status pass and map agree with the warp's own
counts, and the LPV slice is the volume's layer."""
import math

import numpy as np
import pytest

from lpv_preview.gpu.debug_views import STATUS_COLOURS, lpv_slice, vpl_points, warp_status_image
from lpv_preview.gpu.lpv import LightPropagationVolume
from lpv_preview.gpu.pipeline import Pipeline
from lpv_preview.gpu.settings import DisplaySettings, Settings

from ..synthetic_scenes import room_scene

SIZE = 96
DEBUG = ("combined", "direct", "indirect", "vpl_splats", "warp_status")


@pytest.fixture(scope="module")
def room():
    return room_scene(4)


@pytest.fixture(scope="module", params=["cm", "wdpm"])
def rendered(request, glc, room):
    pipeline = Pipeline(Settings(method=request.param, width=SIZE, height=SIZE, rsm_resolution=128,
                                 vpls_per_light=2048, lpv_resolution=16, indirect_method="lpv"), glc)
    frame = pipeline.render(room, passes=DEBUG, display_settings=DisplaySettings(vpl_point_size=1.0))
    yield request.param, pipeline, frame
    pipeline.release()


def projected_pixels(camera, positions):
    """Top-row-first (row, column) of world points, and whether they fall in the image."""
    clip = np.c_[positions, np.ones(len(positions))] @ (camera.projection @ camera.view).T
    ndc = clip[:, :3] / clip[:, 3:]
    inside = (clip[:, 3] > 0) & np.all(np.abs(ndc) < 1.0, axis=1)
    rows = ((1 - (ndc[:, 1] * 0.5 + 0.5)) * SIZE).astype(int)
    columns = ((ndc[:, 0] * 0.5 + 0.5) * SIZE).astype(int)
    return rows, columns, inside


def test_vpl_splats_carry_the_flux_of_the_vpls_the_camera_sees(rendered, room):
    _, pipeline, frame = rendered
    splats = frame.passes["vpl_splats"]
    points = vpl_points(pipeline.last_light_maps)
    rows, columns, inside = projected_pixels(room.camera, points.positions.astype(np.float64))
    # Inside a closed convex room nothing hides a VPL: a one-pixel splat for each one in view.
    expected = points.flux[inside].sum(axis=0)
    assert inside.sum() > 50
    np.testing.assert_allclose(splats.sum(axis=(0, 1)), expected, rtol=0.02)
    lit = np.argwhere(splats.sum(axis=-1) > 0)
    assert len(lit) <= inside.sum()
    near = np.abs(lit[:, None, :] - np.stack([rows[inside], columns[inside]], -1)[None]).max(-1).min(-1)
    assert near.max() <= 1  # every splat sits on a VPL's projection


def test_a_larger_splat_covers_more_pixels_with_the_same_flux_each(glc, room):
    pipeline = Pipeline(Settings(width=SIZE, height=SIZE, rsm_resolution=64, vpls_per_light=64, lpv_resolution=8),
                        glc)
    try:
        small, large = (pipeline.render(room, passes=("vpl_splats",), display_settings=DisplaySettings(
            vpl_point_size=size)).passes["vpl_splats"] for size in (1.0, 5.0))
    finally:
        pipeline.release()
    covered = [(image.sum(axis=-1) > 0).sum() for image in (small, large)]
    assert covered[1] > 10 * covered[0]
    # A pixel holds one VPL's flux or the sum of overlapping ones: never less than the dimmest.
    assert large[large.sum(-1) > 0].sum(-1).min() >= small[small.sum(-1) > 0].sum(-1).min() * (1 - 1e-5)


def test_the_warp_status_pass_shows_each_pixels_map_texel_status(rendered):
    method, pipeline, frame = rendered
    status = frame.passes["warp_status"]
    codes = np.array([np.flatnonzero(np.all(np.isclose(STATUS_COLOURS, colour), axis=1))[0]
                      for colour in status.reshape(-1, 3)]).reshape(SIZE, SIZE)
    if method == "cm":
        assert not codes.any()  # no warped map: nothing to show
        return
    # A point light in a closed room: both hemispheres see every surface the camera sees.
    assert codes.min() >= 1
    shares = np.bincount(codes.ravel(), minlength=5) / codes.size
    assert shares[1] > 0.5, shares
    print(f"\nwarp status pass, room: converged {shares[1]:.1%}, approximate {shares[2]:.1%}, "
          f"failed {shares[3]:.1%}, missed {shares[4]:.1%}")


def test_the_warp_status_map_has_the_warps_own_counts(rendered):
    method, pipeline, _ = rendered
    warp = pipeline.last_light_maps[0].warp
    if method == "cm":
        assert warp is None
        return
    image = warp_status_image(warp)
    for code, name in enumerate(("converged", "approximate", "failed"), start=1):
        matches = np.all(image[..., :3] == STATUS_COLOURS[code], axis=-1) & (image[..., 3] > 0)
        assert matches.sum() == warp.counts[name], name
    assert (image[..., 3] == 0).sum() == warp.counts["background"]


def test_vpl_points_hold_every_valid_vpl_with_colours_by_flux(rendered):
    _, pipeline, _ = rendered
    vpls = pipeline.last_light_maps[0].vpls.read()
    points = vpl_points(pipeline.last_light_maps)
    assert len(points.positions) == vpls["valid"].sum()
    np.testing.assert_allclose(points.flux.sum(axis=0), vpls["flux"][vpls["valid"]].sum(axis=0), rtol=1e-6)
    assert points.colours.min() >= 0 and points.colours[:, :3].max() == pytest.approx(1.0)


@pytest.mark.parametrize("axis, position, layer", [("z", 0.5, 8), ("x", 0.0, 0), ("y", 1.0, 15)])
def test_the_lpv_slice_is_the_volumes_layer_at_its_place(rendered, axis, position, layer):
    _, pipeline, _ = rendered
    indirect = pipeline.last_indirect
    lpv = indirect.volumes[0]
    grid = lpv.grid
    a = "xyz".index(axis)
    piece = lpv_slice(indirect, axis, position)
    volume = np.stack([LightPropagationVolume.read(v)[..., 0] for v in lpv.sums], -1).transpose(2, 1, 0, 3)
    expected = np.maximum(np.take(volume, layer, axis=a), 0) * 2 * math.sqrt(math.pi)
    np.testing.assert_allclose(piece.light, expected.transpose(1, 0, 2), rtol=1e-6, atol=1e-12)
    assert piece.light.sum() > 0 or layer in (0, 15)
    np.testing.assert_allclose(piece.corners[:, a], grid.origin[a] + (layer + 0.5) * grid.cell_size, rtol=1e-6)
    extent = piece.corners.max(axis=0) - piece.corners.min(axis=0)
    np.testing.assert_allclose(np.delete(extent, a), grid.cell_size * grid.size, rtol=1e-6)
    assert np.all((piece.image[..., 3] > 0) == (piece.light.max(axis=-1) > 0))


def room_hits(camera, size, half=(2.0, 2.0), height=3.0):
    """World point and inward normal where each pixel centre's ray leaves the 4 x 4 x 3 m
    room of `room_scene` (top row first), by intersecting its six planes."""
    inverse = np.linalg.inv(camera.projection @ camera.view)
    rows, columns = np.mgrid[0:size, 0:size]
    ndc = np.stack([(columns + 0.5) / size * 2 - 1, 1 - (rows + 0.5) / size * 2], -1)
    near = np.c_[ndc.reshape(-1, 2), -np.ones(size * size), np.ones(size * size)] @ inverse.T
    far = np.c_[ndc.reshape(-1, 2), np.ones(size * size), np.ones(size * size)] @ inverse.T
    origin = near[:, :3] / near[:, 3:]
    direction = far[:, :3] / far[:, 3:] - origin
    best = np.full(len(origin), np.inf)
    normals = np.zeros_like(origin)
    for axis, low, high in ((0, -half[0], half[0]), (1, -half[1], half[1]), (2, 0.0, height)):
        for plane, inward in ((low, 1.0), (high, -1.0)):
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (plane - origin[:, axis]) / direction[:, axis]
            take = (t > 0) & (t < best)
            best[take] = t[take]
            normals[take] = 0.0
            normals[take, axis] = inward
    return (origin + best[:, None] * direction).reshape(size, size, 3), normals.reshape(size, size, 3)


def test_the_exact_transfer_matches_the_sum_over_vpls_done_in_numpy(glc, room):
    from lpv_preview.bench.exact_stages import gathered_indirect
    size = 24
    pipeline = Pipeline(Settings(width=size, height=size, rsm_resolution=32, vpls_per_light=128, lpv_resolution=8),
                        glc)
    try:
        pipeline.render(room, passes=())
        gathered = gathered_indirect(pipeline, room.camera)
        vpls = pipeline.last_light_maps[0].vpls.read()
    finally:
        pipeline.release()
    points, normals = room_hits(room.camera, size)
    v = vpls["valid"]
    d = points[:, :, None, :] - vpls["position"][v][None, None].astype(np.float64)
    dist2 = np.sum(d * d, axis=-1)
    w = d / np.sqrt(dist2)[..., None]
    cosines = (np.maximum(np.einsum("vk,ijvk->ijv", vpls["normal"][v], w), 0)
               * np.maximum(-np.einsum("ijk,ijvk->ijv", normals, w), 0))
    falloff = cosines / np.maximum(dist2, vpls["area"][v][None, None] / math.pi)
    expected = 0.6 / math.pi * np.einsum("ijv,vc->ijc", falloff, vpls["flux"][v]) / math.pi
    assert expected.mean() > 0
    np.testing.assert_allclose(gathered, expected, rtol=2e-3, atol=1e-6 * expected.max())


def test_the_light_grid_slice_shows_each_cells_mean_irradiance(glc, room):
    pipeline = Pipeline(Settings(width=SIZE, height=SIZE, rsm_resolution=64, vpls_per_light=256, lpv_resolution=8,
                                 indirect_method="light_grid"), glc)
    try:
        pipeline.render(room, passes=("indirect",))
        indirect = pipeline.last_indirect
        piece = lpv_slice(indirect, "z", 0.5)
        irradiance = indirect.volumes[0].read_irradiance(0).mean(axis=0)  # (z, y, x, rgb)
        np.testing.assert_allclose(piece.light, np.maximum(irradiance[4], 0), rtol=1e-6)
        assert piece.light.max() > 0
    finally:
        pipeline.release()
