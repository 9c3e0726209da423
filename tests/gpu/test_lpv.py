"""LPV injection and propagation on the GPU: energy, ping-pong, atomic accumulation."""
import math

import numpy as np
import pytest

from lpv_preview.gpu import grids, lpv
from lpv_preview.gpu.grids import Grid, fit_grid
from lpv_preview.gpu.lpv import LightPropagationVolume
from lpv_preview.gpu.vpl import VPLSet


def isotropic_volume(size, centre, intensity):
    data = np.zeros((size, size, size, 4), dtype=np.float32)
    data[centre[2], centre[1], centre[0], 0] = intensity / lpv.SH_C0
    return data


@pytest.fixture
def volume(glc):
    v = LightPropagationVolume(glc, Grid((0.0, 0.0, 0.0), 1.0, 5))
    yield v
    v.release()


def test_isotropic_cell_sends_out_four_pi_times_its_intensity(glc, volume):
    intensity = 2.5
    source = isotropic_volume(5, (2, 2, 2), intensity)
    for channel in volume.ping:
        channel.write(source.tobytes())
    for channel in volume.sums:
        channel.write(np.zeros_like(source).tobytes())
    volume.geometry.write(np.zeros((6, 6, 6, 4), dtype=np.float32).tobytes())
    volume.propagate(1, occlusion=False)
    target = LightPropagationVolume.read(volume.pong[0]).astype(np.float64)
    sent = target[..., 0].sum() * math.pi / lpv.LOBE_C0
    print(f"sent {sent:.6f} W, expected 4*pi*I = {4 * math.pi * intensity:.6f} W")
    assert sent == pytest.approx(4 * math.pi * intensity, rel=1e-5)
    receivers = np.argwhere(np.abs(target).sum(axis=-1) > 0)
    assert sorted(map(tuple, receivers)) == sorted([(2, 2, 1), (2, 2, 3), (2, 1, 2), (2, 3, 2), (1, 2, 2), (3, 2, 2)])
    # Ping-pong: the source grid is untouched and the source cell received nothing back.
    np.testing.assert_array_equal(LightPropagationVolume.read(volume.ping[0]), source)
    assert np.all(target[2, 2, 2] == 0)
    # The accumulation grid received exactly this step.
    np.testing.assert_allclose(LightPropagationVolume.read(volume.sums[1]), target, rtol=1e-6, atol=1e-9)


def test_propagation_through_an_empty_grid_moves_light_one_cell_a_step(glc, volume):
    for channel in volume.ping:
        channel.write(isotropic_volume(5, (2, 2, 2), 1.0).tobytes())
    for channel in volume.sums:
        channel.write(np.zeros((5, 5, 5, 4), dtype=np.float32).tobytes())
    volume.geometry.write(np.zeros((6, 6, 6, 4), dtype=np.float32).tobytes())
    volume.propagate(2, occlusion=False)
    second = LightPropagationVolume.read(volume.ping[0])  # two swaps: step two landed in ping
    assert second[2, 2, 2, 0] > 0  # light came back to the centre after two steps
    assert np.all(second[2, 2, 1] == 0)  # parity: no light an odd number of cells away


def test_many_vpls_in_one_cell_all_add_up(glc, volume):
    count = 1000
    vpls = np.zeros((count, 3, 4), dtype=np.float32)
    vpls[:, 0] = (2.5, 2.5, 1.5, 1.0)      # position, valid
    vpls[:, 1] = (0.0, 0.0, 1.0, 0.0)      # normal +z (shifted a cell: the centre of cell 2,2,2)
    vpls[:, 2] = (1.0, 0.5, 0.25, 0.0)     # flux
    buffer = glc.gl.buffer(vpls.tobytes())
    volume.inject([VPLSet(buffer, count)], flux_bound=count * 1.0)
    expected = count * np.array([1.0, 0.5, 0.25])[:, None] / math.pi * lpv.cos_lobe(np.array([0.0, 0.0, 1.0]))
    for channel in range(3):
        got = LightPropagationVolume.read(volume.ping[channel])[2, 2, 2].astype(np.float64)
        np.testing.assert_allclose(got, expected[channel], rtol=1e-5)
    buffer.release()


def test_a_vpl_between_cell_centres_is_shared_by_trilinear_weights(glc, volume):
    vpls = np.zeros((1, 3, 4), dtype=np.float32)
    vpls[0, 0] = (3.25, 3.0, 2.0, 1.0)   # with the one-cell shift along +z: (3.25, 3.0, 3.0)
    vpls[0, 1] = (0.0, 0.0, 1.0, 0.0)
    vpls[0, 2] = (1.0, 1.0, 1.0, 0.0)
    buffer = glc.gl.buffer(vpls.tobytes())
    volume.inject([VPLSet(buffer, 1)], flux_bound=1.0)
    buffer.release()
    red = LightPropagationVolume.read(volume.ping[0]).astype(np.float64)[..., 0]  # (z, y, x)
    lobe = 1.0 / math.pi * lpv.LOBE_C0
    weights = red / lobe
    assert weights.sum() == pytest.approx(1.0, abs=1e-5)  # nothing lost
    # x: 3.25 lies 3/4 of the way from centre 2.5 to 3.5; y and z sit halfway between centres.
    np.testing.assert_allclose(weights[2:4, 2:4, 2], 0.25 * 0.25, atol=1e-5)
    np.testing.assert_allclose(weights[2:4, 2:4, 3], 0.75 * 0.25, atol=1e-5)


def test_fitted_grid_encloses_the_bounds_snaps_and_moves_with_the_scene():
    centre = np.array([0.03125, -0.01953125, 1.0078125])  # on the anchor lattice (multiples of 2^-8)
    bounds = (centre - 1.0, centre + 1.0)
    grid = fit_grid(bounds, 32)
    low = np.array(grid.origin)
    high = low + grid.cell_size * grid.size
    assert np.all(low <= bounds[0] - grid.cell_size) and np.all(high >= bounds[1] + grid.cell_size)
    step = 2.0 ** math.floor(math.log2(grid.cell_size / grids.GRID_ANCHOR_STEPS))
    assert step == 2.0 ** -8
    nudged = fit_grid((bounds[0] - 0.4 * step, bounds[1] - 0.2 * step), 32)
    assert nudged == grid  # a change of bounds below the anchor step does not move the grid
    offset = np.array([123.456, -7.89, 0.5])  # the scene moved: the grid moves with it, to half a step
    moved = fit_grid((bounds[0] + offset, bounds[1] + offset), 32)
    assert moved.cell_size == grid.cell_size
    assert np.all(np.abs(np.array(moved.origin) - low - offset) <= step / 2 + 1e-9)
    shifted = fit_grid(bounds, 32, shift=0.25)
    np.testing.assert_allclose(np.array(shifted.origin) - low, 0.25 * grid.cell_size)
