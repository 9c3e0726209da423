"""WDPM backward warping (METHOD §4): damping, restarts, status bookkeeping, no NaN."""
import numpy as np
import pytest

from lpv_preview.gpu.mesh_buffer import MeshBuffer
from lpv_preview.gpu.rsm import render_rsm
from lpv_preview.gpu.scene import Camera, Light, Scene
from lpv_preview.gpu.warp import STATUS_NAMES, warp_paraboloid_map

RESOLUTION = 128


def large_floor(cells=4, size=10.0):
    """A 20 m floor under a light 1 m above it: a few huge projected triangles."""
    edges = np.linspace(-size, size, cells + 1)
    triangles = []
    for i in range(cells):
        for j in range(cells):
            a, b = (edges[i], edges[j], 0), (edges[i + 1], edges[j], 0)
            c, d = (edges[i + 1], edges[j + 1], 0), (edges[i], edges[j + 1], 0)
            triangles += [[a, b, c], [a, c, d]]
    triangles = np.array(triangles, dtype=np.float32)
    light = Light("SPOT", (0.3, 0.2, 1.0), (0, 0, -1), (0, 1, 0), (1, 1, 1), 100.0, spot_size=3.1)
    return Scene(triangles, np.zeros_like(triangles), np.full((len(triangles), 3), 0.5), [light],
                 Camera.look_at((0, -5, 3), (0, 0, 0))).sanitize()


@pytest.fixture(scope="module")
def floor_map(glc):
    scene = large_floor()
    mesh = MeshBuffer(glc, scene)
    rsm = render_rsm(glc, mesh, scene.lights[0], RESOLUTION, scene.bounds(), method="dpm")
    yield rsm
    rsm.release()
    mesh.release()


def warp(glc, rsm, alpha, iterations=16):
    warped, status = warp_paraboloid_map(glc, rsm, alpha, iterations, 2)
    arrays = {name: warped.read(getattr(warped, name)) for name in ("position", "normal", "flux")}
    codes, restarted, used = status.read()
    for texture in (warped.position, warped.normal, warped.flux):
        texture.release()
    status.release()
    return arrays, status.counts, status.iteration_histogram, codes, restarted, used


def failed_share(counts):
    found = counts["converged"] + counts["approximate"] + counts["failed"]
    return counts["failed"] / found


def test_damping_makes_large_triangles_converge(glc, floor_map):
    _, damped, *_ = warp(glc, floor_map, alpha=0.7)
    _, undamped, *_ = warp(glc, floor_map, alpha=1.0)
    print(f"\nalpha 0.7: {damped}\nalpha 1.0: {undamped}")
    assert failed_share(damped) < 0.05   # eq. 5 at work
    assert failed_share(undamped) > 0.2  # without it the root oscillates
    assert damped["converged"] + damped["approximate"] > 1.3 * (undamped["converged"] + undamped["approximate"])


def test_background_texels_restart_and_then_converge(glc, floor_map):
    _, _, _, codes, restarted, _ = warp(glc, floor_map, alpha=0.7)
    assert np.count_nonzero(restarted & (codes == 1)) > 50


def test_status_counts_add_up_and_no_texel_is_nan(glc, floor_map):
    for iterations in (1, 4, 16):
        arrays, counts, histogram, codes, _, used = warp(glc, floor_map, alpha=0.7, iterations=iterations)
        total = RESOLUTION * RESOLUTION * floor_map.face_count
        assert sum(counts.values()) == total and histogram.sum() == total
        for index, name in enumerate(STATUS_NAMES):
            assert np.count_nonzero(codes == index) == counts[name]
        assert used.max() <= iterations
        for name, array in arrays.items():
            assert np.all(np.isfinite(array)), name
        filled = arrays["position"][..., 3] > 0
        assert np.all(np.isin(codes[filled], (1, 2, 3)))  # only accepted or nearly converged
