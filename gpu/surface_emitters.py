"""The direct light of emissive surfaces: point emitters sampled on the emissive
triangles (in proportion to their power), whose light every pixel gathers with
visibility through the grid levels' occupancy, as VPL gathering does (gpu/vpl_gather.py).

A triangle of radiance L emits from both sides, as Cycles' emission does: each sample is
two cosine emitters facing either way, each of flux π L A, A the area it stands for.
"""
import numpy as np

from .closed_meshes import side_rooms
from .colour import LUMINANCE_WEIGHTS
from .emitter_bounce import flux_bound
from .scene import array_key
from .shade import add_irradiance


class TrianglePoints:
    """Points drawn on fixed triangles (`corners`, (T, 3, 3) float64) by stratified
    sampling of the weights `weight_of(twice each triangle's area)` and uniformly within
    each triangle: the emissive surfaces' sampling (the bounces' points are drawn alike on
    the GPU, shaders/receiver_draw.comp). The cross products and the
    weights' cumulative sum are made once; each pattern draws its own points."""

    def __init__(self, corners, weight_of):
        self.corners = corners
        self.cross = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        self.doubled_area = np.linalg.norm(self.cross, axis=1)
        self.weights = weight_of(self.doubled_area)
        self.cumulative = np.cumsum(self.weights) / self.weights.sum()

    def draw(self, count, pattern):
        """(the triangles picked, the points) of `count` points with the random numbers of
        `pattern`."""
        rng = np.random.default_rng(pattern)
        picked = np.minimum(np.searchsorted(self.cumulative, (np.arange(count) + rng.random(count)) / count),
                            len(self.weights) - 1)
        root, v = np.sqrt(rng.random(count)), rng.random(count)
        a, b, c = (self.corners[picked, k] for k in range(3))
        return picked, (1 - root)[:, None] * a + (root * (1 - v))[:, None] * b + (root * v)[:, None] * c


class EmissiveSurfaces:
    """The triangles with non-zero emission, ready to be sampled in proportion to their
    power (the luminance of their radiance times their area)."""

    def __init__(self, triangles, emission):
        emissive = np.flatnonzero(np.max(emission, axis=1) > 0)
        self.triangles = emissive  # their numbers in the scene
        self.radiance = emission[emissive].astype(np.float64)
        luminance = np.maximum(self.radiance @ LUMINANCE_WEIGHTS, 1e-30)
        self.points = TrianglePoints(triangles[emissive].astype(np.float64), lambda doubled: luminance * doubled / 2)

    def rows(self, count, pattern, sides=None):
        """(2 count, 3, 4) float32 rows of shaders/emitter.glsl: `count` points drawn with
        the random numbers of `pattern`, each two cosine emitters facing either side, each
        in the room that side looks into (`sides`: gpu/closed_meshes.py's array, or None:
        outside every room)."""
        points = self.points
        picked, positions = points.draw(count, pattern)
        rooms = (0, 0) if sides is None else [room[self.triangles[picked]] for room in side_rooms(sides)]
        power = points.weights
        normals = points.cross[picked] / points.doubled_area[picked, None]
        # each sample stands for area A_t / (count p_t), p_t = power_t / total power
        area = (points.doubled_area[picked] / 2) * (power.sum() / power[picked]) / count
        flux = np.pi * self.radiance[picked] * area[:, None]
        rows = np.zeros((2, count, 3, 4), dtype=np.float32)
        for side, sign in enumerate((1.0, -1.0)):  # the front (the winding's side), then the back
            rows[side, :, 0, :3], rows[side, :, 0, 3] = positions, 1.0 + rooms[side]
            rows[side, :, 1, :3], rows[side, :, 1, 3] = sign * normals, area
            rows[side, :, 2, :3] = flux
        return rows.reshape(2 * count, 3, 4)


def sample_surface_emitters(triangles, emission, count, pattern):
    """EmissiveSurfaces(triangles, emission).rows(count, pattern)."""
    return EmissiveSurfaces(triangles, emission).rows(count, pattern)


class SurfaceEmission:
    """The emitters of a scene's emissive surfaces, sampled once per geometry, and what
    adds their light, and the world's, to the direct image through a pixel gather."""

    def __init__(self, glc):
        self.glc = glc
        self.emitters = None
        self.count = 0
        self.flux_bound = 0.0  # the largest channel of the emitters' summed flux
        self._key = None
        self._surfaces = None  # (geometry key, EmissiveSurfaces)

    def sample(self, scene, count, pattern, sides=None):
        """Sample the emitters, once per scene geometry, count, pattern and `sides` (the
        rooms their sides look into: EmissiveSurfaces.rows)."""
        key = (scene.geometry_key(), count, pattern, None if sides is None else array_key(sides))
        if key != self._key:
            if self._surfaces is None or self._surfaces[0] != key[0]:
                self._surfaces = (key[0], EmissiveSurfaces(scene.triangles, scene.emission))
            rows = self._surfaces[1].rows(count, pattern, sides)
            if self.emitters is not None:
                self.emitters.release()
            self.emitters, self.count, self._key = self.glc.gl.buffer(rows.tobytes()), len(rows), key
            self.flux_bound = flux_bound(rows)

    def add_light(self, gather, mesh, targets, uniforms, camera_position, singularity_bound, pattern, others=(),
                  room_sides=None):
        """Gather the irradiance of the emitters (and of the emitter sets `others`: the
        world's) at every pixel with `gather` (a VPLGather; its occupancy voxelised once
        per mesh), with `room_sides` (the mesh's sides-and-rooms buffer) only those that
        light the pixel's room, and add albedo / π times it to the direct image.
        `uniforms` are the G-buffer's, its textures bound."""
        sets = ([(self.emitters, self.count)] if self.emitters is not None else []) + list(others)
        gather.occupancy.voxelise(mesh)
        gather.gather(targets, uniforms, camera_position, sets, singularity_bound, pattern, room_sides=room_sides)
        add_irradiance(self.glc, targets, uniforms, gather.filtered)

    def resources(self):
        return (self.emitters,) if self.emitters is not None else ()

    def release(self):
        if self.emitters is not None:
            self.emitters.release()
        self.emitters, self._key, self._surfaces = None, None, None
