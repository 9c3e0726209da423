"""The direct light of emissive surfaces: point emitters sampled on the emissive
triangles (in proportion to their power), whose light every pixel gathers with
visibility through the grid levels' occupancy, as VPL gathering does (gpu/vpl_gather.py).

A triangle of radiance L emits from both sides, as Cycles' emission does: each sample is
two cosine emitters facing either way, each of flux π L A, A the area it stands for.
"""
import numpy as np

from .colour import LUMINANCE_WEIGHTS
from .context import dispatch, set_uniforms
from .shade import bind_gbuffer
from .vpl_gather import VPLGather


def sample_surface_emitters(triangles, emission, count, pattern):
    """(2 count, 3, 4) float32 rows of shaders/emitter.glsl: `count` points on the
    triangles with non-zero `emission`, drawn by stratified sampling of their power (the
    luminance of their radiance times their area) with the random numbers of `pattern`."""
    emissive = np.flatnonzero(np.max(emission, axis=1) > 0)
    corners = triangles[emissive].astype(np.float64)
    cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    doubled_area = np.linalg.norm(cross, axis=1)
    radiance = emission[emissive].astype(np.float64)
    power = np.maximum(radiance @ LUMINANCE_WEIGHTS, 1e-30) * doubled_area / 2
    cumulative = np.cumsum(power) / power.sum()
    rng = np.random.default_rng(pattern)
    picked = np.minimum(np.searchsorted(cumulative, (np.arange(count) + rng.random(count)) / count), len(power) - 1)
    u, v = rng.random(count), rng.random(count)
    root = np.sqrt(u)
    a, b, c = (corners[picked, k] for k in range(3))
    positions = (1 - root)[:, None] * a + (root * (1 - v))[:, None] * b + (root * v)[:, None] * c
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
    """The emitters of a scene's emissive surfaces and the gather that adds their light
    to the direct image."""

    def __init__(self, glc, levels):
        self.glc = glc
        self.levels = tuple(levels)
        self.gather = VPLGather(glc, self.levels)
        self.emitters = None
        self._key = None

    def build(self, mesh, scene, count, pattern):
        """Voxelise the mesh (once per mesh) and sample the emitters (once per scene
        geometry, count and pattern)."""
        self.gather.occupancy.voxelise(mesh)
        key = (scene.geometry_key(), count, pattern)
        if key != self._key:
            rows = sample_surface_emitters(scene.triangles, scene.emission, count, pattern)
            if self.emitters is not None:
                self.emitters.release()
            self.emitters = self.glc.gl.buffer(rows.tobytes())
            self._key = key
            self.gather.emitter_sets = [(self.emitters, len(rows))]

    def add_light(self, targets, uniforms, camera_position, singularity_bound, pattern):
        """Gather the emitters' irradiance at every pixel and add albedo / π times it to
        the direct image. `uniforms` are the G-buffer's, its textures bound."""
        self.gather.gather(targets, uniforms, camera_position, singularity_bound, pattern)
        program = self.glc.compute("add_irradiance")
        bind_gbuffer(targets)
        self.gather.filtered.use(location=2)
        targets.direct.bind_to_image(0, read=True, write=True)
        set_uniforms(program, **uniforms, gathered=2)
        dispatch(program, *targets.size)

    def resources(self):
        return (*self.gather.resources(), *((self.emitters,) if self.emitters is not None else ()))

    def release(self):
        self.gather.release()
        if self.emitters is not None:
            self.emitters.release()
        self.emitters = None

