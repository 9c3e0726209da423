"""LPV injection and propagation on the GPU: energy, ping-pong, atomic accumulation."""
import math

import numpy as np
import pytest

from lpv_preview.gpu import lpv
from lpv_preview.gpu.lpv import Grid, LightPropagationVolume, fit_grid
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
    vpls[:, 0] = (2.2, 2.3, 2.1, 1.0)      # position, valid
    vpls[:, 1] = (0.0, 0.0, 1.0, 0.0)      # normal +z (shifted half a cell: stays in cell 2,2,2)
    vpls[:, 2] = (1.0, 0.5, 0.25, 0.0)     # flux
    buffer = glc.gl.buffer(vpls.tobytes())
    volume.inject([VPLSet(buffer, count)], flux_bound=count * 1.0)
    expected = count * np.array([1.0, 0.5, 0.25])[:, None] / math.pi * lpv.cos_lobe(np.array([0.0, 0.0, 1.0]))
    for channel in range(3):
        got = LightPropagationVolume.read(volume.ping[channel])[2, 2, 2].astype(np.float64)
        np.testing.assert_allclose(got, expected[channel], rtol=1e-5)
    buffer.release()


def test_fitted_grid_encloses_the_bounds_and_snaps():
    bounds = (np.array([-0.97, -1.02, 0.01]), np.array([1.03, 0.98, 2.01]))
    grid = fit_grid(bounds, 32)
    low = np.array(grid.origin)
    high = low + grid.cell_size * grid.size
    assert np.all(low <= bounds[0] - grid.cell_size) and np.all(high >= bounds[1] + grid.cell_size)
    nudged = fit_grid((bounds[0] - 0.004, bounds[1] - 0.002), 32)
    assert nudged == grid  # a small change of bounds does not move the grid
