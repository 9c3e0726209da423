"""The world as radiance maps: what lights the scene from every direction and what the
camera sees where it sees no surface, equirectangular as Blender's Environment Texture
maps a direction (row 0 looks up, the middle row at the horizon, u = 0.5 looks along +x).

The world lights the scene as distant emitters (`emitter_rows`): directions drawn in
proportion to the lighting map's power, each a cosine emitter far beyond the scene whose
light every pixel gathers with visibility through the grids' occupancy, as emissive
surfaces' light is gathered (docs/method.md, "The world").
"""
import hashlib
import math
from dataclasses import dataclass, field

import numpy as np

from .colour import LUMINANCE_WEIGHTS

DISTANCE_SCALE = 1000.0
"""A world emitter lies this many scene diagonals from the scene's centre: its light
falls off by at most 0.1 % across the scene, as a distant light's does not at all."""
SCENE_SHARE = 1.0 / (2.0 * DISTANCE_SCALE) ** 2
"""The most of a world emitter's flux that reaches the scene: what crosses the disc of its
bounding sphere (half a diagonal across), DISTANCE_SCALE diagonals off (R² / D²)."""


def directions_of(height, width):
    """The unit directions of an equirectangular map's texel centres, (height, width, 3)."""
    v = (np.arange(height) + 0.5) / height  # from the top
    u = (np.arange(width) + 0.5) / width
    theta = v * math.pi  # from +z
    phi = math.pi - 2 * math.pi * u
    sin_theta = np.sin(theta)[:, None]
    return np.stack(np.broadcast_arrays(sin_theta * np.cos(phi)[None, :], sin_theta * np.sin(phi)[None, :],
                                        np.cos(theta)[:, None]), axis=-1)


def map_coordinates(directions):
    """(u, v from the top) of unit `directions` (..., 3) in an equirectangular map."""
    d = np.asarray(directions, dtype=np.float64)
    u = (0.5 - np.arctan2(d[..., 1], d[..., 0]) / (2 * math.pi)) % 1.0
    v = np.arccos(np.clip(d[..., 2], -1.0, 1.0)) / math.pi
    return u, v


@dataclass
class World:
    """The world: `lighting` (height, width, 3) float32, the radiance that lights the
    scene, and `background` (height, width, 3) float32, the radiance the camera sees (they
    differ where a Light Path node tells camera rays apart), both in W/(m² sr) at the
    scene's scale, equirectangular; what of its node tree was `approximated`, named."""

    lighting: np.ndarray
    background: np.ndarray
    approximated: tuple = ()
    _key: str = field(default=None, repr=False, compare=False)
    _power: np.ndarray = field(default=None, repr=False, compare=False)  # texel_power, flat, and its running sum
    _cumulative: np.ndarray = field(default=None, repr=False, compare=False)

    @staticmethod
    def uniform(colour, size=(8, 16)):
        """A world of one radiance everywhere (a plain background colour times its strength)."""
        radiance = np.broadcast_to(np.asarray(colour, dtype=np.float32), (*size, 3)).copy()
        return World(radiance, radiance)

    @property
    def lights_anything(self):
        return bool(np.any(self.lighting > 0))

    def key(self):
        """A content key of both maps."""
        if self._key is None:
            digest = hashlib.sha1()
            for image in (self.lighting, self.background):
                digest.update(str(image.shape).encode())
                digest.update(np.ascontiguousarray(image, dtype=np.float32).tobytes())
            self._key = digest.hexdigest()[:16]
        return self._key

    def texel_power(self):
        """Each lighting texel's luminance times its solid angle, flat: what sampling
        draws directions by."""
        height, width = self.lighting.shape[:2]
        theta = (np.arange(height) + 0.5) / height * math.pi
        solid_angle = (2 * math.pi / width) * (math.pi / height) * np.sin(theta)
        return np.maximum(self.lighting.astype(np.float64) @ LUMINANCE_WEIGHTS, 0.0) * solid_angle[:, None]

    def emitter_rows(self, count, pattern, centre, diagonal):
        """(count, 3, 4) float32 rows of shaders/emitter.glsl: `count` directions drawn in
        proportion to the lighting's power with the random numbers of `pattern`, each a
        cosine emitter facing the scene from DISTANCE_SCALE diagonals beyond `centre`,
        of the flux that gives a surface there L cos θ / (count pdf) of irradiance."""
        if self._cumulative is None:  # the same for every pattern: made once a world
            self._power = self.texel_power().ravel()
            self._cumulative = np.cumsum(self._power)
        power, total = self._power, self._cumulative[-1]
        rows = np.zeros((count, 3, 4), dtype=np.float32)
        if total <= 0 or count == 0:
            return rows[:0]
        height, width = self.lighting.shape[:2]
        rng = np.random.default_rng(pattern)
        cumulative = self._cumulative / total
        texel = np.minimum(np.searchsorted(cumulative, (np.arange(count) + rng.random(count)) / count), power.size - 1)
        row, column = np.divmod(texel, width)
        # a point within the texel, uniform in u and in cos θ (its solid angle)
        u = (column + rng.random(count)) / width
        top, bottom = np.cos(row / height * math.pi), np.cos((row + 1) / height * math.pi)
        z = top + (bottom - top) * rng.random(count)
        phi = math.pi - 2 * math.pi * u
        sin_theta = np.sqrt(np.maximum(1 - z * z, 0.0))
        direction = np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), z], axis=1)
        texel_solid_angle = (2 * math.pi / width) * (top - bottom)
        pdf = power[texel] / total / texel_solid_angle  # per steradian
        radiance = self.lighting.reshape(-1, 3)[texel].astype(np.float64)
        distance = DISTANCE_SCALE * max(diagonal, 1e-6)
        flux = math.pi * distance ** 2 * radiance / (count * pdf[:, None])
        rows[:, 0, :3], rows[:, 0, 3] = np.asarray(centre) + direction * distance, 1.0
        rows[:, 1, :3] = -direction
        rows[:, 2, :3] = flux
        return rows
