"""The direct light of emissive surfaces: point emitters sampled on the emissive
triangles (in proportion to their power), whose light every pixel gathers with
visibility through the grid levels' occupancy, as VPL gathering does (gpu/vpl_gather.py).

A triangle of radiance L emits from both sides, as Cycles' emission does: each sample is
two cosine emitters facing either way, each of flux π L A, A the area it stands for.
"""
import numpy as np

from .colour import LUMINANCE_WEIGHTS
from .shade import add_irradiance
from .vpl_gather import VPLGather


def points_on_triangles(corners, weight_of, count, pattern):
    """`count` points on the triangles `corners` ((T, 3, 3) float64), drawn by stratified
    sampling of the weights `weight_of(twice each triangle's area)` and uniformly within
    each triangle, with the random numbers of `pattern` (the emitters' and the receivers'
    sampling): (the triangles picked, the points, every triangle's corner cross product,
    its length)."""
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    doubled_area = np.linalg.norm(cross, axis=1)
    weights = weight_of(doubled_area)
    cumulative = np.cumsum(weights) / weights.sum()
    rng = np.random.default_rng(pattern)
    picked = np.minimum(np.searchsorted(cumulative, (np.arange(count) + rng.random(count)) / count), len(weights) - 1)
    root, v = np.sqrt(rng.random(count)), rng.random(count)
    a, b, c = (corners[picked, k] for k in range(3))
    positions = (1 - root)[:, None] * a + (root * (1 - v))[:, None] * b + (root * v)[:, None] * c
    return picked, positions, cross, doubled_area


def sample_surface_emitters(triangles, emission, count, pattern):
    """(2 count, 3, 4) float32 rows of shaders/emitter.glsl: `count` points on the
    triangles with non-zero `emission`, drawn by stratified sampling of their power (the
    luminance of their radiance times their area) with the random numbers of `pattern`."""
    emissive = np.flatnonzero(np.max(emission, axis=1) > 0)
    radiance = emission[emissive].astype(np.float64)
    luminance = np.maximum(radiance @ LUMINANCE_WEIGHTS, 1e-30)
    picked, positions, cross, doubled_area = points_on_triangles(
        triangles[emissive].astype(np.float64), lambda doubled: luminance * doubled / 2, count, pattern)
    power = luminance * doubled_area / 2
    normals = cross[picked] / doubled_area[picked, None]
    # each sample stands for area A_t / (count p_t), p_t = power_t / total power
    area = (doubled_area[picked] / 2) * (power.sum() / power[picked]) / count
    flux = np.pi * radiance[picked] * area[:, None]
    rows = np.zeros((2, count, 3, 4), dtype=np.float32)
    for side, sign in enumerate((1.0, -1.0)):
        rows[side, :, 0, :3], rows[side, :, 0, 3] = positions, 1.0
        rows[side, :, 1, :3], rows[side, :, 1, 3] = sign * normals, area
        rows[side, :, 2, :3] = flux
    return rows.reshape(2 * count, 3, 4)


class SurfaceEmission:
    """The emitters of a scene's emissive surfaces, and for indirect methods other than
    VPL gathering a pixel gather of its own to add their light to the direct image."""

    def __init__(self, glc):
        self.glc = glc
        self.emitters = None
        self.count = 0
        self._key = None
        self._own = None  # VPLGather over the last levels asked for

    def sample(self, scene, count, pattern):
        """Sample the emitters, once per scene geometry, count and pattern."""
        key = (scene.geometry_key(), count, pattern)
        if key != self._key:
            rows = sample_surface_emitters(scene.triangles, scene.emission, count, pattern)
            if self.emitters is not None:
                self.emitters.release()
            self.emitters, self.count, self._key = self.glc.gl.buffer(rows.tobytes()), len(rows), key

    def own_gather(self, levels):
        """A pixel gather of its own over `levels`, made again when they change."""
        if self._own is not None and self._own.levels != tuple(levels):
            self._own.release()
            self._own = None
        if self._own is None:
            self._own = VPLGather(self.glc, levels)
        return self._own

    def add_light(self, gather, mesh, targets, uniforms, camera_position, singularity_bound, pattern):
        """Gather the emitters' irradiance at every pixel with `gather` (a VPLGather; its
        occupancy voxelised once per mesh) and add albedo / π times it to the direct
        image. `uniforms` are the G-buffer's, its textures bound."""
        gather.occupancy.voxelise(mesh)
        gather.gather(targets, uniforms, camera_position, [(self.emitters, self.count)], singularity_bound, pattern)
        add_irradiance(self.glc, targets, uniforms, gather.filtered)

    def resources(self):
        held = self._own.resources() if self._own is not None else ()
        return (*held, *((self.emitters,) if self.emitters is not None else ()))

    def release(self):
        if self._own is not None:
            self._own.release()
        if self.emitters is not None:
            self.emitters.release()
        self.emitters, self._own, self._key = None, None, None
